"""Non-temporal constraints (speeds, altitudes, agents, areas) through OR-Tools CP-SAT.

Numbers are scaled to integers with a resolution of ``1 / SCALE`` in their unit (a strict
``x < y`` becomes ``x <= y - 1/SCALE``); names (agents, areas, points, paths) are indices into
the declared values of their type. Every constraint is enforced under an assumption literal, so
an infeasible model names a sufficient set of conflicting constraints
(``sufficient_assumptions_for_infeasibility``).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import NamedTuple

from ortools.sat.python import cp_model

from hdrc3_deliberative.mission_syntax import Cmp

SCALE = 1000
LIMIT = 10**6
"""Numeric variables live in [-LIMIT, LIMIT] of their unit."""


class LinearConstraint(NamedTuple):
    """``sum(coef * var) OP constant`` over numeric variables, with its label.

    Named tuples (immutable) rather than frozen dataclasses: a mission makes thousands of
    constraints (every constant and envelope bound), three times faster so.
    """

    terms: tuple[tuple[float, str], ...]
    op: Cmp
    constant: float
    label: str


class SymbolConstraint(NamedTuple):
    """``var = value``, ``var != value``, ``var = other``, ``var in {..}`` over names."""

    var: str
    op: Cmp
    values: tuple[str, ...] = ()
    other: str | None = None
    label: str = ""


class SolveStatus(enum.Enum):
    """Outcome of a consistency check."""

    CONSISTENT = "consistent"
    INCONSISTENT = "inconsistent"
    UNKNOWN = "unknown"
    """The solver's time limit was reached (not seen on the shipped examples)."""


@dataclass(frozen=True)
class SolveResult:
    """Status, a witness assignment, and the conflicting labels when inconsistent."""

    status: SolveStatus
    witness: dict[str, float | str] = field(default_factory=dict)
    conflict: tuple[str, ...] = ()


@dataclass
class FiniteModel:
    """Numeric and symbolic variables with their constraints; solved from scratch each time."""

    numeric: set[str] = field(default_factory=set)
    domains: dict[str, tuple[str, ...]] = field(default_factory=dict)
    """Symbolic variable -> the names it may take."""
    linear: list[LinearConstraint] = field(default_factory=list)
    symbolic: list[SymbolConstraint] = field(default_factory=list)

    def copy(self) -> FiniteModel:
        """An independent model with the same variables and (frozen) constraints."""
        return FiniteModel(
            set(self.numeric), dict(self.domains), list(self.linear), list(self.symbolic)
        )

    def solve(self, time_limit: float = 5.0) -> SolveResult:
        """Check consistency; on failure name the constraints that conflict.

        Constraints over one variable only (bounds from the flight envelope, ``P = uav0``)
        are intersected directly; the variables that share a constraint go to CP-SAT together.
        """
        for sym in self.symbolic:
            for var in (sym.var, sym.other):
                if var is not None and not self.domains[var]:
                    return SolveResult(
                        SolveStatus.INCONSISTENT, {}, (sym.label, f"{var} has no possible value")
                    )
        single: dict[str, list[LinearConstraint | SymbolConstraint]] = {}
        shared = FiniteModel(set(), {}, [], [])
        for lin in self.linear:
            if len(lin.terms) == 1 or len({v for _, v in lin.terms}) == 1:
                single.setdefault(lin.terms[0][1], []).append(lin)
            else:
                shared.linear.append(lin)
        for sym in self.symbolic:
            if sym.other is None:
                single.setdefault(sym.var, []).append(sym)
            else:
                shared.symbolic.append(sym)
        witness: dict[str, float | str] = {}
        for var, constraints in single.items():
            value = _one_variable(constraints, self.domains.get(var))
            if isinstance(value, tuple):
                return SolveResult(SolveStatus.INCONSISTENT, {}, value)
            witness[var] = value
        used = {v for lin in shared.linear for _, v in lin.terms}
        used |= {v for sym in shared.symbolic for v in (sym.var, sym.other) if v is not None}
        if not used:
            return SolveResult(SolveStatus.CONSISTENT, witness)
        shared.numeric = used & self.numeric
        shared.domains = {v: d for v, d in self.domains.items() if v in used}
        shared.linear += [
            c for v in used for c in single.get(v, ()) if isinstance(c, LinearConstraint)
        ]
        shared.symbolic += [
            c for v in used for c in single.get(v, ()) if isinstance(c, SymbolConstraint)
        ]
        result = shared.solve_with_cp_sat(time_limit)
        if result.status is SolveStatus.CONSISTENT:
            witness.update(result.witness)
            return SolveResult(SolveStatus.CONSISTENT, witness)
        return result

    def solve_with_cp_sat(self, time_limit: float = 5.0) -> SolveResult:
        """The whole model through CP-SAT, each constraint under an assumption literal."""
        model = cp_model.CpModel()
        ints = {v: model.new_int_var(-LIMIT * SCALE, LIMIT * SCALE, v) for v in self.numeric}
        syms = {
            v: model.new_int_var(0, max(len(d) - 1, 0), v) for v, d in self.domains.items() if d
        }
        labels: list[str] = []
        literals: list[cp_model.IntVar] = []

        def guard(label: str) -> cp_model.IntVar:
            lit = model.new_bool_var(f"a{len(literals)}")
            literals.append(lit)
            labels.append(label)
            return lit

        for lin in self.linear:
            expr = sum(round(c * SCALE) * ints[v] for c, v in lin.terms)
            rhs = round(lin.constant * SCALE * SCALE)
            lit = guard(lin.label)
            _post(model, expr, lin.op, rhs, SCALE).only_enforce_if(lit)
        for sym in self.symbolic:
            var, dom = syms[sym.var], self.domains[sym.var]
            lit = guard(sym.label)
            if sym.other is not None:
                _post(model, var - syms[sym.other], sym.op, 0, 1).only_enforce_if(lit)
            elif sym.op is Cmp.EQ and len(sym.values) > 1:  # membership
                allowed = [[dom.index(v)] for v in sym.values if v in dom]
                model.add_allowed_assignments([var], allowed).only_enforce_if(lit)
            else:
                index = dom.index(sym.values[0]) if sym.values[0] in dom else -1
                _post(model, var, sym.op, index, 1).only_enforce_if(lit)
        model.add_assumptions(literals)
        solver = cp_model.CpSolver()
        solver.parameters.max_time_in_seconds = time_limit
        solver.parameters.num_workers = 1
        status = solver.solve(model)
        if status in (cp_model.OPTIMAL, cp_model.FEASIBLE):
            witness: dict[str, float | str] = {v: solver.value(x) / SCALE for v, x in ints.items()}
            witness.update({v: self.domains[v][solver.value(x)] for v, x in syms.items()})
            return SolveResult(SolveStatus.CONSISTENT, witness)
        if status == cp_model.INFEASIBLE:
            core = solver.sufficient_assumptions_for_infeasibility()
            by_literal = {lit.index: i for i, lit in enumerate(literals)}
            return SolveResult(
                SolveStatus.INCONSISTENT, {}, tuple(sorted(labels[by_literal[c]] for c in core))
            )
        return SolveResult(SolveStatus.UNKNOWN)


