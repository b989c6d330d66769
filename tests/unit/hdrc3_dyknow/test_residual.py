"""Hash-consed nodes: interning, the simplification rules and tense merging."""

from __future__ import annotations

import math

import pytest

from hdrc3_dyknow.formula import Atom, FluentTerm
from hdrc3_dyknow.residual import Kind, Node, NodeTable, to_formula


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


@pytest.mark.parametrize(
    ("first", "second", "now", "expected"),
    [
        # Both lower bounds at or before the current state: equal for every later state.
        ((50, 1050), (100, 1099), 100, "always[0,950] p"),
        ((100, 1099), (50, 1050), 100, "always[0,950] p"),
        ((100, 1099), (100, 1050), 100, "always[0,950] p"),  # lower bound exactly now
        # A lower bound after the current state differs: no merge.
        ((50, 1050), (150, 1099), 100, "always[0,950] p or always[50,999] p"),
        ((101, 1050), (100, 1099), 100, "always[1,950] p or always[0,999] p"),
    ],
)
def test_absolute_tense_operands_merge_up_to_now(
    first: tuple[float, float], second: tuple[float, float], now: float, expected: str
) -> None:
    table = NodeTable()
    p = atom(table, "p")
    table.stamp(now)
    one, two = (
        table.tense(Kind.ALWAYS, lower, upper, p, None, True) for lower, upper in (first, second)
    )
    assert str(to_formula(table.either(one, two), now)) == expected


def test_absolute_and_relative_tense_operands_do_not_merge(table: NodeTable) -> None:
    p = atom(table, "p")
    table.stamp(0)
    relative = table.always(0, 10, p)
    absolute = table.tense(Kind.ALWAYS, 0, 20, p, None, True)
    assert text(table.either(relative, absolute)) == "always[0,10] p or always[0,20] p"


@pytest.mark.parametrize(
    ("lower", "upper", "time", "expected"),
    [
        (1000, 2000, 400, "eventually[600,1600] p"),
        (1000, 2000, 1000, "eventually[0,1000] p"),
        (1000, 2000, 1500, "eventually[0,500] p"),  # started: the past part is not shown
        (1000, math.inf, 1500, "eventually p"),
    ],
)
def test_absolute_intervals_print_relative_to_a_time(
    lower: float, upper: float, time: float, expected: str, table: NodeTable
) -> None:
    node = table.tense(Kind.EVENTUALLY, lower, upper, atom(table, "p"), None, True)
    assert str(to_formula(node, time)) == expected


@pytest.mark.parametrize(
    ("junction", "keeper", "node", "expected"),
    [
        # (kind, lower, upper) of absolute tense nodes over p; the state is at 100 ms.
        ("or", ("always", 50, 1050), ("always", 100, 1099), True),  # the weaker is kept
        ("or", ("always", 50, 1050), ("always", 100, 1000), False),
        ("or", ("always", 50, 1050), ("always", 100, 1050), True),  # equal windows
        ("and", ("always", 50, 1050), ("always", 100, 1000), True),  # the stronger is kept
        ("and", ("eventually", 0, 1000), ("eventually", 100, 1100), True),
        ("or", ("eventually", 0, 1000), ("eventually", 100, 1100), False),
        ("or", ("always", 50, 1050), ("always", 150, 1099), False),  # lower bound after now
        ("or", ("always", 50, 1050), ("eventually", 50, 1050), False),  # kinds differ
    ],
)
def test_absorbs_follows_the_merge_rule(
    junction: str,
    keeper: tuple[str, float, float],
    node: tuple[str, float, float],
    expected: bool,
) -> None:
    table = NodeTable()
    p = atom(table, "p")
    table.stamp(100)
    kinds = {"always": Kind.ALWAYS, "eventually": Kind.EVENTUALLY}
    built = [
        table.tense(kinds[kind], lower, upper, p, None, True)
        for kind, lower, upper in (keeper, node)
    ]
    kind = Kind.OR if junction == "or" else Kind.AND
    assert table.absorbs(kind, built[0], built[1]) is expected
    combine = table.disjunction if junction == "or" else table.conjunction
    merged = to_formula(combine(built), 100)
    if expected:  # absorbing agrees with what the junction builds
        assert str(merged) == str(to_formula(built[0], 100))
    assert table.absorbs(kind, built[0], built[0])
