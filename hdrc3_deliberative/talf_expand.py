"""Expansion of composite action terms: the body of their type, instantiated (section 9.4).

``[u, u'] comp(a1, ..., an)`` with ``[t, t'] comp(v1, ..., vn) ~> A`` becomes ``A`` with ``t, t'``
replaced by ``u, u'`` and each ``vi`` by ``ai``; the variables ``A`` binds itself (``with`` and
``foreach`` variables) and its labels get fresh names, so two instances never share one. When
the term's C-ACT has a ``with``, a ``where``, an agent or an interval of its own, the instance
becomes the only element of a sequence inside it, which keeps all of these. A Task
Specification Tree calls a library TST with its node interface only, (P, TS, TE); TALF's
composite actions take any parameters, so a mission is expanded before it becomes a TST.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from hdrc3_base.errors import ConfigError
from hdrc3_deliberative.mission_syntax import (
    Arg,
    Comparison,
    LinExpr,
    Membership,
    Name,
    Number,
    Term,
)
from hdrc3_deliberative.talf_formulas import (
    And,
    Atom,
    Exists,
    Forall,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    formula_names,
)
from hdrc3_deliberative.talf_syntax import (
    ActionTerm,
    CAct,
    CompositeSpec,
    Concurrent,
    Foreach,
    If,
    Interval,
    Mission,
    Sequence,
    Task,
    While,
)


class ExpansionError(ConfigError):
    """A composite action term cannot be instantiated (a number where a timepoint is needed)."""


Subst = Mapping[str, Arg]


def _name(name: str, sub: Subst, what: str) -> str:
    value = sub.get(name, Name(name))
    if isinstance(value, Number):
        raise ExpansionError(f"{what} {name!r} is given the number {value.value:g}")
    return value.id


def _arg(arg: Arg, sub: Subst) -> Arg:
    if isinstance(arg, Number):
        return arg
    value = sub.get(arg.id)
    return arg if value is None else (Name(value.id, arg.pos) if isinstance(value, Name) else value)


def _expr(expr: LinExpr, sub: Subst) -> LinExpr:
    terms: list[Term] = []
    for term in expr.terms:
        value = sub.get(term.name.id) if term.name is not None else None
        if isinstance(value, Number):
            terms.append(Term(term.coef * value.value))
        elif isinstance(value, Name) and term.name is not None:
            terms.append(Term(term.coef, Name(value.id, term.name.pos)))
        else:
            terms.append(term)
    return LinExpr(tuple(terms))


def subst_formula(formula: Formula, sub: Subst) -> Formula:
    """Replace free names (quantified names are left alone)."""
    if isinstance(formula, Comparison):
        return Comparison(
            _expr(formula.left, sub), formula.op, _expr(formula.right, sub), formula.pos
        )
    if isinstance(formula, Membership):
        var = _arg(formula.var, sub)
        if isinstance(var, Number):
            raise ExpansionError(f"{formula.var.id} in {{...}} is given a number")
        return Membership(var, tuple(_arg(v, sub) for v in formula.values), formula.pos)
    if isinstance(formula, Atom):
        time = None if formula.time is None else _name(formula.time, sub, "timepoint")
        return Atom(formula.name, tuple(_arg(a, sub) for a in formula.args), time, formula.pos)
    if isinstance(formula, Not):
        return Not(subst_formula(formula.arg, sub))
    if isinstance(formula, And | Or):
        return type(formula)(tuple(subst_formula(a, sub) for a in formula.args))
    if isinstance(formula, Implies | Iff):
        return type(formula)(subst_formula(formula.left, sub), subst_formula(formula.right, sub))
    if isinstance(formula, Exists | Forall):
        inner = {k: v for k, v in sub.items() if k not in formula.vars}
        return type(formula)(formula.vars, subst_formula(formula.body, inner))
    return formula


def _interval(interval: Interval, sub: Subst) -> Interval:
    return Interval(_name(interval.start, sub, "timepoint"), _name(interval.end, sub, "timepoint"))


@dataclass
class _Fresh:
    """Fresh variable names and labels, never one used in the mission."""

    used: set[str]
    count: int = 0

    def name(self, base: str) -> str:
        while True:
            self.count += 1
            candidate = f"{base}_{self.count}"
            if candidate not in self.used:
                self.used.add(candidate)
                return candidate


def _subst_task(task: Task, sub: dict[str, Arg], fresh: _Fresh) -> Task:
    if isinstance(task, ActionTerm):
        interval = None if task.interval is None else _interval(task.interval, sub)
        return ActionTerm(task.name, tuple(_arg(a, sub) for a in task.args), interval, task.pos)
    if isinstance(task, Sequence | Concurrent):
        return type(task)(tuple(_subst(c, sub, fresh) for c in task.children))
    if isinstance(task, If):
        cond = subst_formula(task.cond, sub)
        return If(cond, _subst(task.then, sub, fresh), _subst(task.orelse, sub, fresh))
    if isinstance(task, While):
        return While(subst_formula(task.cond, sub), _subst(task.body, sub, fresh))
    loop = {v: fresh.name(v) for v in task.vars}
    inner = {**sub, **{k: Name(v) for k, v in loop.items()}}
    return Foreach(
        tuple(loop.values()), subst_formula(task.cond, inner), _subst(task.body, inner, fresh)
    )


def _subst(cact: CAct, sub: Mapping[str, Arg], fresh: _Fresh) -> CAct:
    """An instance of ``cact``: ``sub`` applied, its own binders renamed fresh."""
    own = {v: fresh.name(v) for v in cact.with_vars}
    inner: dict[str, Arg] = {**sub, **{k: Name(v) for k, v in own.items()}}
    return CAct(
        _interval(cact.interval, inner),
        _subst_task(cact.task, inner, fresh),
        tuple(own.values()),
        None if cact.where is None else subst_formula(cact.where, inner),
        None if cact.agent is None else _name(cact.agent, inner, "agent"),
        None if cact.label is None else fresh.name(cact.label),
        cact.pos,
    )


def _used(cact: CAct) -> set[str]:
    names: set[str] = set()
    for sub in cact.walk():
        names |= {sub.interval.start, sub.interval.end, *sub.with_vars}
        names |= {n.id for f in (sub.where,) if f is not None for n in formula_names(f)}
        if isinstance(sub.task, ActionTerm):
            names |= {a.id for a in sub.task.args if isinstance(a, Name)}
        if isinstance(sub.task, Foreach):
            names |= set(sub.task.vars)
        if sub.label:
            names.add(sub.label)
    return names


@dataclass
class _Expander:
    specs: Mapping[str, CompositeSpec]
    fresh: _Fresh

    def cact(self, cact: CAct) -> CAct:
        task = cact.task
        if isinstance(task, ActionTerm):
            spec = self.specs.get(task.name)
            if spec is None:
                return cact
            return self.instance(cact, task, spec)
        if isinstance(task, Sequence | Concurrent):
            new: Task = type(task)(tuple(self.cact(c) for c in task.children))
        elif isinstance(task, If):
            new = If(task.cond, self.cact(task.then), self.cact(task.orelse))
        elif isinstance(task, While):
            new = While(task.cond, self.cact(task.body))
        else:
            new = Foreach(task.vars, task.cond, self.cact(task.body))
        return replace(cact, task=new)

    def instance(self, cact: CAct, term: ActionTerm, spec: CompositeSpec) -> CAct:
        interval = term.interval or cact.interval
        sub: dict[str, Arg] = {
            spec.interval.start: Name(interval.start),
            spec.interval.end: Name(interval.end),
        }
        if len(term.args) != len(spec.params):
            raise ExpansionError(f"{term.pos}: {spec.name} takes {len(spec.params)} arguments")
        sub.update(zip(spec.params, term.args, strict=True))
        try:
            instance = _subst(spec.body, sub, self.fresh)
        except ExpansionError as exc:
            raise ExpansionError(f"{term.pos}: {spec.name}: {exc}") from None
        body = self.cact(instance)
        body = replace(body, label=body.label or self.fresh.name(spec.name))
        plain = not cact.with_vars and cact.where is None and cact.agent is None
        if plain and interval == cact.interval:
            return body if cact.label is None else replace(body, label=cact.label)
        return replace(cact, task=Sequence((body,)))


def expand(mission: Mission, specs: Mapping[str, CompositeSpec]) -> Mission:
    """The mission with every composite action term replaced by an instance of its type.

    The file must have passed :func:`~hdrc3_deliberative.talf_check.check` (no unknown or
    recursive composite actions).
    """
    used = _used(mission.body) | {n for s in specs.values() for n in _used(s.body)}
    expander = _Expander(specs, _Fresh(used))
    return Mission(mission.name, expander.cact(mission.body), mission.pos)
