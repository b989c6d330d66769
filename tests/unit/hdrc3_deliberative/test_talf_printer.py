"""TALF printer: printed text parses back to an equal tree."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.talf_library import library, library_text
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_deliberative.talf_printer import file_text

CASES = [
    "world revinge\nagents uav0\narea A = polygon((0, 0.5), (1, 0), (1, 1))\n"
    "point P = H1 at 20\npoint Q = (1, -2, 3)\npath R = (P, Q)\nopen S, V",
    "constraint c = t <= t2 and t2 - t < 5.5\nmission m: [t, t2] land() where c and P in {uav0}",
    "mission m: top: [t, t2] by P with u, v do (a: [t, u] land() ; [u, v] fly-to(S, D))",
    "mission m: [t, t2] ([t, t2] land() || [t, t2] hover(1) || [t, t2] wait(2))",
    # nested tail positions: the inner C-ACTs need `where true` so the outer where stays outer
    "mission m: [t, t2] with c do while [c] not airborne(P) do [t, t2] if [c] a(x) then"
    " [t, t2] land() else [t, t2] foreach q where [c] area(q) do conc [t, t2] hover(1)"
    " where true where true where true where t2 - t <= 3",
    "mission m: [t, t2] land() where [t] a(x) and not b(y) and t = t2",
    "mission m: [t, t2] land() where ([t] a(x)) and ([t2] b(x)) or exists z (c(z))",
    "[t, t2] f(a, b) ~> [t, t2] with u do [u, t2] g(a, -1.25) where u - t >= b",
]


@pytest.mark.parametrize("text", CASES)
def test_printed_text_parses_back_equal(text: str) -> None:
    first = parse_text(text)
    assert first.tree is not None, first.diagnostics
    printed = file_text(first.tree)
    again = parse_text(printed)
    assert again.tree == first.tree, printed
    assert file_text(again.tree) == printed


def test_the_library_prints_and_parses_back_equal() -> None:
    printed = file_text(library())
    again = parse_text(printed)
    assert again.tree == library()
    assert printed != library_text()  # comments and layout are not kept
