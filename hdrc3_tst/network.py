"""The constraint network of a TST (section 6.3.1): node parameters are its variables.

Time variables and difference constraints go to the :class:`SimpleTemporalNetwork`; everything
else (speeds, altitudes, agents, areas) to the CP-SAT :class:`FiniteModel`. Fixing a parameter
(mixed initiative: a person or an agent sets it before or during execution) updates the STN
incrementally, or re-solves the finite model; an inconsistent value is refused with the
constraints that conflict, and the network stays as it was.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from hdrc3_deliberative.mission_syntax import Cmp
from hdrc3_tst.actions import ParamType
from hdrc3_tst.finite import FiniteModel, LinearConstraint, SolveStatus, SymbolConstraint
from hdrc3_tst.stn import Inconsistent, SimpleTemporalNetwork, Window


class FixStatus(enum.Enum):
    """Outcome of fixing a parameter."""

    OK = "ok"
    INCONSISTENT = "inconsistent"
    UNKNOWN_VARIABLE = "unknown_variable"
    BAD_VALUE = "bad_value"


@dataclass(frozen=True)
class FixResult:
    """Status, a reason, and the conflicting constraints when refused."""

    status: FixStatus
    reason: str = ""
    conflict: tuple[str, ...] = ()


@dataclass
class ConstraintNetwork:
    """Typed variables, their fixed values, the STN and the finite model."""

    types: dict[str, ParamType] = field(default_factory=dict)
    values: dict[str, float | str] = field(default_factory=dict)
    stn: SimpleTemporalNetwork = field(default_factory=SimpleTemporalNetwork)
    finite: FiniteModel = field(default_factory=FiniteModel)

    def copy(self) -> ConstraintNetwork:
        """An independent network (a what-if: a contractor's schedule on top of a mission)."""
        return ConstraintNetwork(
            dict(self.types), dict(self.values), self.stn.copy(), self.finite.copy()
        )

    def declare(self, var: str, kind: ParamType, domain: tuple[str, ...] = ()) -> None:
        """A new variable of type ``kind`` (names: with their possible values)."""
        self.types[var] = kind
        if kind is ParamType.TIME:
            self.stn.add_variable(var)
        elif kind.numeric:
            self.finite.numeric.add(var)
        else:
            self.finite.domains[var] = domain

    def window(self, var: str) -> Window:
        """Earliest/latest of a time variable."""
        return self.stn.window(var)

    def check(self) -> tuple[str, ...]:
        """Propagate everything from scratch; the conflicting constraints, or () if consistent."""
        try:
            self.stn.propagate()
        except Inconsistent as exc:
            return tuple(e.label for e in exc.cycle)
        result = self.finite.solve()
        if result.status is SolveStatus.INCONSISTENT:
            return result.conflict
        return ()

    def fix(self, var: str, value: float | str, label: str = "") -> FixResult:
        """Give ``var`` a value; refused (network unchanged) when it conflicts."""
        kind = self.types.get(var)
        if kind is None:
            return FixResult(FixStatus.UNKNOWN_VARIABLE, f"no parameter variable {var!r}")
        label = label or f"set {var} = {value}"
        if kind.numeric != isinstance(value, float | int):
            want = "a number" if kind.numeric else f"a name of a {kind.value}"
            return FixResult(FixStatus.BAD_VALUE, f"{var} is a {kind.value}: give {want}")
        if kind is ParamType.TIME:
            assert isinstance(value, float | int)
            try:
                self.stn.fix(var, float(value), label)
            except Inconsistent as exc:
                return FixResult(
                    FixStatus.INCONSISTENT,
                    f"{var} = {value} conflicts",
                    tuple(e.label for e in exc.cycle),
                )
            self.values[var] = float(value)
            return FixResult(FixStatus.OK)
        return self._fix_finite(var, kind, value, label)

    def _fix_finite(self, var: str, kind: ParamType, value: float | str, label: str) -> FixResult:
        if kind.numeric:
            assert isinstance(value, float | int)
            self.finite.linear.append(LinearConstraint(((1.0, var),), Cmp.EQ, float(value), label))
            undo = self.finite.linear
        else:
            assert isinstance(value, str)
            if value not in self.finite.domains[var]:
                return FixResult(
                    FixStatus.BAD_VALUE,
                    f"{value!r} is not a {kind.value} "
                    f"(known: {', '.join(self.finite.domains[var])})",
                )
            self.finite.symbolic.append(SymbolConstraint(var, Cmp.EQ, (value,), None, label))
            undo = self.finite.symbolic  # type: ignore[assignment]
        result = self.finite.solve()
        if result.status is not SolveStatus.CONSISTENT:
            undo.pop()
            return FixResult(FixStatus.INCONSISTENT, f"{var} = {value} conflicts", result.conflict)
        self.values[var] = value
        return FixResult(FixStatus.OK)
