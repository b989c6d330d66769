"""Monitor formula language: concrete syntax, precedence, printing and syntax errors."""

from __future__ import annotations

import math

import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_dyknow.formula import (
    Always,
    And,
    Arithmetic,
    ArithOp,
    Atom,
    CompareOp,
    Comparison,
    Constant,
    Eventually,
    FluentTerm,
    Implies,
    Interval,
    Negative,
    Not,
    Number,
    Or,
    Quantified,
    Quantifier,
    Until,
)
from hdrc3_dyknow.formula_parser import FormulaParser, FormulaSyntaxError, parse_formula

PARSER = FormulaParser()
p, q, r = (Atom(FluentTerm(name)) for name in "pqr")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("true", Constant(True)),
        ("false", Constant(False)),
        ("p", p),
        ("carrying(av, box)", Atom(FluentTerm("carrying", ("av", "box")))),
        ("executing-climb(av)", Atom(FluentTerm("executing-climb", ("av",)))),
        ("EXEC", Atom(FluentTerm("EXEC"))),
        ("not p", Not(p)),
        ("p and q or r", Or((And((p, q)), r))),
        ("p or q and r", Or((p, And((q, r))))),
        ("p and q and r", And((p, q, r))),
        ("p implies q implies r", Implies(p, Implies(q, r))),
        ("not p implies q", Implies(Not(p), q)),
        ("always p", Always(Interval(), p)),
        ("always[0,999] p", Always(Interval(0, 999), p)),
        ("eventually[10.5,inf] p", Eventually(Interval(10.5, math.inf), p)),
        ("always p and q", And((Always(Interval(), p), q))),
        ("p until q", Until(Interval(), p, q)),
        ("p until[0,5000] q until r", Until(Interval(0, 5000), p, Until(Interval(), q, r))),
        ("p and q until r", And((p, Until(Interval(), q, r)))),
        ("not p until q", Until(Interval(), Not(p), q)),
        (
            "speed(uav0) > 10.5",
            Comparison(CompareOp.GT, FluentTerm("speed", ("uav0",)), Number(10.5)),
        ),
        (
            "altitude(av) >= 7.0",
            Comparison(CompareOp.GE, FluentTerm("altitude", ("av",)), Number(7.0)),
        ),
        ("x = y", Comparison(CompareOp.EQ, FluentTerm("x"), FluentTerm("y"))),
        (
            "a - 2 * b / c < -d",
            Comparison(
                CompareOp.LT,
                Arithmetic(
                    ArithOp.SUB,
                    FluentTerm("a"),
                    Arithmetic(
                        ArithOp.DIV,
                        Arithmetic(ArithOp.MUL, Number(2), FluentTerm("b")),
                        FluentTerm("c"),
                    ),
                ),
                Negative(FluentTerm("d")),
            ),
        ),
        (
            "(a + b) * 2 != 3",
            Comparison(
                CompareOp.NE,
                Arithmetic(
                    ArithOp.MUL,
                    Arithmetic(ArithOp.ADD, FluentTerm("a"), FluentTerm("b")),
                    Number(2),
                ),
                Number(3),
            ),
        ),
        (
            "forall x in AV: p(x) and q",
            Quantified(Quantifier.FORALL, "x", "AV", And((Atom(FluentTerm("p", ("x",))), q))),
        ),
        (
            "always exists x in AV: p(x)",
            Always(
                Interval(), Quantified(Quantifier.EXISTS, "x", "AV", Atom(FluentTerm("p", ("x",))))
            ),
        ),
        ("p # a comment\n and q", And((p, q))),
        ("always-on", Atom(FluentTerm("always-on"))),
        (  # nested fluent terms (Definition 9.2)
            "fuel-usage(av, x(av), y(z(av)))",
            Atom(
                FluentTerm(
                    "fuel-usage",
                    ("av", FluentTerm("x", ("av",)), FluentTerm("y", (FluentTerm("z", ("av",)),))),
                )
            ),
        ),
    ],
)
def test_parse_table(text: str, expected: object) -> None:
    assert PARSER.parse(text) == expected


@pytest.mark.parametrize(
    "text",
    [
        "always (not p implies eventually[0,1000] always[0,999] p)",
        "forall x in AV: x != av1 implies always xydist(x, av1) > 10",
        "EXEC until[0,5000] (carrying(av, box) until executing-putdown(av, box))",
        "always (power(av) > m implies power(av) < f * m until[0,300] always[0,500] power(av) <= m)",  # noqa: E501
        "(p until q) until[1,2] r",
        "always fuel-usage(av, location(av), dest(av)) < 3 and windy(location(av))",
    ],
)
def test_printing_round_trips(text: str) -> None:
    formula = PARSER.parse(text)
    assert PARSER.parse(str(formula)) == formula


@pytest.mark.parametrize(
    ("text", "line", "column", "offending", "expected_token"),
    [
        ("always[0 p", 1, 10, "p", "','"),
        ("p and", 1, 6, "end of formula", "identifier"),
        ("p\n  and and q", 2, 7, "and", "'not'"),
        ("p & q", 1, 3, "&", "'and'"),
        ("forall in AV: p", 1, 8, "in", "identifier"),
        ("speed(x) < ", 1, 12, "end of formula", "number"),
    ],
)
def test_syntax_errors_report_position_and_expected(
    text: str, line: int, column: int, offending: str, expected_token: str
) -> None:
    with pytest.raises(FormulaSyntaxError) as caught:
        PARSER.parse(text, source="mon.txt")
    error = caught.value
    assert isinstance(error, ConfigError)
    assert (error.line, error.column, error.text) == (line, column, offending)
    assert expected_token in error.expected
    assert str(error).startswith(f"mon.txt:{line}:{column}:")


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("speed(x) + 1", "used as a formula"),
        ("true + 1 > 0", "used as a value term"),
        ("always[inf,3] p", "lower bound must be finite"),
        ("(p and q) > 1", "used as a value term"),
    ],
)
def test_semantic_syntax_errors(text: str, reason: str) -> None:
    with pytest.raises(FormulaSyntaxError, match=reason):
        parse_formula(text)
