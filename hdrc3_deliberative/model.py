"""Syntax tree of planning domains, problems and control formulas (frozen dataclasses).

Both readers (PDDL and the TAL domain language) produce these values; the grounder and the
control-formula compiler walk them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

ROOT_TYPE = "object"


@dataclass(frozen=True)
class Pos:
    """Source position of a syntax element (1-based line and column)."""

    source: str = ""
    line: int = 0
    column: int = 0


NOWHERE = Pos()


@dataclass(frozen=True)
class Term:
    """A variable (an operator or quantifier parameter) or a constant object name."""

    name: str
    is_var: bool = False


@dataclass(frozen=True)
class Atom:
    """``pred(args)``: a boolean feature, or a numeric feature inside expressions."""

    pred: str
    args: tuple[Term, ...]
    pos: Pos = field(default=NOWHERE, compare=False)


# --- numeric expressions -------------------------------------------------------------------


@dataclass(frozen=True)
class Num:
    """A numeric literal."""

    value: float


@dataclass(frozen=True)
class FuncTerm:
    """Value of a numeric feature or a motion-plan-info function."""

    atom: Atom


@dataclass(frozen=True)
class BinOp:
    """``left op right`` with op in + - * /."""

    op: str
    left: NumExpr
    right: NumExpr


NumExpr = Num | FuncTerm | BinOp


# --- conditions (operator preconditions, prevail conditions, goals) -------------------------


@dataclass(frozen=True)
class Literal:
    """``atom`` or ``not atom``."""

    atom: Atom
    positive: bool = True


@dataclass(frozen=True)
class Equality:
    """``left = right`` (or ``!=`` when not positive) between objects."""

    left: Term
    right: Term
    positive: bool = True


@dataclass(frozen=True)
class Comparison:
    """``left op right`` between numeric expressions, op in < <= > >= = !=."""

    op: str
    left: NumExpr
    right: NumExpr


Condition = Literal | Equality | Comparison


class EffectTime(Enum):
    """When an effect takes place relative to the occurrence ``[t, t']``."""

    START = "t+1"
    END = "t'"


@dataclass(frozen=True)
class AtomEffect:
    """``R([time] atom := positive)``."""

    time: EffectTime
    literal: Literal


@dataclass(frozen=True)
class NumEffect:
    """``R([time] f := expr)`` with op ``:=``, ``+=`` or ``-=``."""

    time: EffectTime
    op: str
    target: Atom
    value: NumExpr


Effect = AtomEffect | NumEffect


@dataclass(frozen=True)
class Param:
    """A typed parameter or quantified variable."""

    name: str
    type: str


@dataclass(frozen=True)
class Operator:
    """A plan operator: TAL action type with duration, agent, pre/prevail conditions, effects."""

    name: str
    params: tuple[Param, ...]
    pre: tuple[Condition, ...]
    effects: tuple[Effect, ...]
    duration: NumExpr = Num(1.0)
    agent: str | None = None
    prevail: tuple[Condition, ...] = ()
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class Domain:
    """A planning domain (types, features, operators)."""

    name: str
    types: dict[str, str]
    constants: tuple[Param, ...]
    predicates: dict[str, tuple[str, ...]]
    functions: dict[str, tuple[str, ...]]
    operators: tuple[Operator, ...]
    resources: frozenset[str] = frozenset()
    requirements: tuple[str, ...] = ()
    source: str = ""


@dataclass(frozen=True)
class Problem:
    """A problem instance: objects, complete initial state, goal conditions."""

    name: str
    domain: str
    objects: tuple[Param, ...]
    init: tuple[Atom, ...]
    init_values: tuple[tuple[Atom, float], ...]
    goal: tuple[Condition, ...]
    positions: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    source: str = ""


# --- control formulas ----------------------------------------------------------------------


class TimeRef(Enum):
    """State a formula atom is evaluated in."""

    NOW = "t"
    NEXT = "t+1"


@dataclass(frozen=True)
class FAtom:
    """An atom evaluated at a time reference (None outside any ``[..]``: static only)."""

    atom: Atom
    time: TimeRef | None


@dataclass(frozen=True)
class FGoal:
    """``goal(atom)``: the atom is among the goal statements."""

    atom: Atom


@dataclass(frozen=True)
class FEq:
    """Equality of objects (``=`` / ``!=``)."""

    left: Term
    right: Term
    positive: bool = True


@dataclass(frozen=True)
class FConst:
    """``true`` or ``false``."""

    value: bool


@dataclass(frozen=True)
class FNot:
    """Negation."""

    arg: Formula


@dataclass(frozen=True)
class FAnd:
    """Conjunction."""

    args: tuple[Formula, ...]


@dataclass(frozen=True)
class FOr:
    """Disjunction."""

    args: tuple[Formula, ...]


@dataclass(frozen=True)
class FImplies:
    """Implication."""

    left: Formula
    right: Formula


@dataclass(frozen=True)
class FQuant:
    """``forall`` / ``exists`` over typed variables."""

    universal: bool
    variables: tuple[Param, ...]
    body: Formula


@dataclass(frozen=True)
class FCompare:
    """Numeric comparison ``left op right`` of a control formula, evaluated at ``time``.

    Every function term of the comparison is read in the same state (``[t]`` unless marked).
    """

    op: str
    left: NumExpr
    right: NumExpr
    time: TimeRef | None = None
    pos: Pos = field(default=NOWHERE, compare=False)


Formula = FAtom | FGoal | FEq | FCompare | FConst | FNot | FAnd | FOr | FImplies | FQuant


class RuleKind(Enum):
    """Always-rules hold for every pair of consecutive states; final rules in the end state."""

    ALWAYS = "always"
    FINAL = "final"


@dataclass(frozen=True)
class ControlRule:
    """A named TAL control formula, implicitly universally quantified over t."""

    name: str
    kind: RuleKind
    formula: Formula
    pos: Pos = NOWHERE


class MapRelation(Enum):
    """Kinds of relations a control file derives from a static map (``REL(k.., x, y)`` edges)."""

    STEP = "step"  # NAME(k.., x, y, g): edge x->y lies on a shortest path from x to g
    NEARER = "nearer"  # NAME(k.., x, a, b): a is strictly closer to x than b


@dataclass(frozen=True)
class StepDecl:
    """``step|nearer NAME by REL``: a static relation derived from the map ``REL``."""

    kind: MapRelation
    name: str
    relation: str
    pos: Pos = NOWHERE


@dataclass(frozen=True)
class ControlSpec:
    """Contents of a control file: rules, successor preference and agent types."""

    rules: tuple[ControlRule, ...] = ()
    prefer: tuple[str, ...] = ()
    agent_types: tuple[str, ...] = ()
    source: str = ""
    steps: tuple[StepDecl, ...] = ()
