"""Syntax tree of the TST language (chapter section 6.3.2, Figure 16): frozen dataclasses.

Positions never take part in equality, so a printed and re-parsed tree equals the original.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field


@dataclass(frozen=True)
class SourcePos:
    """Where a construct starts (1-based line and column; 0 when not from a file)."""

    file: str = "<string>"
    line: int = 0
    column: int = 0

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


NOWHERE = SourcePos()


# --- arguments and constraints ------------------------------------------------------------


@dataclass(frozen=True)
class Name:
    """A variable or a declared value (area, point, agent), told apart by the resolver."""

    id: str
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class Number:
    """A numeric literal (SI units of the parameter it is given to)."""

    value: float
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


Arg = Name | Number


@dataclass(frozen=True)
class Term:
    """``coef * name``, or the constant ``coef`` when ``name`` is None."""

    coef: float
    name: Name | None = None


@dataclass(frozen=True)
class Expr:
    """A linear expression: the sum of its terms."""

    terms: tuple[Term, ...]


class Cmp(enum.Enum):
    """Comparison operators of constraints."""

    LE = "<="
    LT = "<"
    GE = ">="
    GT = ">"
    EQ = "="
    NE = "!="


@dataclass(frozen=True)
class Comparison:
    """``left OP right`` over linear expressions."""

    left: Expr
    op: Cmp
    right: Expr
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class Membership:
    """``VAR in {v1, v2, ...}``: a finite domain."""

    var: Name
    values: tuple[Arg, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class ConsRef:
    """A reference to a named constraint set (``where cons_tau0``, Example 6.2)."""

    name: Name


Constraint = Comparison | Membership | ConsRef


@dataclass(frozen=True)
class Condition:
    """``[T] not? name(args)``: a query answered by an agent when the node executes."""

    name: str
    args: tuple[Arg, ...]
    negated: bool = False
    time: str | None = None
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


# --- tasks ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class ActionTask:
    """An elementary action call ``name(args)``; the name is a type of the action registry."""

    name: str
    args: tuple[Arg, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class GoalTask:
    """``goal name(args)``: a goal statement expanded by a task planner at execution time."""

    name: str
    args: tuple[Arg, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class CallTask:
    """``call NAME(args)``: an instance of another TST of the file."""

    name: str
    args: tuple[Arg, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class SequenceTask:
    """``sequence TSTS``: the children one after the other."""

    children: tuple[TstDef, ...]


@dataclass(frozen=True)
class ConcurrentTask:
    """``concurrent TSTS``: the children at the same time."""

    children: tuple[TstDef, ...]


@dataclass(frozen=True)
class IfTask:
    """``if [T] COND then TST else TST``."""

    cond: Condition
    then: TstDef
    orelse: TstDef


@dataclass(frozen=True)
class WhileTask:
    """``while [T] COND TST``."""

    cond: Condition
    body: TstDef


@dataclass(frozen=True)
class ForeachTask:
    """``foreach VARS where [T] COND do conc TST``: one concurrent body per answer."""

    vars: tuple[str, ...]
    cond: Condition
    body: TstDef


Elementary = ActionTask | GoalTask | CallTask
Composite = SequenceTask | ConcurrentTask | IfTask | WhileTask | ForeachTask
Task = Elementary | Composite


@dataclass(frozen=True)
class TstDef:
    """``NAME(VARS) = with VARS TASK where CONS``: one named, parameterised node."""

    name: str
    params: tuple[str, ...]
    with_vars: tuple[str, ...]
    task: Task
    where: tuple[Constraint, ...] = ()
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)

    def children(self) -> tuple[TstDef, ...]:
        """The child TSTs written inside this one, in order."""
        task = self.task
        if isinstance(task, SequenceTask | ConcurrentTask):
            return task.children
        if isinstance(task, IfTask):
            return (task.then, task.orelse)
        if isinstance(task, WhileTask | ForeachTask):
            return (task.body,)
        return ()


# --- declarations ---------------------------------------------------------------------------


@dataclass(frozen=True)
class WorldDecl:
    """``world NAME``: places are resolved against this world (``sim/worlds``)."""

    name: str
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class AgentsDecl:
    """``agents a, b``: the agents nodes may be assigned to."""

    names: tuple[str, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class AreaDecl:
    """``area NAME = polygon((e, n), ...)`` in the world's local ENU metres."""

    name: str
    vertices: tuple[tuple[float, float], ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class PointDecl:
    """``point NAME = (e, n, u)`` or ``point NAME = PLACE at U`` (a place of the world)."""

    name: str
    xyz: tuple[float, float, float] | None = None
    place: str | None = None
    altitude: float = 0.0
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class PathDecl:
    """``path NAME = (P1, P2, ...)``: a polyline through declared points."""

    name: str
    points: tuple[str, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class ConsDef:
    """``NAME = CONS``: a named constraint set, referenced from where clauses."""

    name: str
    constraints: tuple[Constraint, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


Item = WorldDecl | AgentsDecl | AreaDecl | PointDecl | PathDecl | ConsDef | TstDef


@dataclass(frozen=True)
class TstFile:
    """A whole ``.tst`` file: its items in the order written."""

    items: tuple[Item, ...]

    def tsts(self) -> tuple[TstDef, ...]:
        """The top-level TST definitions (the first one is the mission)."""
        return tuple(i for i in self.items if isinstance(i, TstDef))
