"""Translation between TALF missions and Task Specification Trees, both ways (section 9.4, Fig. 29).

Every C-ACT becomes one TST node: its label is the node name (generated when it has none), its
interval and agent the node interface ``(P, TS, TE)``, its ``with`` variables the node's, its
where clause the node's constraints; sequences, concurrencies, ``if``, ``while`` and
``foreach ... do conc`` become the TST node of the same kind, and an elementary action term
``[u, u'] name(args)`` the action node ``name(u, u', args)``. Composite action terms are
expanded first (:mod:`hdrc3_deliberative.talf_expand`): a TST ``call`` passes only the node
interface. Named constraint sets and the header declarations carry over as they are.

What one side has and the other does not raises :class:`TranslationError` naming it: where
clauses beyond conjunctions of comparisons, memberships and constraint-set names (a fluent, a
disjunction, a quantifier), conditions beyond one possibly negated atom, TST goal nodes and
calls, a concurrency of one node.

This lives in ``hdrc3_tst`` rather than beside the TALF language in ``hdrc3_deliberative``
because it needs the TST syntax tree and the action registry, and ``hdrc3_deliberative`` is the
lower layer (TST goal nodes use TALplanner).
"""

from __future__ import annotations

from dataclasses import dataclass

from hdrc3_deliberative import mission_syntax as ms
from hdrc3_deliberative import talf_formulas as tf
from hdrc3_deliberative import talf_syntax as ts
from hdrc3_deliberative.talf_check import free_names
from hdrc3_deliberative.talf_expand import expand
from hdrc3_tst import syntax as tst
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.errors import TstError


class TranslationError(TstError):
    """A construct of one language has no counterpart in the other; names it and where it is."""

    def __init__(self, construct: str, reason: str, where: str = "") -> None:
        self.construct = construct
        self.reason = reason
        super().__init__(f"{where}: {construct}: {reason}" if where else f"{construct}: {reason}")


# --- TALF -> TST ---------------------------------------------------------------------------


def _constraint_to(part: tf.Formula, where: str) -> tst.Constraint:
    if isinstance(part, ms.Comparison | ms.Membership | ms.ConsRef):
        return part  # the languages share them (mission_syntax)
    raise TranslationError(
        f"where clause part '{tf.formula_text(part)}'",
        "a TST constraint is a comparison of linear expressions, a membership or a constraint "
        "set name (fluents, disjunctions, negations and quantifiers have no TST counterpart)",
        where,
    )


def _constraints_to(formula: tf.Formula | None, where: str) -> tuple[tst.Constraint, ...]:
    return tuple(_constraint_to(p, where) for p in tf.conjuncts(formula))


def _condition_to(formula: tf.Formula, where: str) -> tst.Condition:
    negated = isinstance(formula, tf.Not)
    atom = formula.arg if isinstance(formula, tf.Not) else formula
    if not isinstance(atom, tf.Atom):
        raise TranslationError(
            f"condition '{tf.formula_text(formula)}'",
            "a TST condition is one query [T] not? name(args)",
            where,
        )
    return tst.Condition(atom.name, atom.args, negated, atom.time, atom.pos)


@dataclass
class _ToTst:
    taken: set[str]
    count: int = 0

    def name(self, cact: ts.CAct) -> str:
        if cact.label is not None:
            return cact.label
        task = cact.task
        base = task.name if isinstance(task, ts.ActionTerm) else type(task).__name__.lower()
        while True:
            self.count += 1
            candidate = f"{base}{self.count}"
            if candidate not in self.taken:
                self.taken.add(candidate)
                return candidate

    def node(self, cact: ts.CAct, name: str | None = None) -> tst.TstDef:
        where = str(cact.pos)
        task = cact.task
        new: tst.Task
        if isinstance(task, ts.ActionTerm):
            if task.name not in ACTIONS:
                raise TranslationError(
                    f"composite action term {task.name}", "not expanded (unknown type)", where
                )
            interval = task.interval or cact.interval
            times = (ms.Name(interval.start), ms.Name(interval.end))
            args = (*times, *task.args)
            new = tst.ActionTask(task.name, args, task.pos)
        elif isinstance(task, ts.Sequence):
            new = tst.SequenceTask(tuple(self.node(c) for c in task.children))
        elif isinstance(task, ts.Concurrent):
            new = tst.ConcurrentTask(tuple(self.node(c) for c in task.children))
        elif isinstance(task, ts.If):
            cond = _condition_to(task.cond, where)
            new = tst.IfTask(cond, self.node(task.then), self.node(task.orelse))
        elif isinstance(task, ts.While):
            new = tst.WhileTask(_condition_to(task.cond, where), self.node(task.body))
        else:
            cond = _condition_to(task.cond, where)
            new = tst.ForeachTask(task.vars, cond, self.node(task.body))
        head = (cact.interval.start, cact.interval.end)
        params = head if cact.agent is None else (cact.agent, *head)
        return tst.TstDef(
            name or self.name(cact),
            params,
            cact.with_vars,
            new,
            _constraints_to(cact.where, where),
            cact.pos,
        )


