"""The syntax both mission languages share: positions, arguments, linear constraints, headers.

TALF (section 9.4, ``talf_*``) and the TST language (section 6.3.2, ``hdrc3_tst.syntax``) write
the same arguments (names and numbers), the same linear comparisons and finite domains in their
where clauses, and the same header lines (``world``, ``agents``, ``area``, ``point``, ``path``).
They are defined once, here, so that a TALF mission translates into a TST without converting
them (``hdrc3_tst.talf_translation``). Frozen dataclasses; positions never take part in
equality, so a printed and re-parsed tree equals the original.
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
    """A variable or a declared value (agent, area, point, path), told apart by a resolver."""

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
class LinExpr:
    """A linear expression: the sum of its terms."""

    terms: tuple[Term, ...]


class Cmp(enum.Enum):
    """Comparison operators."""

    LE = "<="
    LT = "<"
    GE = ">="
    GT = ">"
    EQ = "="
    NE = "!="


@dataclass(frozen=True)
class Comparison:
    """``left OP right`` over linear expressions (a chain ``a = b = c`` is one per link)."""

    left: LinExpr
    op: Cmp
    right: LinExpr
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class Membership:
    """``VAR in {v1, v2, ...}``: a finite domain."""

    var: Name
    values: tuple[Arg, ...]
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class ConsRef:
    """A bare name in a where clause: a named constraint set (``where cons_tau0``)."""

    name: Name


# --- header declarations --------------------------------------------------------------------


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


Declaration = WorldDecl | AgentsDecl | AreaDecl | PointDecl | PathDecl
"""A header line of either language."""
