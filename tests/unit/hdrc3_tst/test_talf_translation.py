"""TALF <-> TST: round trips over the examples and the library, and what has no counterpart."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_deliberative.talf_check import check
from hdrc3_deliberative.talf_expand import expand
from hdrc3_deliberative.talf_library import with_library
from hdrc3_deliberative.talf_parser import parse_file as parse_talf_file
from hdrc3_deliberative.talf_parser import parse_text as parse_talf
from hdrc3_deliberative.talf_printer import file_text as talf_text
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.parser import parse_file, parse_text
from hdrc3_tst.printer import file_text
from hdrc3_tst.talf_translation import TranslationError, from_tst, to_tst

ROOT = Path(__file__).resolve().parents[3]
TST_EXAMPLES = sorted((ROOT / "examples" / "tst").glob("*.tst"))
NOT_COVERED = {
    "delivery_box_drop.tst": "goal node d",
    "delivery_carrier_overweight.tst": "goal node first",
    "patrol.tst": "call node go",
}


@pytest.mark.parametrize("path", TST_EXAMPLES, ids=lambda p: p.name)
def test_tst_to_talf_to_tst_is_the_identity(path: Path) -> None:
    tree = parse_file(path).tree
    assert tree is not None
    if path.name in NOT_COVERED:
        with pytest.raises(TranslationError) as info:
            from_tst(tree)
        assert info.value.construct == NOT_COVERED[path.name]
        assert str(info.value).startswith(f"{path}:")
        return
    talf = from_tst(tree)
    # through the text too: the printed TALF parses back to the same tree, and checks clean
    reparsed = parse_talf(talf_text(talf), "rt.talf").tree
    assert reparsed == talf
    assert check(reparsed, ACTIONS) == ()
    assert to_tst(reparsed) == tree


def test_every_example_tst_is_either_covered_or_named() -> None:
    assert {p.name for p in TST_EXAMPLES} >= set(NOT_COVERED)
    assert len(TST_EXAMPLES) - len(NOT_COVERED) >= 9


HEADER = """world revinge
agents uav0, uav1, uav2, uav3
area Region = polygon((-180, -180), (-80, -180), (-80, -50), (-180, -50))
point Reactor = town_hall at 0
point N = (190, 100, 30)
point S = (190, 0, 30)
point E = (240, 50, 30)
point W = (140, 50, 30)
point Depot = supply_depot at 20
point Above = west_field at 20
point Field = west_field at 0
point box1 = box1 at 0
"""

LIBRARY_USES = [
    "[TS, TE] monitor-single(uav0, Reactor, 60)",
    "[TS, TE] monitor-pattern(Reactor, N, S, E, W, 6, 120)",
    "[TS, TE] scan-for-people(uav1, Region, 5)",
    "[TS, TE] scan-with-all-uavs(Region, 5)",
    "[TS, TE] deliver-box(uav2, box1, Depot, Above, Field, 6)",
    "[TS, TE] deliver-supplies(Depot, Above, Field, 6)",
]


@pytest.mark.parametrize("use", LIBRARY_USES, ids=lambda u: u.split("]")[1].split("(")[0].strip())
def test_library_actions_go_to_a_valid_tst_and_back(use: str) -> None:
    parsed = parse_talf(f"{HEADER}mission m: {use} where TS = 0 and TE <= 3600", "m.talf")
    assert parsed.tree is not None, parsed.diagnostics
    tree = with_library(parsed.tree)
    assert check(tree, ACTIONS) == ()
    tst = to_tst(tree)
    text = file_text(tst)
    checked = load_text(text, "m.tst")
    assert checked.status is CheckStatus.OK, [str(d) for d in checked.diagnostics]
    back = from_tst(parse_text(text).tree)  # type: ignore[arg-type]
    expanded = expand(tree.missions()[0], tree.specs())
    assert back.missions() == (expanded,), talf_text(back)
    assert to_tst(back) == tst


@pytest.mark.parametrize(
    ("file", "mission", "nodes"),
    [
        ("fukushima_monitor.talf", "diamond", 26),
        ("fukushima_monitor.talf", "single", 6),
        ("emergency_services.talf", "emergency", 12),
    ],
)
def test_the_talf_examples_become_tsts_that_check(file: str, mission: str, nodes: int) -> None:
    parsed = parse_talf_file(ROOT / "examples" / "talf" / file)
    assert parsed.tree is not None, parsed.diagnostics
    tree = with_library(parsed.tree)
    assert check(tree, ACTIONS) == ()
    checked = load_text(file_text(to_tst(tree, mission)), f"{mission}.tst")
    assert checked.status is CheckStatus.OK, [str(d) for d in checked.diagnostics]
    assert checked.tst is not None
    assert len(checked.tst.tree.nodes) == nodes


@pytest.mark.parametrize(
    ("talf", "construct"),
    [
        (
            "mission m: [t, t2] land() where [t] has-camera(P)",
            "where clause part '[t] has-camera(P)'",
        ),
        ("mission m: [t, t2] land() where a = b or a = c", "where clause part 'a = b or a = c'"),
        (
            "mission m: [t, t2] with c do while [c] a(x) and b(x) do [t, t2] land() where true",
            "condition '[c] a(x) and b(x)'",
        ),
        ("mission m: [t, t2] land()", "mission n"),
    ],
)
def test_talf_without_a_tst_counterpart_is_named(talf: str, construct: str) -> None:
    parsed = parse_talf(talf)
    assert parsed.tree is not None
    with pytest.raises(TranslationError) as info:
        to_tst(parsed.tree, "n" if construct == "mission n" else None)
    assert info.value.construct == construct


@pytest.mark.parametrize(
    ("tst", "construct"),
    [
        ("m(TS, TE) = with A concurrent a(TS, TE) = land(TS, TE)", "concurrent node m"),
        ("m(TS, TE) = land(1, 2)", "action node m"),
        ("m(X, TS, TE, Y) = land(TS, TE)", "node m"),
    ],
)
def test_tst_without_a_talf_counterpart_is_named(tst: str, construct: str) -> None:
    tree = parse_text(tst).tree
    assert tree is not None
    with pytest.raises(TranslationError) as info:
        from_tst(tree)
    assert info.value.construct == construct
