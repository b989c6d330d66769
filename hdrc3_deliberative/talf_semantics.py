"""Formal semantics of TALF: a composite action as a theory in L(FL_FP) (section 9.4).

The translation Trans of a C-ACT over its interval ``[t, t']`` (Doherty et al., 2012, in the
form used here; every sub-action ``Ci`` has its own interval ``[si, ei]``):

* ``[t, t'] with X do TASK where PHI``: ``exists X (t <= t' and Task(t, t') and PHI)``.
* elementary or composite action term ``[u, u'] a(args)``: ``t <= u and u' <= t' and
  Occurs(u, u', a(args))`` (just ``Occurs(t, t', a(args))`` over the C-ACT's own interval); an
  elementary action's agent (the nearest ``by``) is its first argument, as in ``fly-to(av, x, y)``.
* ``(C1; ...; Cn)``: ``t <= s1 and e1 <= s2 and ... and en <= t'`` and every ``Trans(Ci)``: in
  order, gaps allowed, no overlap.
* ``(C1 || ... || Cn)``: ``t <= si and ei <= t'`` and ``Trans(Ci)`` for each ``i``.
* ``if [tc] PSI then A else B``: ``t <= tc and tc <= t' and (PSI -> In(A)) and
  (not PSI -> In(B))`` where ``In(C)`` is ``C``'s containment in ``[t, t']`` and ``Trans(C)``.
* ``while [tc] PSI do A``: unbounded iteration is not first-order; it is the least fixpoint
  ``(lfp W(tc, e). ((not PSI and tc <= e) or (PSI and exists sA, eA (tc <= sA and Trans(A)
  and W(eA, e)))))(t, t')``: each test at ``tc``; while PSI holds, one execution of ``A``
  starts no earlier than the test and the next test is at its end; the loop ends at a test
  where PSI fails, within ``[t, t']``.
* ``foreach X where [tc] PSI do conc A``: ``t <= tc and tc <= t' and forall X (PSI -> In(A))``.

A composite action type ``[t, t'] comp(V) ~> A`` is the definition ``forall t, t', V
(Occurs(t, t', comp(V)) <-> Trans(A))``; a named constraint set is replaced by its formula. A
mission's theory is the definitions of the types it uses (directly or not) and the translation
of its C-ACT, whose interval (and agent) are its free variables.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from hdrc3_deliberative.mission_syntax import ConsRef, Name
from hdrc3_deliberative.talf_formulas import (
    And,
    Atom,
    Exists,
    Forall,
    Formula,
    Iff,
    Implies,
    Lfp,
    Not,
    Occurs,
    Or,
    PredApp,
    conj,
    formula_text,
    negate,
    time_le,
)
from hdrc3_deliberative.talf_syntax import (
    ActionTerm,
    CAct,
    CompositeSpec,
    Concurrent,
    ConstraintDef,
    Foreach,
    If,
    Mission,
    Sequence,
    TalfFile,
    While,
)


@dataclass(frozen=True)
class Statement:
    """One axiom of a narrative, with what it is (``definition monitor-single``, ``mission m``)."""

    what: str
    formula: Formula


@dataclass(frozen=True)
class Narrative:
    """A TAL narrative: the theory a mission stands for."""

    statements: tuple[Statement, ...]

    def text(self) -> str:
        """One statement per paragraph: ``what:`` then the formula."""
        return "\n\n".join(
            f"{s.what}:\n  {formula_text(s.formula, hoist=False)}" for s in self.statements
        )


def _inline(formula: Formula | None, cons: Mapping[str, ConstraintDef]) -> Formula | None:
    """Replace references to named constraint sets by their formulas."""
    if formula is None:
        return None
    if isinstance(formula, ConsRef) and formula.name.id in cons:
        return _inline(cons[formula.name.id].formula, cons)
    if isinstance(formula, And):
        return conj(*(_inline(a, cons) for a in formula.args))
    return formula


@dataclass
class _Translator:
    cons: Mapping[str, ConstraintDef]
    composite: frozenset[str]
    """Names of composite action types (their terms take no agent argument)."""
    loops: int = 0

    def cact(self, cact: CAct, agent: str | None) -> Formula:
        """Trans(C) over C's own interval."""
        agent = cact.agent if cact.agent is not None else agent
        start, end = cact.interval.start, cact.interval.end
        body = conj(time_le(start, end), self.task(cact, agent), _inline(cact.where, self.cons))
        return Exists(cact.with_vars, body) if cact.with_vars else body

    def inside(self, child: CAct, start: str, end: str, agent: str | None) -> Formula:
        """In(C): C within ``[start, end]`` and Trans(C)."""
        return conj(
            time_le(start, child.interval.start),
            time_le(child.interval.end, end),
            self.cact(child, agent),
        )

    def task(self, cact: CAct, agent: str | None) -> Formula:
        start, end = cact.interval.start, cact.interval.end
        task = cact.task
        if isinstance(task, ActionTerm):
            return self.term(task, start, end, agent)
        if isinstance(task, Sequence):
            points = [start]
            for child in task.children:
                points += [child.interval.start, child.interval.end]
            points.append(end)
            order = [time_le(a, b) for a, b in zip(points[0::2], points[1::2], strict=True)]
            return conj(*order, *(self.cact(c, agent) for c in task.children))
        if isinstance(task, Concurrent):
            return conj(*(self.inside(c, start, end, agent) for c in task.children))
        if isinstance(task, If):
            time = _time(task.cond) or start
            return conj(
                time_le(start, time),
                time_le(time, end),
                Implies(task.cond, self.inside(task.then, start, end, agent)),
                Implies(negate(task.cond), self.inside(task.orelse, start, end, agent)),
            )
        if isinstance(task, While):
            return self.loop(task, start, end, agent)
        assert isinstance(task, Foreach)
        time = _time(task.cond) or start
        each = Forall(task.vars, Implies(task.cond, self.inside(task.body, start, end, agent)))
        return conj(time_le(start, time), time_le(time, end), each)

    def term(self, term: ActionTerm, start: str, end: str, agent: str | None) -> Formula:
        args = term.args
        if agent is not None and term.name not in self.composite:
            args = (Name(agent), *args)
        own = term.interval
        if own is None or (own.start, own.end) == (start, end):
            return Occurs(start, end, term.name, args)
        return conj(
            time_le(start, own.start),
            time_le(own.end, end),
            Occurs(own.start, own.end, term.name, args),
        )

    def loop(self, task: While, start: str, end: str, agent: str | None) -> Formula:
        self.loops += 1
        pred, test, stop = f"W{self.loops}", _time(task.cond) or f"tc{self.loops}", f"e{self.loops}"
        body = task.body
        step_vars = tuple(v for v in (body.interval.start, body.interval.end) if v != test)
        step = conj(
            time_le(test, body.interval.start),
            self.cact(body, agent),
            PredApp(pred, (body.interval.end, stop)),
        )
        fixpoint_body = Or(
            (
                conj(negate(task.cond), time_le(test, stop)),
                conj(task.cond, Exists(step_vars, step) if step_vars else step),
            )
        )
        return Lfp(pred, (test, stop), fixpoint_body, (start, end))


