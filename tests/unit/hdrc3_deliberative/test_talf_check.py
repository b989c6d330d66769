"""TALF name, arity and kind checks against the TST action registry, and capabilities."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.talf_check import check, check_capabilities, free_names
from hdrc3_deliberative.talf_expand import expand
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_deliberative.talf_syntax import TalfFile
from hdrc3_tst.actions import ACTIONS

HEADER = "agents uav0, uav1\narea A = polygon((0, 0), (9, 0), (9, 9))\npoint D = H1 at 20\n"
"""Three lines: every case below starts on line 4."""


def _tree(text: str) -> TalfFile:
    parsed = parse_text(HEADER + text, "m.talf")
    assert parsed.tree is not None, parsed.diagnostics
    return parsed.tree


@pytest.mark.parametrize(
    "text",
    [
        "mission m: [t, t2] by P with u, u2 do [u, u2] fly-to(6, D) where P = uav0",
        "mission m: [t, t2] with s do [t, t2] scan-area(s, A, 30, 1, 2) where s <= 6",
        "[t, t2] go(av, p) ~> [t, t2] by av fly-to(5, p)\nmission m: [a, b] go(uav1, D)",
        "open S\nmission m: [t, t2] fly-to(S, D)",
        "constraint c = t <= t2\nmission m: [t, t2] land() where c",
        "mission m: [t, t2] with c do foreach x where [c] area(x) do conc [t, t2] scan-area(5, x)",
    ],
)
def test_valid_missions_have_no_diagnostics(text: str) -> None:
    assert check(_tree(text), ACTIONS) == ()


@pytest.mark.parametrize(
    ("text", "code", "where", "reason"),
    [
        ("mission m: [t, t2] fly-to(6, Nowhere)", "T101", "4:30", "unbound variable 'Nowhere'"),
        ("mission m: [t, t2] ([u, u2] land())", "T101", "4:22", "unbound variable 'u'"),
        (
            "mission m: [t, t2] ([t, t2] by X land())",
            "T101",
            "4:22",
            "unbound variable 'X' in 'by'",
        ),
        ("mission m: [t, t2] land() where x <= 3", "T101", "4:33", "unbound variable 'x'"),
        ("mission m: [t, t2] fly(6, D)", "T102", "4:20", "unknown action 'fly'"),
        ("mission m: [t, t2] hover()", "T103", "4:20", "hover takes (duration), got 0"),
        ("mission m: [t, t2] land(0, 1)", "T103", "4:20", "land takes (heading), got 2"),
        ("mission m: [t, t2] fly-to(6, A)", "T104", "4:30", "destination is a point; A is a area"),
        ("mission m: [t, t2] fly-to(6, 7)", "T104", "4:20", "destination is a point, not a number"),
        (
            "mission m: [t, t2] scan-area(uav0, A)",
            "T104",
            "4:30",
            "speed is a speed; uav0 is a agent",
        ),
        (
            "[t, t2] go(p) ~> [t, t2] fly-to(5, p)\nmission m: [a, b] go(D, D)",
            "T103",
            "5:19",
            "go takes 1 arguments (p), got 2",
        ),
        ("[t, t2] go() ~> [t, t2] go()", "T106", "4:9", "recursive composite action: go -> go"),
        ("[t, t2] land() ~> [t, t2] hover(1)", "T105", "4:9", "'land' is an elementary action"),
        ("point D = H2 at 9", "T105", "4:7", "'D' defined twice"),
        ("mission m: [t, t2] land() where nope", "T107", "4:33", "unknown constraint set 'nope'"),
        (
            "constraint a = b\nconstraint b = a\nmission m: [t, t2] land() where a",
            "T107",
            "5:16",
            "recursive constraint set 'a'",
        ),
        ("mission m: [t, t2] ([t, t2] by D land())", "T104", "4:22", "'by' takes an agent; D is a"),
        (
            "mission m: [t, t2] (a: [t, t2] land() ; a: [t, t2] land())",
            "T105",
            "4:41",
            "label 'a' used twice",
        ),
    ],
)
def test_bad_input_gives_a_located_reason(text: str, code: str, where: str, reason: str) -> None:
    diags = check(_tree(text), ACTIONS)
    assert diags, "expected a diagnostic"
    first = diags[0]
    assert (first.code, f"{first.pos.line}:{first.pos.column}") == (code, where), str(first)
    assert reason in first.message
    assert str(first).startswith(f"m.talf:{where}: error {code}: ")


def test_free_names_are_listed_in_order_of_use() -> None:
    tree = _tree("mission m: [t, t2] with u do ([u, v] fly-to(S, D) ; [v, w] hover(H))")
    assert free_names(tree, ACTIONS) == ("v", "S", "w", "H")


ALL = frozenset({"flight", "camera", "ptu", "hook"})


@pytest.mark.parametrize(
    ("text", "capabilities", "found"),
    [
        ("mission m: [t, t2] scan-area(5, A)", {"uav0": ALL, "uav1": frozenset()}, []),
        (
            "mission m: [t, t2] scan-area(5, A)",
            {"uav0": frozenset({"flight"}), "uav1": frozenset({"flight", "hook"})},
            [
                "m/scan-area needs camera+flight+ptu; no agent has it"
                " (uav0: flight; uav1: flight+hook)"
            ],
        ),
        (
            # the agent is fixed by the where clause: only uav1 is a candidate
            "mission m: [t, t2] by P with u do (x: [t, u] land() ; [u, t2] scan-area(5, A))"
            " where P = uav1",
            {"uav0": ALL, "uav1": frozenset({"flight"})},
            ["m/scan-area needs camera+flight+ptu; no agent has it (uav1: flight)"],
        ),
        (
            "mission m: [t, t2] by uav1 (x: [t, t2] pick-up-box(D))",
            {"uav0": ALL, "uav1": frozenset({"flight", "camera"})},
            ["m/x needs flight+hook; no agent has it (uav1: camera+flight)"],
        ),
        (
            "mission m: [t, t2] by P wait(3) where P in {uav0}",
            {"uav0": frozenset(), "uav1": frozenset()},
            [],
        ),
    ],
)
def test_no_agent_with_the_needed_capabilities_is_reported(
    text: str, capabilities: dict[str, frozenset[str]], found: list[str]
) -> None:
    tree = _tree(text)
    assert check(tree, ACTIONS) == ()
    mission = expand(tree.missions()[0], tree.specs())
    diags = check_capabilities("m", mission.body, ACTIONS, capabilities)
    assert [d.message.removeprefix("unsatisfiable constraints: ") for d in diags] == found
    assert all(d.code == "T110" for d in diags)
