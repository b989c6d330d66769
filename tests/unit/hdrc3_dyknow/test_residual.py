"""Hash-consed nodes: interning, the simplification rules and tense merging."""

from __future__ import annotations

import math

import pytest

from hdrc3_dyknow.formula import Atom, FluentTerm
from hdrc3_dyknow.residual import Node, NodeTable, to_formula


@pytest.fixture
def table() -> NodeTable:
    return NodeTable()


def atom(table: NodeTable, name: str) -> Node:
    return table.atom(name, Atom(FluentTerm(name)))


def text(node: Node) -> str:
    return str(to_formula(node))


def test_identical_formulas_are_one_object(table: NodeTable) -> None:
    with table.compiling():
        first = table.always(0, 10, table.negation(atom(table, "p")))
        second = table.always(0, 10, table.negation(atom(table, "p")))
    assert first is second
    table.advance()  # compiled nodes are kept across states
    with table.compiling():
        assert table.always(0, 10, table.negation(atom(table, "p"))) is first


def test_residuals_are_interned_per_state_on_request() -> None:
    table = NodeTable(intern_residuals=True)
    with table.compiling():
        p = atom(table, "p")
    residual = table.eventually(0, 50, p)
    assert table.eventually(0, 50, p) is residual
    assert table.either(residual, p) is table.disjunction([residual, p])
    table.advance()
    assert table.eventually(0, 50, p) is not residual  # forgotten, rebuilt
    assert len(table) == 2  # the atom and the new residual


def test_residuals_are_not_interned_by_default(table: NodeTable) -> None:
    with table.compiling():
        p = atom(table, "p")
    assert table.eventually(0, 50, p) is not table.eventually(0, 50, p)
    assert text(table.eventually(0, 50, p)) == "eventually[0,50] p"
    assert len(table) == 1


@pytest.mark.parametrize(
    ("build", "expected"),
    [
        (lambda t, p, q: t.negation(t.true), "false"),
        (lambda t, p, q: t.negation(t.negation(p)), "p"),
        (lambda t, p, q: t.conjunction([p, t.false, q]), "false"),
        (lambda t, p, q: t.conjunction([t.true, p]), "p"),
        (lambda t, p, q: t.conjunction([]), "true"),
        (lambda t, p, q: t.disjunction([p, t.true]), "true"),
        (lambda t, p, q: t.disjunction([t.false, q]), "q"),
        (lambda t, p, q: t.disjunction([]), "false"),
        (lambda t, p, q: t.conjunction([p, t.conjunction([q, p])]), "p and q"),
        (lambda t, p, q: t.both(p, p), "p"),
        (lambda t, p, q: t.either(p, t.disjunction([q, p])), "p or q"),
        (lambda t, p, q: t.always(5, 3, p), "true"),  # empty interval
        (lambda t, p, q: t.eventually(5, 3, p), "false"),
        (lambda t, p, q: t.until(5, 3, p, q), "false"),
        (lambda t, p, q: t.always(-20, 30, p), "always[0,30] p"),  # past part dropped
        (lambda t, p, q: t.always(0, 30, t.true), "true"),
        (lambda t, p, q: t.eventually(0, 30, t.false), "false"),
        (lambda t, p, q: t.always(0, math.inf, p), "always p"),
    ],
)
def test_simplification_rules(build: object, expected: str, table: NodeTable) -> None:
    p, q = atom(table, "p"), atom(table, "q")
    assert text(build(table, p, q)) == expected  # type: ignore[operator]


@pytest.mark.parametrize(
    ("kind", "junction", "expected"),
    [
        ("eventually", "and", "eventually[0,10] p"),  # the chapter's min rule
        ("eventually", "or", "eventually[0,20] p"),
        ("always", "and", "always[0,20] p"),
        ("always", "or", "always[0,10] p"),
    ],
)
def test_tense_operands_merge(kind: str, junction: str, expected: str, table: NodeTable) -> None:
    p = atom(table, "p")
    make = table.eventually if kind == "eventually" else table.always
    combine = table.conjunction if junction == "and" else table.disjunction
    assert text(combine([make(0, 10, p), atom(table, "q"), make(0, 20, p)])).startswith(expected)
    assert text(combine([make(0, 10, p), make(5, 20, p)])).count(kind) == 2  # lower bounds differ