def _time(cond: Formula) -> str | None:
    """The timepoint of a condition ``[t] psi`` (of its first timed atom)."""
    if isinstance(cond, Atom):
        return cond.time
    if isinstance(cond, Not):
        return _time(cond.arg)
    if isinstance(cond, And | Or):
        return next((t for t in map(_time, cond.args) if t is not None), None)
    if isinstance(cond, Exists | Forall):
        return _time(cond.body)
    if isinstance(cond, Implies | Iff):
        return _time(cond.left) or _time(cond.right)
    return None


def translate(cact: CAct, tree: TalfFile | None = None) -> Formula:
    """Trans(C) of one composite action (named constraint sets and types from ``tree``)."""
    if tree is None:
        return _Translator({}, frozenset()).cact(cact, None)
    return _Translator(tree.constraints(), frozenset(tree.specs())).cact(cact, None)


def definition(spec: CompositeSpec, tree: TalfFile) -> Formula:
    """``forall t, t', V (Occurs(t, t', comp(V)) <-> Trans(A))``."""
    head = Occurs(
        spec.interval.start, spec.interval.end, spec.name, tuple(Name(p) for p in spec.params)
    )
    variables = (spec.interval.start, spec.interval.end, *spec.params)
    return Forall(variables, Iff(head, translate(spec.body, tree)))


def _used_specs(cact: CAct, specs: Mapping[str, CompositeSpec], out: list[str]) -> None:
    for sub in cact.walk():
        if isinstance(sub.task, ActionTerm) and sub.task.name in specs:
            name = sub.task.name
            if name not in out:
                out.append(name)
                _used_specs(specs[name].body, specs, out)


def narrative(tree: TalfFile, mission: Mission) -> Narrative:
    """The theory of a mission: the definitions of the types it uses, then its translation."""
    specs = tree.specs()
    used: list[str] = []
    _used_specs(mission.body, specs, used)
    statements = [Statement(f"definition {n}", definition(specs[n], tree)) for n in used]
    statements.append(Statement(f"mission {mission.name}", translate(mission.body, tree)))
    return Narrative(tuple(statements))
