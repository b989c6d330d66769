"""A lark syntax error as a place and a sentence."""

from __future__ import annotations

import lark
import pytest

from hdrc3_base.syntax_errors import describe

GRAMMAR = """
start: item+
item: "let" NAME "=" NUMBER ";"
NAME: /[a-z]+/
NUMBER: /[0-9]+/
%ignore " " | "\\n"
"""


@pytest.mark.parametrize(
    ("text", "line", "column", "message"),
    [
        ("let x = 1", 1, 10, "unexpected end of file; expected one of: ';'"),
        ("let x = 1;\nlet", 2, 4, "unexpected end of file; expected one of: NAME"),
        ("let x = y;", 1, 9, "unexpected 'y'; expected one of: NUMBER"),
        ("let x = 1; @", 1, 12, "unexpected '@'; expected one of: 'let'"),
        ("let = 1;", 1, 5, "unexpected '='; expected one of: NAME"),
    ],
)
def test_an_error_is_placed_and_named(text: str, line: int, column: int, message: str) -> None:
    parser = lark.Lark(GRAMMAR, parser="lalr")
    with pytest.raises(lark.exceptions.UnexpectedInput) as caught:
        parser.parse(text)
    problem = describe(caught.value, parser, text)
    assert (problem.line, problem.column, problem.message) == (line, column, message)


def test_the_expected_list_is_cut_to_the_most_asked_for() -> None:
    parser = lark.Lark('start: "a" | "b" | "c"', parser="lalr")
    with pytest.raises(lark.exceptions.UnexpectedInput) as caught:
        parser.parse("d")
    problem = describe(caught.value, parser, "d", most=2)
    assert problem.message == "unexpected 'd'; expected one of: 'a', 'b'"
    assert problem.expected == ("'a'", "'b'", "'c'")
