"""Expansion of composite action terms into instances of their types."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.talf_expand import ExpansionError, expand
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_deliberative.talf_printer import cact_text

LIBRARY = """
[t, t2] hop(av, p) ~> [t, t2] by av with a, b do [a, b] fly-to(5, p) where b - a <= 60
[t, t2] twice(av, p) ~> [t, t2] with c, d, e, f do ([c, d] hop(av, p) ; [e, f] hop(av, p))
[t, t2] wait-for(d) ~> [t, t2] wait(d) where t2 - t >= d
"""


@pytest.mark.parametrize(
    ("mission", "expected"),
    [
        (
            # a plain term: replaced by the instance, its own variables renamed fresh
            "[x, y] hop(uav0, D)",
            "hop_3: [x, y] by uav0 with a_1, b_2 do [a_1, b_2] fly-to(5, D) where b_2 - a_1 <= 60",
        ),
        (
            # a term with an interval and a with clause of its own: a sequence of one keeps them
            "m1: [x, y] with u, v do [u, v] hop(P, D)",
            "m1: [x, y] with u, v do (\n"
            "  hop_3: [u, v] by P with a_1, b_2 do [a_1, b_2] fly-to(5, D) where b_2 - a_1 <= 60\n"
            ")",
        ),
        (
            # nested composite actions: two instances never share a variable
            "[x, y] twice(uav1, D)",
            "twice_11: [x, y] with c_1, d_2, e_3, f_4 do (\n"
            "  hop_7: [c_1, d_2] by uav1 with a_5, b_6 do [a_5, b_6] fly-to(5, D)"
            " where b_6 - a_5 <= 60 ;\n"
            "  hop_10: [e_3, f_4] by uav1 with a_8, b_9 do [a_8, b_9] fly-to(5, D)"
            " where b_9 - a_8 <= 60\n"
            ")",
        ),
        (
            # a number for a parameter goes into the constraints as a constant
            "[x, y] wait-for(30)",
            "wait-for_1: [x, y] wait(30) where y - x >= 30",
        ),
    ],
)
def test_terms_become_instances_of_their_types(mission: str, expected: str) -> None:
    parsed = parse_text(f"{LIBRARY}\nmission m: {mission}")
    assert parsed.tree is not None, parsed.diagnostics
    expanded = expand(parsed.tree.missions()[0], parsed.tree.specs())
    assert cact_text(expanded.body) == expected


def test_elementary_actions_are_left_alone() -> None:
    parsed = parse_text("mission m: [x, y] (a: [x, y] land())")
    assert parsed.tree is not None
    mission = parsed.tree.missions()[0]
    assert expand(mission, {}) == mission


def test_a_number_where_a_timepoint_is_needed_is_refused() -> None:
    parsed = parse_text("[t, t2] f(a) ~> [t, t2] ([a, t2] land())\nmission m: [x, y] f(3)")
    assert parsed.tree is not None
    with pytest.raises(
        ExpansionError, match=r"^<string>:2:19: f: timepoint 'a' is given the number 3$"
    ):
        expand(parsed.tree.missions()[0], parsed.tree.specs())
