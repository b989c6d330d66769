"""Syntax tree of the TST language (chapter section 6.3.2, Figure 16): frozen dataclasses.

Positions never take part in equality, so a printed and re-parsed tree equals the original.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdrc3_deliberative.mission_syntax import (
    NOWHERE,
    AgentsDecl,
    AreaDecl,
    Arg,
    Comparison,
    ConsRef,
    Membership,
    PathDecl,
    PointDecl,
    SourcePos,
    WorldDecl,
)

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


# --- declarations (the header lines are mission_syntax's) ------------------------------


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