def _one_variable(
    constraints: list[LinearConstraint | SymbolConstraint], domain: tuple[str, ...] | None
) -> float | str | tuple[str, ...]:
    """Intersect the constraints over one variable: bounds for a number, a set for a name.

    Returns:
        A value the variable may take, or the labels of the constraints that leave it none
        (the tightest bound of each side, or every constraint of a name).
    """
    if domain is not None:  # a name (agent, area, point, path); a variable without possible
        allowed = set(domain)  # values stays open while nothing constrains it
        for sym in constraints:
            assert isinstance(sym, SymbolConstraint)
            values = set(sym.values)
            allowed = allowed & values if sym.op is Cmp.EQ else allowed - values
        if not allowed:
            return tuple(sorted(c.label for c in constraints))
        return min(allowed, key=domain.index)
    step = 1.0 / SCALE
    lo, hi = (-float(LIMIT), ""), (float(LIMIT), "")
    excluded: list[tuple[float, str]] = []
    for lin in constraints:
        assert isinstance(lin, LinearConstraint)
        coef = lin.terms[0][0]
        if coef == 0:
            if not _holds(0.0, lin.op, lin.constant):
                return (lin.label,)
            continue
        bound = lin.constant / coef
        op = _FLIP[lin.op] if coef < 0 else lin.op
        if op in (Cmp.LE, Cmp.LT, Cmp.EQ):
            cand = bound - (step if op is Cmp.LT else 0.0)
            hi = min(hi, (cand, lin.label))
        if op in (Cmp.GE, Cmp.GT, Cmp.EQ):
            cand = bound + (step if op is Cmp.GT else 0.0)
            lo = max(lo, (cand, lin.label))
        if op is Cmp.NE:
            excluded.append((bound, lin.label))
    if lo[0] > hi[0] + 1e-12:
        return tuple(sorted(x for x in (lo[1], hi[1]) if x))
    value = lo[0]
    for bad, label in sorted(excluded):
        if abs(value - bad) < 1e-12:
            value += step
            if value > hi[0] + 1e-12:
                return tuple(sorted({lo[1], hi[1], label} - {""}))
    return value


_FLIP = {
    Cmp.LE: Cmp.GE,
    Cmp.LT: Cmp.GT,
    Cmp.GE: Cmp.LE,
    Cmp.GT: Cmp.LT,
    Cmp.EQ: Cmp.EQ,
    Cmp.NE: Cmp.NE,
}


def _holds(left: float, op: Cmp, right: float) -> bool:
    return {
        Cmp.LE: left <= right,
        Cmp.LT: left < right,
        Cmp.GE: left >= right,
        Cmp.GT: left > right,
        Cmp.EQ: left == right,
        Cmp.NE: left != right,
    }[op]


def _post(
    model: cp_model.CpModel, expr: cp_model.LinearExprT, op: Cmp, rhs: int, step: int
) -> cp_model.Constraint:
    """``expr OP rhs`` on integers; strict comparisons move by one resolution step."""
    if op is Cmp.LE:
        return model.add(expr <= rhs)
    if op is Cmp.LT:
        return model.add(expr <= rhs - step)
    if op is Cmp.GE:
        return model.add(expr >= rhs)
    if op is Cmp.GT:
        return model.add(expr >= rhs + step)
    if op is Cmp.EQ:
        return model.add(expr == rhs)
    return model.add(expr != rhs)
