"""TALF formulas: flat conjunctions, negation, the text of timed atoms."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.mission_syntax import Name
from hdrc3_deliberative.talf_formulas import (
    And,
    Atom,
    Exists,
    Formula,
    Lfp,
    Not,
    Occurs,
    Or,
    PredApp,
    TrueF,
    conj,
    conjuncts,
    formula_names,
    formula_text,
    negate,
    time_le,
)

A = Atom("a", (Name("x"),), "t")
B = Atom("b", (Name("y"),), "t")
C = Atom("c", (), "u")


def test_conj_flattens_and_drops_true_and_repeats() -> None:
    assert conj() == TrueF()
    assert conj(None, TrueF(), A) == A
    assert conj(And((A, B)), A, C) == And((A, B, C))
    assert conjuncts(conj(A, B)) == (A, B)
    assert conjuncts(None) == ()
    assert time_le("t", "t") == TrueF()


def test_negate_does_not_stack_negations() -> None:
    assert negate(A) == Not(A)
    assert negate(Not(A)) == A


@pytest.mark.parametrize(
    ("formula", "hoisted", "local"),
    [
        (conj(A, Not(B)), "[t] a(x) and not b(y)", "([t] a(x)) and not ([t] b(y))"),
        (Or((A, C)), "([t] a(x)) or ([u] c())", "([t] a(x)) or ([u] c())"),
        (Exists(("x",), A), "[t] exists x (a(x))", "exists x (([t] a(x)))"),
        (
            Lfp("W", ("s", "e"), Or((A, PredApp("W", ("s", "e")))), ("t", "t2")),
            "[t] (lfp W(s, e). a(x) or W(s, e))(t, t2)",
            "(lfp W(s, e). ([t] a(x)) or W(s, e))(t, t2)",
        ),
        (Occurs("t", "t2", "fly-to", (Name("av"),)), "Occurs(t, t2, fly-to(av))", None),
    ],
)
def test_text_of_timed_formulas(formula: Formula, hoisted: str, local: str | None) -> None:
    assert formula_text(formula) == hoisted
    assert formula_text(formula, hoist=False) == (local or hoisted)


def test_names_of_a_formula_leave_out_quantified_ones() -> None:
    formula = conj(Exists(("x",), A), B)
    assert [n.id for n in formula_names(formula)] == ["t", "t", "y"]
