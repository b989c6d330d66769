"""Grounding of monitor formulas: variables, objects, finite sorts and compiled atoms.

A :class:`Scope` says which objects each sort holds, which variables are already bound (e.g. the
arguments of an operator-specific monitor formula, chapter Example 9.2) and which execution flag
``EXEC`` stands for. Identifiers are resolved as follows:

* a fluent argument is its variable's object if bound, else an object name as written;
* a bare identifier in a value term is its variable's object if bound, an object constant if some
  sort contains it, and otherwise a 0-ary fluent;
* ``EXEC`` is the scope's ``exec_flag`` (``"EXEC"`` when none is given).

:func:`compile_formula` grounds a formula into hash-consed :mod:`residual` nodes, expanding
``forall``/``exists`` into conjunctions/disjunctions over the (static, finite) domain, which is
what Definition 9.3 does at every progression step, done once up front.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

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
    Formula,
    Implies,
    Negative,
    Not,
    Number,
    Or,
    Quantified,
    Quantifier,
    Term,
    Until,
)
from hdrc3_dyknow.interpretation import (
    FluentTypeError,
    FluentValue,
    UnknownFluentError,
    atom_key,
    parse_atom_key,
)
from hdrc3_dyknow.residual import Node, NodeTable

Values = Mapping[str, FluentValue]
TermFunction = Callable[[Values, float], FluentValue]
"""Compiled value term: ``(values, time_ms) -> value``."""

COMPARE_FUNCTIONS: dict[CompareOp, Callable[[FluentValue, FluentValue], bool]] = {
    CompareOp.LT: operator.lt,
    CompareOp.LE: operator.le,
    CompareOp.GT: operator.gt,
    CompareOp.GE: operator.ge,
    CompareOp.EQ: operator.eq,
    CompareOp.NE: operator.ne,
}
EXEC = "EXEC"


class GroundingError(ConfigError):
    """A formula refers to an unknown sort or uses a variable where a fluent is needed."""


@dataclass(frozen=True)
class Scope:
    """What the identifiers of a formula mean.

    Attributes:
        domains: Objects of each sort, e.g. ``{"AV": ("uav0", "uav1")}``.
        bindings: Values of free variables, e.g. ``{"av": "uav0", "box": "box3"}``.
        exec_flag: Ground atom key that ``EXEC`` stands for, e.g. ``"executing-climb(uav0)"``.

    """

    domains: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    bindings: Mapping[str, str] = field(default_factory=dict)
    exec_flag: str | None = None

    def objects(self) -> frozenset[str]:
        """Every object of every sort."""
        return frozenset(obj for members in self.domains.values() for obj in members)

    def domain(self, sort: str) -> tuple[str, ...]:
        """Objects of ``sort``.

        Raises:
            GroundingError: The sort is unknown.

        """
        try:
            return self.domains[sort]
        except KeyError:
            known = ", ".join(sorted(self.domains)) or "none"
            raise GroundingError(f"unknown sort {sort!r} (known sorts: {known})") from None

    def ground_fluent(self, fluent: FluentTerm, env: Mapping[str, str]) -> FluentTerm:
        """``fluent`` with variables in ``env`` (then bindings) and ``EXEC`` substituted."""
        if fluent.name == EXEC and not fluent.args and self.exec_flag is not None:
            name, args = parse_atom_key(self.exec_flag)
            return FluentTerm(name, args)
        return FluentTerm(
            fluent.name,
            tuple(
                self.ground_fluent(arg, env)
                if isinstance(arg, FluentTerm)
                else env.get(arg, self.bindings.get(arg, arg))
                for arg in fluent.args
            ),
        )

    def fluent_key(
        self,
        fluent: FluentTerm,
        env: Mapping[str, str],
        values: Values | None = None,
        time_ms: float = math.nan,
    ) -> str:
        """Ground atom key of ``fluent`` in ``env``; nested arguments are read from ``values``.

        Raises:
            UnknownFluentError: A nested argument's fluent is not in ``values``.
            FluentTypeError: A nested argument's value is not an object name.

        """
        return resolve_key(self.ground_fluent(fluent, env), values or {}, time_ms)

    def object_constant(
        self, fluent: FluentTerm, env: Mapping[str, str], objects: frozenset[str]
    ) -> str | None:
        """The object a bare identifier in a value term denotes, or None if it is a fluent."""
        if fluent.args:
            return None
        bound = env.get(fluent.name, self.bindings.get(fluent.name))
        if bound is not None:
            return bound
        return fluent.name if fluent.name in objects else None


def resolve_key(ground: FluentTerm, values: Values, time_ms: float) -> str:
    """Atom key of a ground fluent term, nested arguments replaced by their values.

    A nested argument's value in ``values`` is an object, e.g.
    ``fuel-usage(uav0, location(uav0))`` -> ``fuel-usage(uav0,depot1)``.

    Raises:
        UnknownFluentError: A nested argument's fluent is not in ``values``.
        FluentTypeError: A nested argument's value is not an object name.

    """
    args: list[str] = []
    for arg in ground.args:
        if isinstance(arg, str):
            args.append(arg)
            continue
        key = resolve_key(arg, values, time_ms)
        try:
            value = values[key]
        except KeyError:
            raise UnknownFluentError(key, time_ms) from None
        if not isinstance(value, str):
            raise FluentTypeError(
                f"argument {arg} of {ground.name} has the value {value!r}, not an object name"
            )
        args.append(value)
    return atom_key(ground.name, tuple(args))


def compile_formula(table: NodeTable, formula: Formula, scope: Scope) -> Node:
    """Ground ``formula`` in ``scope`` into interned nodes of ``table``.

    Raises:
        GroundingError: Unknown sort, or a variable used as a boolean fluent.

    """
    return _Compiler(table, scope).formula(formula, {})


def quantified_sorts(formula: Formula) -> set[str]:
    """Sorts that the quantifiers of ``formula`` range over."""
    if isinstance(formula, Quantified):
        return {formula.sort} | quantified_sorts(formula.body)
    if isinstance(formula, Not):
        return quantified_sorts(formula.operand)
    if isinstance(formula, And | Or):
        return set().union(*(quantified_sorts(op) for op in formula.operands))
    if isinstance(formula, Implies | Until):
        return quantified_sorts(formula.left) | quantified_sorts(formula.right)
    if isinstance(formula, Always | Eventually):
        return quantified_sorts(formula.body)
    return set()


def evaluate_arithmetic(op: ArithOp, left: FluentValue, right: FluentValue, text: str) -> float:
    """``left op right`` for numbers, with readable errors for strings and division by zero."""
    if isinstance(left, str) or isinstance(right, str):
        raise FluentTypeError(f"arithmetic on an object name in {text}")
    if op == ArithOp.ADD:
        return left + right
    if op == ArithOp.SUB:
        return left - right
    if op == ArithOp.MUL:
        return left * right
    if right == 0:
        return math.copysign(math.inf, left) if left != 0 else math.nan
    return left / right


def compare_values(op: CompareOp, left: FluentValue, right: FluentValue, text: str) -> bool:
    """``left op right``; ordering an object name against a number is a :class:`FluentTypeError`."""
    try:
        return COMPARE_FUNCTIONS[op](left, right)
    except TypeError:
        raise FluentTypeError(f"cannot compare {left!r} and {right!r} in {text}") from None


class _Compiler:
    def __init__(self, table: NodeTable, scope: Scope) -> None:
        self._table = table
        self._scope = scope
        self._objects = scope.objects()

    def formula(self, formula: Formula, env: dict[str, str]) -> Node:
        table = self._table
        if isinstance(formula, Constant):
            return table.true if formula.value else table.false
        if isinstance(formula, Atom):
            return self._atom(formula.fluent, env)
        if isinstance(formula, Comparison):
            return self._comparison(formula, env)
        if isinstance(formula, Not):
            return table.negation(self.formula(formula.operand, env))
        if isinstance(formula, And):
            return table.conjunction(self.formula(op, env) for op in formula.operands)
        if isinstance(formula, Or):
            return table.disjunction(self.formula(op, env) for op in formula.operands)
        if isinstance(formula, Implies):
            left = table.negation(self.formula(formula.left, env))
            return table.disjunction((left, self.formula(formula.right, env)))
        if isinstance(formula, Always):
            bounds = formula.interval
            return table.always(bounds.lower, bounds.upper, self.formula(formula.body, env))
        if isinstance(formula, Eventually):
            bounds = formula.interval
            return table.eventually(bounds.lower, bounds.upper, self.formula(formula.body, env))
        if isinstance(formula, Until):
            bounds = formula.interval
            return table.until(
                bounds.lower,
                bounds.upper,
                self.formula(formula.left, env),
                self.formula(formula.right, env),
            )
        return self._quantified(formula, env)

    def _quantified(self, formula: Quantified, env: dict[str, str]) -> Node:
        instances = [
            self.formula(formula.body, {**env, formula.variable: obj})
            for obj in self._scope.domain(formula.sort)
        ]
        if formula.quantifier == Quantifier.FORALL:
            return self._table.conjunction(instances)
        return self._table.disjunction(instances)

    def _atom(self, fluent: FluentTerm, env: dict[str, str]) -> Node:
        if not fluent.args and (fluent.name in env or fluent.name in self._scope.bindings):
            raise GroundingError(f"variable {fluent.name!r} used as a boolean fluent")
        ground = self._scope.ground_fluent(fluent, env)
        if ground.nested:
            # The key depends on the state: a compiled test rather than an interned atom.
            text = str(ground)

            def holds(values: Values, time_ms: float) -> bool:
                key = resolve_key(ground, values, time_ms)
                try:
                    value = values[key]
                except KeyError:
                    raise UnknownFluentError(key, time_ms) from None
                if isinstance(value, str):
                    raise FluentTypeError(f"boolean fluent {text} has the object value {value!r}")
                return bool(value)

            return self._table.comparison(holds, Atom(ground))
        return self._table.atom(resolve_key(ground, {}, math.nan), Atom(ground))

    def _comparison(self, comparison: Comparison, env: dict[str, str]) -> Node:
        left, left_tree = self._term(comparison.left, env)
        right, right_tree = self._term(comparison.right, env)
        ground = Comparison(comparison.op, left_tree, right_tree)
        text = str(ground)
        op = comparison.op

        def compare(values: Values, time_ms: float) -> bool:
            return compare_values(op, left(values, time_ms), right(values, time_ms), text)

        try:
            # Comparisons of constants and objects (x != av1 under a quantifier) fold now.
            static = compare({}, math.nan)
        except (UnknownFluentError, FluentTypeError):
            return self._table.comparison(compare, ground)
        return self._table.true if static else self._table.false

    def _term(self, term: Term, env: dict[str, str]) -> tuple[TermFunction, Term]:
        """Compile ``term`` into a function and its ground tree."""
        if isinstance(term, Number):
            number = term.value
            return (lambda values, time_ms: number), term
        if isinstance(term, FluentTerm):
            return self._fluent_term(term, env)
        if isinstance(term, Negative):
            inner, tree = self._term(term.operand, env)
            text = str(term)

            def negate(values: Values, time_ms: float) -> FluentValue:
                value = inner(values, time_ms)
                if isinstance(value, str):
                    raise FluentTypeError(f"arithmetic on an object name in {text}")
                return -value

            return negate, Negative(tree)
        left, left_tree = self._term(term.left, env)
        right, right_tree = self._term(term.right, env)
        op = term.op
        text = str(term)

        def arithmetic(values: Values, time_ms: float) -> FluentValue:
            return evaluate_arithmetic(op, left(values, time_ms), right(values, time_ms), text)

        return arithmetic, Arithmetic(op, left_tree, right_tree)

    def _fluent_term(self, term: FluentTerm, env: dict[str, str]) -> tuple[TermFunction, Term]:
        constant = self._scope.object_constant(term, env, self._objects)
        if constant is not None:
            return (lambda values, time_ms: constant), FluentTerm(constant)
        ground = self._scope.ground_fluent(term, env)
        if ground.nested:

            def lookup_nested(values: Values, time_ms: float) -> FluentValue:
                key = resolve_key(ground, values, time_ms)
                try:
                    return values[key]
                except KeyError:
                    raise UnknownFluentError(key, time_ms) from None

            return lookup_nested, ground
        key = resolve_key(ground, {}, math.nan)

        def lookup(values: Values, time_ms: float) -> FluentValue:
            try:
                return values[key]
            except KeyError:
                raise UnknownFluentError(key, time_ms) from None

        return lookup, ground
