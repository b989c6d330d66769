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

from ortools.sat.python import cp_model

from hdrc3_tst.syntax import Cmp

SCALE = 1000
LIMIT = 10**6
"""Numeric variables live in [-LIMIT, LIMIT] of their unit."""


@dataclass(frozen=True)
class LinearConstraint:
    """``sum(coef * var) OP constant`` over numeric variables, with its label."""

    terms: tuple[tuple[float, str], ...]
    op: Cmp
    constant: float
    label: str


@dataclass(frozen=True)
class SymbolConstraint:
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

    def solve(self, time_limit: float = 5.0) -> SolveResult:
        """Check consistency; on failure name the constraints that conflict."""
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

        # A name variable without possible values (no agents declared yet) stays open as long
        # as nothing constrains it.
        for sym in self.symbolic:
            for var in (sym.var, sym.other):
                if var is not None and not self.domains[var]:
                    reason = f"{var} has no possible value"
                    return SolveResult(SolveStatus.INCONSISTENT, {}, (sym.label, reason))
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
            index = {lit.index: i for i, lit in enumerate(literals)}
            return SolveResult(
                SolveStatus.INCONSISTENT, {}, tuple(sorted(labels[index[c]] for c in core))
            )
        return SolveResult(SolveStatus.UNKNOWN)


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
