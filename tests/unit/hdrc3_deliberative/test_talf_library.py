"""The shipped library of composite actions."""

from __future__ import annotations

from hdrc3_deliberative.talf_check import check
from hdrc3_deliberative.talf_library import library, with_library
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_tst.actions import ACTIONS


def test_the_library_declares_the_chapter_actions_and_checks_clean() -> None:
    assert set(library().specs()) == {
        "monitor-single",
        "monitor-pattern",
        "scan-for-people",
        "scan-with-all-uavs",
        "deliver-box",
        "deliver-supplies",
    }
    assert check(library(), ACTIONS) == ()
    assert library().missions() == ()


def test_a_file_s_own_type_wins_over_the_library_s() -> None:
    parsed = parse_text("[t, t2] monitor-single(a) ~> [t, t2] hover(1)")
    assert parsed.tree is not None
    merged = with_library(parsed.tree)
    assert merged.specs()["monitor-single"].params == ("a",)
    assert set(merged.specs()) == set(library().specs())
