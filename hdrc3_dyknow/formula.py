"""Syntax tree of monitor formulas (HDRC3 chapter Definition 9.2).

A monitor formula combines boolean fluents (``carrying(av, box)``, ``executing-climb(av)``,
``EXEC``), comparisons of value terms (``speed(uav0) > 10.5``), the connectives ``not``, ``and``,
``or``, ``implies``, quantifiers over finite sorts and the metric tense operators ``always[a,b]``,
``eventually[a,b]`` and ``until[a,b]``. Intervals are closed, in milliseconds, relative to the
time at which the operator is evaluated; an omitted interval is ``[0, inf)``.

Identifiers inside fluent arguments and bare identifiers in value terms are resolved when the
formula is grounded (see :mod:`hdrc3_dyknow.grounding`): a quantified variable or binding becomes
its object, a known domain object stays an object constant, anything else is a 0-ary fluent.

Nodes are frozen dataclasses; ``str(node)`` prints the concrete syntax that the parser reads back.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import TypeAlias


class CompareOp(enum.Enum):
    """Comparison operators between value terms."""

    LT = "<"
    LE = "<="
    GT = ">"
    GE = ">="
    EQ = "=="
    NE = "!="


class ArithOp(enum.Enum):
    """Arithmetic operators in value terms."""

    ADD = "+"
    SUB = "-"
    MUL = "*"
    DIV = "/"


class Quantifier(enum.Enum):
    """Quantifiers over a finite sort."""

    FORALL = "forall"
    EXISTS = "exists"


@dataclass(frozen=True, slots=True)
class Interval:
    """A closed relative time interval ``[lower, upper]`` in ms; ``upper`` may be ``inf``."""

    lower: float = 0.0
    upper: float = math.inf

    @property
    def is_default(self) -> bool:
        """True for ``[0, inf)``, the interval of the un-annotated operators."""
        return self.lower == 0.0 and self.upper == math.inf

    @property
    def is_empty(self) -> bool:
        """True when no time point lies in the interval."""
        return self.lower > self.upper

    def __str__(self) -> str:
        return f"[{_number_text(self.lower)},{_number_text(self.upper)}]"


@dataclass(frozen=True, slots=True)
class Number:
    """A numeric constant."""

    value: float

    def __str__(self) -> str:
        return _number_text(self.value)


@dataclass(frozen=True, slots=True)
class FluentTerm:
    """A fluent (state variable) applied to arguments, e.g. ``carrying(av, box)``.

    Attributes:
        name: Fluent name; may contain ``-`` (``executing-climb``).
        args: Arguments: variables or object names, or *nested* fluent terms whose value in
            the current state is the object (``fuel-usage(av, location(av))``, Def. 9.2).

    """

    name: str
    args: tuple[str | FluentTerm, ...] = ()

    @property
    def nested(self) -> bool:
        """Whether an argument is itself a fluent term (its key depends on the state)."""
        return any(isinstance(arg, FluentTerm) for arg in self.args)

    def __str__(self) -> str:
        if not self.args:
            return self.name
        return f"{self.name}({', '.join(str(arg) for arg in self.args)})"


@dataclass(frozen=True, slots=True)
class Negative:
    """Arithmetic negation ``-term``."""

    operand: Term

    def __str__(self) -> str:
        return f"-{_term_text(self.operand, 3)}"


@dataclass(frozen=True, slots=True)
class Arithmetic:
    """A binary arithmetic term ``left op right``."""

    op: ArithOp
    left: Term
    right: Term

    def __str__(self) -> str:
        level = _ARITH_LEVEL[self.op]
        # Left-associative: the right operand needs parentheses at the same level.
        return f"{_term_text(self.left, level)} {self.op.value} {_term_text(self.right, level + 1)}"


Term: TypeAlias = Number | FluentTerm | Negative | Arithmetic
"""A value term."""


@dataclass(frozen=True, slots=True)
class Constant:
    """``true`` or ``false``."""

    value: bool

    def __str__(self) -> str:
        return "true" if self.value else "false"


@dataclass(frozen=True, slots=True)
class Atom:
    """A boolean fluent used as a formula."""

    fluent: FluentTerm

    def __str__(self) -> str:
        return str(self.fluent)


@dataclass(frozen=True, slots=True)
class Comparison:
    """``left op right`` between value terms."""

    op: CompareOp
    left: Term
    right: Term

    def __str__(self) -> str:
        return f"{_term_text(self.left, 0)} {self.op.value} {_term_text(self.right, 0)}"


@dataclass(frozen=True, slots=True)
class Not:
    """Negation."""

    operand: Formula

    def __str__(self) -> str:
        return f"not {_text(self.operand, _UNARY)}"


@dataclass(frozen=True, slots=True)
class And:
    """Conjunction of two or more formulas."""

    operands: tuple[Formula, ...]

    def __str__(self) -> str:
        return " and ".join(_text(op, _CONJ + 1) for op in self.operands)


@dataclass(frozen=True, slots=True)
class Or:
    """Disjunction of two or more formulas."""

    operands: tuple[Formula, ...]

    def __str__(self) -> str:
        return " or ".join(_text(op, _DISJ + 1) for op in self.operands)


@dataclass(frozen=True, slots=True)
class Implies:
    """Implication ``left implies right`` (right-associative)."""

    left: Formula
    right: Formula

    def __str__(self) -> str:
        return f"{_text(self.left, _IMPL + 1)} implies {_text(self.right, _IMPL)}"


@dataclass(frozen=True, slots=True)
class Always:
    """``always[a,b] body``: body holds in every state within the interval."""

    interval: Interval
    body: Formula

    def __str__(self) -> str:
        return f"always{_interval_text(self.interval)} {_text(self.body, _UNARY)}"


@dataclass(frozen=True, slots=True)
class Eventually:
    """``eventually[a,b] body``: body holds in some state within the interval."""

    interval: Interval
    body: Formula

    def __str__(self) -> str:
        return f"eventually{_interval_text(self.interval)} {_text(self.body, _UNARY)}"


@dataclass(frozen=True, slots=True)
class Until:
    """``left until[a,b] right``: right holds in some state within the interval, left before."""

    interval: Interval
    left: Formula
    right: Formula

    def __str__(self) -> str:
        return (
            f"{_text(self.left, _UNTIL + 1)} until{_interval_text(self.interval)} "
            f"{_text(self.right, _UNTIL)}"
        )


@dataclass(frozen=True, slots=True)
class Quantified:
    """``forall x in SORT: body`` or ``exists x in SORT: body`` over a finite domain."""

    quantifier: Quantifier
    variable: str
    sort: str
    body: Formula

    def __str__(self) -> str:
        return f"{self.quantifier.value} {self.variable} in {self.sort}: {self.body}"


Formula: TypeAlias = (
    Constant
    | Atom
    | Comparison
    | Not
    | And
    | Or
    | Implies
    | Always
    | Eventually
    | Until
    | Quantified
)
"""A monitor formula."""

# Binding strength of the concrete syntax, loosest first; printing adds parentheses by it.
_QUANT, _IMPL, _DISJ, _CONJ, _UNTIL, _UNARY, _ATOMIC = range(7)
_ARITH_LEVEL = {ArithOp.ADD: 1, ArithOp.SUB: 1, ArithOp.MUL: 2, ArithOp.DIV: 2}


def _level(formula: Formula) -> int:
    if isinstance(formula, Quantified):
        return _QUANT
    if isinstance(formula, Implies):
        return _IMPL
    if isinstance(formula, Or):
        return _DISJ
    if isinstance(formula, And):
        return _CONJ
    if isinstance(formula, Until):
        return _UNTIL
    if isinstance(formula, Not | Always | Eventually):
        return _UNARY
    return _ATOMIC


def _text(formula: Formula, minimum: int) -> str:
    return f"({formula})" if _level(formula) < minimum else str(formula)


def _term_text(term: Term, minimum: int) -> str:
    level = _ARITH_LEVEL[term.op] if isinstance(term, Arithmetic) else 3
    return f"({term})" if level < minimum else str(term)


def _interval_text(interval: Interval) -> str:
    return "" if interval.is_default else str(interval)


def _number_text(value: float) -> str:
    if value == math.inf:
        return "inf"
    return str(int(value)) if value == int(value) else repr(value)
