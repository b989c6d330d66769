"""Type hierarchy and name checks: undefined predicates, types, objects and functions.

Every reference in a domain and problem is checked before grounding, so errors name the
offending identifier and carry the position of the statement that uses it.
"""

from __future__ import annotations

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import (
    ROOT_TYPE,
    Atom,
    AtomEffect,
    BinOp,
    Condition,
    Domain,
    Equality,
    FuncTerm,
    Literal,
    NumExpr,
    Pos,
    Problem,
    Term,
)

FLIGHT_FUNCTIONS = ("flight-time", "flight-cost")
_EITHER = "(either "


def union_type(members: tuple[str, ...]) -> str:
    """Canonical name of the PDDL type ``(either a b ...)`` (members sorted, deduplicated)."""
    return _EITHER + " ".join(sorted(set(members))) + ")"


def union_members(tname: str) -> tuple[str, ...] | None:
    """The member types of a union type name, None for a plain type."""
    if not tname.startswith(_EITHER):
        return None
    return tuple(tname[len(_EITHER) : -1].split())


def _used_types(domain: Domain, problem: Problem) -> set[str]:
    """Every type name the domain and problem mention."""
    used = {p.type for p in (*domain.constants, *problem.objects)}
    for table in (domain.predicates, domain.functions):
        for arg_types in table.values():
            used.update(arg_types)
    for op in domain.operators:
        used.update(p.type for p in op.params)
    return used


def _fail(message: str, pos: Pos) -> PlanningInputError:
    return PlanningInputError(message, pos.source, pos.line, pos.column)


class TypeTable:
    """Type hierarchy and typed object lists with undefined-name checks."""

    def __init__(self, domain: Domain, problem: Problem) -> None:
        self.parent = dict(domain.types)
        self.parent.pop(ROOT_TYPE, None)
        for tname, parent in sorted(self.parent.items()):
            self.check_type(parent, Pos(domain.source), f"the parent of type '{tname}'")
        self.obj_type: dict[str, str] = {}
        for param in (*domain.constants, *problem.objects):
            self.check_type(param.type, Pos(problem.source), f"object '{param.name}'")
            self.obj_type[param.name] = param.type
        self.ancestors: dict[str, frozenset[str]] = {t: self._up(t) for t in self.parent}
        self.ancestors[ROOT_TYPE] = frozenset({ROOT_TYPE})
        by_type: dict[str, list[str]] = {t: [] for t in self.ancestors}
        for obj in sorted(self.obj_type):
            tname = self.obj_type[obj]
            for anc in self.ancestors.get(tname, frozenset({tname, ROOT_TYPE})):
                by_type.setdefault(anc, []).append(obj)
        for tname in sorted(_used_types(domain, problem)):
            members = union_members(tname)
            if members is not None:
                found = {o for m in members for o in by_type.get(m, ())}
                by_type[tname] = sorted(found)
        self.objects = {t: tuple(objs) for t, objs in by_type.items()}

    def _up(self, tname: str) -> frozenset[str]:
        seen = {tname, ROOT_TYPE}
        while tname in self.parent and self.parent[tname] not in seen:
            tname = self.parent[tname]
            seen.add(tname)
        return frozenset(seen)

    def check_type(self, tname: str, pos: Pos, what: str) -> None:
        """Raise if ``tname`` (or a member of an ``either`` type) is not declared."""
        members = union_members(tname)
        if members is not None:
            for member in members:
                self.check_type(member, pos, what)
            return
        if tname != ROOT_TYPE and tname not in self.parent:
            raise PlanningInputError(
                f"undefined type '{tname}' of {what}", pos.source, pos.line, pos.column
            )


class NameChecker:
    """Checks that a domain and problem only use declared names, with matching arities."""

    def __init__(self, domain: Domain, problem: Problem, types: TypeTable) -> None:
        self.domain = domain
        self.problem = problem
        self.types = types

    def _check_atom(
        self, atom: Atom, scope: dict[str, str], table: dict[str, tuple[str, ...]], kind: str
    ) -> None:
        if atom.pred not in table:
            raise _fail(f"undefined {kind} '{atom.pred}'", atom.pos)
        expected = table[atom.pred]
        if len(expected) != len(atom.args):
            raise _fail(
                f"{kind} '{atom.pred}' takes {len(expected)} arguments, got {len(atom.args)}",
                atom.pos,
            )
        for term in atom.args:
            self._check_term(term, scope, atom.pos)

    def _check_term(self, term: Term, scope: dict[str, str], pos: Pos) -> None:
        if term.name not in scope and term.name not in self.types.obj_type:
            raise _fail(f"undefined object or variable '{term.name}'", pos)

    def _check_num(self, expr: NumExpr, scope: dict[str, str], pos: Pos) -> None:
        if isinstance(expr, BinOp):
            self._check_num(expr.left, scope, pos)
            self._check_num(expr.right, scope, pos)
        elif isinstance(expr, FuncTerm):
            if expr.atom.pred in FLIGHT_FUNCTIONS:
                if len(expr.atom.args) != 3:
                    raise _fail(f"'{expr.atom.pred}' takes (agent, from, to)", expr.atom.pos)
                for term in expr.atom.args:
                    self._check_term(term, scope, expr.atom.pos)
            else:
                self._check_atom(expr.atom, scope, self.domain.functions, "function")

    def _check_conditions(
        self, conds: tuple[Condition, ...], scope: dict[str, str], pos: Pos
    ) -> None:
        for cond in conds:
            if isinstance(cond, Literal):
                self._check_atom(cond.atom, scope, self.domain.predicates, "predicate")
            elif isinstance(cond, Equality):
                self._check_term(cond.left, scope, pos)
                self._check_term(cond.right, scope, pos)
            else:
                self._check_num(cond.left, scope, pos)
                self._check_num(cond.right, scope, pos)

    def check(self) -> None:
        """Raise PlanningInputError for the first undefined or misused name."""
        for pname, ptypes in {**self.domain.predicates, **self.domain.functions}.items():
            for tname in ptypes:
                self.types.check_type(tname, Pos(self.domain.source), f"'{pname}'")
        for op in self.domain.operators:
            scope = {p.name: p.type for p in op.params}
            for p in op.params:
                self.types.check_type(p.type, op.pos, f"parameter '{p.name}' of '{op.name}'")
            if op.agent is not None and op.agent not in scope:
                raise _fail(f"agent '{op.agent}' of '{op.name}' is not a parameter", op.pos)
            self._check_conditions(op.pre + op.prevail, scope, op.pos)
            self._check_num(op.duration, scope, op.pos)
            for eff in op.effects:
                if isinstance(eff, AtomEffect):
                    self._check_atom(eff.literal.atom, scope, self.domain.predicates, "predicate")
                else:
                    self._check_atom(eff.target, scope, self.domain.functions, "function")
                    self._check_num(eff.value, scope, op.pos)
        for atom in self.problem.init:
            self._check_atom(atom, {}, self.domain.predicates, "predicate")
        for atom, _ in self.problem.init_values:
            self._check_atom(atom, {}, self.domain.functions, "function")
        self._check_conditions(self.problem.goal, {}, Pos(self.problem.source))

    # --- numeric expressions ---------------------------------------------------------------
