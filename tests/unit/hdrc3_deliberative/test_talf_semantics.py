"""TALF -> L(FL_FP): the chapter's examples (section 9.4) against theories derived by hand.

Each expected theory below was written out from the translation rules in the module docstring
of :mod:`hdrc3_deliberative.talf_semantics` (``t'`` is written ``tp``; ``monitor-radiation``,
``hover-at``, ``collect-video`` and ``scan-cell`` are the chapter's, which the semantics does
not need to find in the registry).
"""

from __future__ import annotations

import pytest

from hdrc3_deliberative.talf_formulas import formula_text
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_deliberative.talf_semantics import definition, narrative, translate
from hdrc3_deliberative.talf_syntax import TalfFile

CHAPTER = """
[t, tp] monitor-single(av, xav, yav, xtarg, ytarg) ~>
  [t, tp] with t1, t2, t3, t4, t5, t6 do (
    [t1, t2] hover-at(av, xav, yav) ||
    [t3, t4] monitor-radiation(av, xtarg, ytarg) ||
    [t5, t6] collect-video(av, xtarg, ytarg)
  ) where [t] surveil-equipped(av) and radiation-hardened(av)
      and t1 = t3 = t5 = t and t2 = t4 = t6 = tp

[t, tp] scan-with-all-uavs() ~>
  [t, tp] foreach av where [t] can-scan(av) do conc
    [t, tp] with u, up do [u, up] scan-for-people(av) where true

[t, tp] scan-for-people(av) ~>
  [t, tp] with tc, u, up do while [tc] exists x, y (owns(av, x, y) and not scanned(x, y)) do
    [u, up] with x2, y2 do [u, up] scan-cell(av, x2, y2)
    where [tc] owns(av, x2, y2) and not scanned(x2, y2)

mission video:
  [t1, t2] with av, t3, t4, t5, t6 do (
    [t3, t4] fly-to(av, x, y) ;
    [t5, t6] collect-video(av, x, y)
  ) where [t1] has-camera(av)
"""

EXPECTED_DEFINITIONS = {
    "monitor-single": (
        "forall t, tp, av, xav, yav, xtarg, ytarg (Occurs(t, tp, monitor-single(av, xav, yav, "
        "xtarg, ytarg)) <-> exists t1, t2, t3, t4, t5, t6 (t <= tp"
        " and t <= t1 and t2 <= tp and t1 <= t2 and Occurs(t1, t2, hover-at(av, xav, yav))"
        " and t <= t3 and t4 <= tp and t3 <= t4 and Occurs(t3, t4, monitor-radiation(av, xtarg,"
        " ytarg))"
        " and t <= t5 and t6 <= tp and t5 <= t6 and Occurs(t5, t6, collect-video(av, xtarg,"
        " ytarg))"
        " and ([t] surveil-equipped(av)) and ([t] radiation-hardened(av))"
        " and t1 = t3 and t3 = t5 and t5 = t and t2 = t4 and t4 = t6 and t6 = tp))"
    ),
    "scan-with-all-uavs": (
        "forall t, tp (Occurs(t, tp, scan-with-all-uavs()) <-> (t <= tp"
        " and forall av (([t] can-scan(av)) -> exists u, up (t <= tp and t <= u and up <= tp"
        " and Occurs(u, up, scan-for-people(av))))))"
    ),
    "scan-for-people": (
        "forall t, tp, av (Occurs(t, tp, scan-for-people(av)) <-> exists tc, u, up (t <= tp and"
        " (lfp W1(tc, e1)."
        " (not exists x, y (([tc] owns(av, x, y)) and not ([tc] scanned(x, y))) and tc <= e1)"
        " or (exists x, y (([tc] owns(av, x, y)) and not ([tc] scanned(x, y)))"
        " and exists u, up (tc <= u and exists x2, y2 (u <= up"
        " and Occurs(u, up, scan-cell(av, x2, y2))"
        " and ([tc] owns(av, x2, y2)) and not ([tc] scanned(x2, y2))) and W1(up, e1))))(t, tp)))"
    ),
}


def _chapter() -> TalfFile:
    parsed = parse_text(CHAPTER, "chapter.talf")
    assert parsed.tree is not None, parsed.diagnostics
    return parsed.tree


@pytest.mark.parametrize("name", sorted(EXPECTED_DEFINITIONS))
def test_composite_action_types_translate_to_their_definitions(name: str) -> None:
    tree = _chapter()
    got = formula_text(definition(tree.specs()[name], tree), hoist=False)
    assert got == EXPECTED_DEFINITIONS[name]


def test_the_sequence_example_orders_its_actions_within_the_interval() -> None:
    tree = _chapter()
    got = formula_text(translate(tree.missions()[0].body, tree), hoist=False)
    assert got == (
        "exists av, t3, t4, t5, t6 (t1 <= t2 and t1 <= t3 and t4 <= t5 and t6 <= t2"
        " and t3 <= t4 and Occurs(t3, t4, fly-to(av, x, y))"
        " and t5 <= t6 and Occurs(t5, t6, collect-video(av, x, y)) and ([t1] has-camera(av)))"
    )


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            # an elementary action's agent is the nearest `by`, as its first argument
            "mission m: [t, t2] by P ([t, t2] fly-to(6, D))",
            "t <= t2 and Occurs(t, t2, fly-to(P, 6, D))",
        ),
        (
            "mission m: [t, t2] with c do if [c] airborne(P) then [t, t2] land() else"
            " [t, t2] wait(1) where true",
            "exists c (t <= t2 and t <= c and c <= t2 and (([c] airborne(P)) ->"
            " (t <= t2 and Occurs(t, t2, land()))) and (not ([c] airborne(P)) ->"
            " (t <= t2 and Occurs(t, t2, wait(1)))))",
        ),
        (
            # named constraint sets are replaced by their formulas
            "constraint c = t2 - t <= 9\nmission m: [t, t2] land() where c and P = uav0",
            "t <= t2 and Occurs(t, t2, land()) and t2 - t <= 9 and P = uav0",
        ),
    ],
)
def test_other_constructs(text: str, expected: str) -> None:
    parsed = parse_text(text)
    assert parsed.tree is not None, parsed.diagnostics
    got = formula_text(translate(parsed.tree.missions()[0].body, parsed.tree), hoist=False)
    assert got == expected


def test_a_narrative_holds_the_definitions_the_mission_uses_then_the_mission() -> None:
    tree = _chapter()
    parsed = parse_text("mission all: [a, b] scan-with-all-uavs()")
    assert parsed.tree is not None
    both = TalfFile((*tree.items, *parsed.tree.missions()))
    story = narrative(both, both.missions()[1])
    assert [s.what for s in story.statements] == [
        "definition scan-with-all-uavs",
        "definition scan-for-people",
        "mission all",
    ]
    assert story.text().endswith("mission all:\n  a <= b and Occurs(a, b, scan-with-all-uavs())")