def pick_mission(tree: ts.TalfFile, name: str | None) -> ts.Mission:
    """The mission called ``name`` (the first one when None); TranslationError when missing."""
    missions = tree.missions()
    chosen = missions[0] if missions and name is None else None
    chosen = chosen or next((m for m in missions if m.name == name), None)
    if chosen is None:
        have = ", ".join(m.name for m in missions) or "none"
        raise TranslationError(
            f"mission {name or ''}".strip(), f"not in the file (missions: {have})"
        )
    return chosen


def to_tst(tree: ts.TalfFile, mission: str | None = None) -> tst.TstFile:
    """One mission of a checked TALF file as a TST file (its composite actions expanded)."""
    chosen = expand(pick_mission(tree, mission), tree.specs())
    labels = {c.label for c in chosen.body.walk() if c.label is not None}
    builder = _ToTst(labels | {chosen.name})
    items: list[tst.Item] = []
    for item in tree.items:
        if isinstance(item, ts.Mission) and item.name == chosen.name:
            items.append(builder.node(chosen.body, chosen.name))
        elif isinstance(item, ts.ConstraintDef):
            cons = _constraints_to(item.formula, str(item.pos))
            items.append(tst.ConsDef(item.name, cons, item.pos))
        elif isinstance(
            item, ms.WorldDecl | ms.AgentsDecl | ms.AreaDecl | ms.PointDecl | ms.PathDecl
        ):
            items.append(item)  # the languages share the header lines (mission_syntax)
    return tst.TstFile(tuple(items))


# --- TST -> TALF ---------------------------------------------------------------------------


def _constraint_from(cons: tst.Constraint) -> tf.Formula:
    return cons  # the languages share them (mission_syntax)


def _where_from(cons: tuple[tst.Constraint, ...]) -> tf.Formula | None:
    return None if not cons else tf.conj(*(_constraint_from(c) for c in cons))


def _cond_from(cond: tst.Condition) -> tf.Formula:
    atom = tf.Atom(cond.name, cond.args, cond.time, cond.pos)
    return tf.Not(atom) if cond.negated else atom


class _FromTst:
    def cact(self, node: tst.TstDef, root: bool = False) -> ts.CAct:
        where = str(node.pos)
        if len(node.params) not in (2, 3):
            raise TranslationError(
                f"node {node.name}", "a node interface is (TS, TE) or (P, TS, TE)", where
            )
        agent = node.params[0] if len(node.params) == 3 else None
        interval = ts.Interval(node.params[-2], node.params[-1])
        task = node.task
        new: ts.Task
        if isinstance(task, tst.ActionTask):
            times = task.args[:2]
            if len(times) < 2 or not all(isinstance(a, ms.Name) for a in times):
                raise TranslationError(
                    f"action node {node.name}", "its first two arguments must name times", where
                )
            own = ts.Interval(times[0].id, times[1].id)  # type: ignore[union-attr]
            args = task.args[2:]
            term_interval = None if own == interval else own
            new = ts.ActionTerm(task.name, args, term_interval, task.pos)
        elif isinstance(task, tst.GoalTask):
            raise TranslationError(
                f"goal node {node.name}",
                "TALF has no goal statements (a task planner expands them at execution time)",
                where,
            )
        elif isinstance(task, tst.CallTask):
            raise TranslationError(
                f"call node {node.name}",
                "TALF composite actions are expanded into the TST, never called",
                where,
            )
        elif isinstance(task, tst.SequenceTask):
            new = ts.Sequence(tuple(self.cact(c) for c in task.children))
        elif isinstance(task, tst.ConcurrentTask):
            if len(task.children) < 2:
                raise TranslationError(
                    f"concurrent node {node.name}", "TALF's (A || B) has two or more", where
                )
            new = ts.Concurrent(tuple(self.cact(c) for c in task.children))
        elif isinstance(task, tst.IfTask):
            new = ts.If(_cond_from(task.cond), self.cact(task.then), self.cact(task.orelse))
        elif isinstance(task, tst.WhileTask):
            new = ts.While(_cond_from(task.cond), self.cact(task.body))
        else:
            assert isinstance(task, tst.ForeachTask)
            new = ts.Foreach(task.vars, _cond_from(task.cond), self.cact(task.body))
        return ts.CAct(
            interval,
            new,
            node.with_vars,
            _where_from(node.where),
            agent,
            None if root else node.name,
            node.pos,
        )


def from_tst(tree: tst.TstFile) -> ts.TalfFile:
    """A TST file as TALF: one mission per top-level TST; free names become ``open``."""
    builder = _FromTst()
    items: list[ts.Item] = []
    for item in tree.items:
        pos = item.pos
        if isinstance(item, tst.TstDef):
            items.append(ts.Mission(item.name, builder.cact(item, root=True), pos))
        elif isinstance(item, tst.ConsDef):
            formula = tf.conj(*(_constraint_from(c) for c in item.constraints))
            items.append(ts.ConstraintDef(item.name, formula, pos))
        else:
            items.append(item)  # the languages share the header lines (mission_syntax)
    talf = ts.TalfFile(tuple(items))
    free = free_names(talf, ACTIONS)
    if not free:
        return talf
    first = next((i for i, it in enumerate(items) if isinstance(it, ts.Mission)), len(items))
    items.insert(first, ts.OpenDecl(free))
    return ts.TalfFile(tuple(items))
