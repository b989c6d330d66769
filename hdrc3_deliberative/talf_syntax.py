"""Syntax tree of TALF, the mission specification language of section 9.4: frozen dataclasses.

A composite action (C-ACT) is ``[t, t'] with VARS do TASK where PHI``; its TASK is a timed
elementary or composite action term, a sequence ``(A; B)``, a concurrency ``(A || B)``, an
``if``, a ``while`` or a ``foreach ... do conc``. Named composite actions are declared by type
specifications ``[t, t'] comp(v) ~> A``. Formulas (where clauses and conditions) are in
:mod:`hdrc3_deliberative.talf_formulas`.

Two additions to the chapter's grammar carry what a Task Specification Tree node has and a
C-ACT does not: an optional *label* (``tau1: [TS1, TE1] ...``, the TST node name) and an
optional *agent* (``[t, t'] by av ...``, the TST node's P). Labels and positions never take part
in equality: a TALF tree translated to a TST with generated node names and back equals the
original.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdrc3_deliberative.mission_syntax import (
    NOWHERE,
    AgentsDecl,
    AreaDecl,
    Arg,
    Declaration,
    PathDecl,
    PointDecl,
    SourcePos,
)
from hdrc3_deliberative.talf_formulas import Formula


@dataclass(frozen=True)
class Interval:
    """``[start, end]``: the two timepoint variables of an execution interval."""

    start: str
    end: str


@dataclass(frozen=True)
class ActionTerm:
    """``name(args)``: an elementary action (a type of the action registry) or a composite one.

    ``interval`` is the term's own ``[u, u']``; None when written without one, i.e. over the
    enclosing C-ACT's interval (``[t1, t2] fly-to(...)``).
    """

    name: str
    args: tuple[Arg, ...]
    interval: Interval | None = None
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class Sequence:
    """``(A; B; ...)``: in order, without overlap, gaps allowed."""

    children: tuple[CAct, ...]


@dataclass(frozen=True)
class Concurrent:
    """``(A || B || ...)``: each somewhere within the enclosing interval."""

    children: tuple[CAct, ...]


@dataclass(frozen=True)
class If:
    """``if [t] PSI then A else B``."""

    cond: Formula
    then: CAct
    orelse: CAct


@dataclass(frozen=True)
class While:
    """``while [t] PSI do A``: unbounded, given meaning by a least fixpoint."""

    cond: Formula
    body: CAct


@dataclass(frozen=True)
class Foreach:
    """``foreach VARS where [t] PSI do conc A``: one concurrent A per binding of VARS."""

    vars: tuple[str, ...]
    cond: Formula
    body: CAct


Task = ActionTerm | Sequence | Concurrent | If | While | Foreach


@dataclass(frozen=True)
class CAct:
    """``label: [t, t'] by agent with VARS do TASK where PHI`` (label and agent optional)."""

    interval: Interval
    task: Task
    with_vars: tuple[str, ...] = ()
    where: Formula | None = None
    agent: str | None = None
    label: str | None = field(default=None, compare=False)
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)

    def children(self) -> tuple[CAct, ...]:
        """The composite sub-actions written inside this one, in order."""
        task = self.task
        if isinstance(task, Sequence | Concurrent):
            return task.children
        if isinstance(task, If):
            return (task.then, task.orelse)
        if isinstance(task, While | Foreach):
            return (task.body,)
        return ()

    def walk(self) -> tuple[CAct, ...]:
        """Every C-ACT from this one down, depth first."""
        return (self, *(sub for child in self.children() for sub in child.walk()))


@dataclass(frozen=True)
class CompositeSpec:
    """``[t, t'] name(params) ~> body``: a named composite action type (a library entry)."""

    interval: Interval
    name: str
    params: tuple[str, ...]
    body: CAct
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class Mission:
    """``mission NAME: C-ACT``: a composite action to execute (a TST's root)."""

    name: str
    body: CAct
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


# --- header declarations (the same lines as a .tst file's) ------------------------------------


@dataclass(frozen=True)
class OpenDecl:
    """``open X, Y``: mission parameters left open (a TST's free numeric argument names)."""

    names: tuple[str, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class ConstraintDef:
    """``constraint NAME = PHI``: a named constraint set, referenced by NAME in where clauses."""

    name: str
    formula: Formula
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


Item = Declaration | OpenDecl | ConstraintDef | CompositeSpec | Mission


@dataclass(frozen=True)
class TalfFile:
    """A whole ``.talf`` file: its items in the order written."""

    items: tuple[Item, ...]

    def missions(self) -> tuple[Mission, ...]:
        """The missions, in order."""
        return tuple(i for i in self.items if isinstance(i, Mission))

    def specs(self) -> dict[str, CompositeSpec]:
        """The composite action types by name."""
        return {i.name: i for i in self.items if isinstance(i, CompositeSpec)}

    def agents(self) -> tuple[str, ...]:
        """The declared agents, in order."""
        return tuple(n for i in self.items if isinstance(i, AgentsDecl) for n in i.names)

    def places(self) -> dict[str, str]:
        """Declared areas, points and paths: name -> kind (``area``, ``point``, ``path``)."""
        out: dict[str, str] = {}
        for item in self.items:
            if isinstance(item, AreaDecl | PointDecl | PathDecl):
                out[item.name] = type(item).__name__.removesuffix("Decl").lower()
        return out

    def open_names(self) -> tuple[str, ...]:
        """The mission parameters declared open."""
        return tuple(n for i in self.items if isinstance(i, OpenDecl) for n in i.names)

    def constraints(self) -> dict[str, ConstraintDef]:
        """Named constraint sets."""
        return {i.name: i for i in self.items if isinstance(i, ConstraintDef)}
