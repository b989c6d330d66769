"""Matching operator preconditions against reachable facts (the joins of grounding).

An operator's positive preconditions are joined like a conjunctive query: a *join plan* fixes,
once per operator and seed position, the order in which the atoms are matched (the seed first,
then always the atom with most arguments already bound) and, per argument, whether it checks
a bound parameter or binds a new one. Matching then runs nested loops over fact lists chosen
from an index by the most selective bound argument, with parameter values in a flat list.
Written for hdrc3 because the planner needs semi-naive, deadline-interruptible matching over
its own fact index; a generic Datalog engine would add a dependency for one loop nest.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from hdrc3_deliberative.model import Atom, Literal, Operator

Args = tuple[str, ...]


class FactIndex:
    """Reachable facts by predicate and by (predicate, position, value)."""

    def __init__(self) -> None:
        self.by_pred: dict[str, list[Args]] = {}
        self.by_arg: dict[tuple[str, int, str], list[Args]] = {}

    def add(self, pred: str, args: Args) -> None:
        """Record a new fact (callers ensure it is new)."""
        self.by_pred.setdefault(pred, []).append(args)
        for i, value in enumerate(args):
            self.by_arg.setdefault((pred, i, value), []).append(args)


@dataclass(frozen=True)
class _Step:
    """One atom of a join plan."""

    pred: str
    lookups: tuple[tuple[int, int, str], ...]  # (position, slot or -1, constant) of bound args
    tests: tuple[tuple[int, int, str], ...]  # bound args the candidate must agree with
    binds: tuple[tuple[int, int], ...]  # (position, slot) of parameters bound here
    repeats: tuple[tuple[int, int], ...]  # (position, slot): a parameter bound twice here


@dataclass(frozen=True)
class JoinPlan:
    """Join order for one operator; ``free`` are parameters no positive atom binds."""

    steps: tuple[_Step, ...]
    free: tuple[int, ...]


def join_plan(op: Operator, seed: Atom | None) -> JoinPlan:
    """The join plan of ``op``'s positive preconditions, ``seed`` (if any) matched first."""
    slot_of = {p.name: i for i, p in enumerate(op.params)}
    remaining = [c.atom for c in op.pre if isinstance(c, Literal) and c.positive]
    bound: set[int] = set()
    steps: list[_Step] = []
    while remaining:
        if seed is not None and not steps:
            best = seed
        else:
            best = max(
                remaining,
                key=lambda a: sum(
                    1 for t in a.args if t.name not in slot_of or slot_of[t.name] in bound
                ),
            )
        remaining.remove(best)
        lookups: list[tuple[int, int, str]] = []
        binds: list[tuple[int, int]] = []
        repeats: list[tuple[int, int]] = []
        new: set[int] = set()
        for pos, term in enumerate(best.args):
            slot = slot_of.get(term.name, -1)
            if slot < 0 or slot in bound:
                lookups.append((pos, slot, term.name))
            elif slot in new:
                repeats.append((pos, slot))
            else:
                binds.append((pos, slot))
                new.add(slot)
        bound |= new
        steps.append(_Step(best.pred, tuple(lookups), tuple(lookups), tuple(binds), tuple(repeats)))
    free = tuple(i for i in range(len(op.params)) if i not in bound)
    return JoinPlan(tuple(steps), free)


def match(
    plan: JoinPlan,
    facts: FactIndex,
    members: Sequence[frozenset[str]],
    objects: Sequence[Sequence[str]],
    tick: Callable[[], None],
    seed_facts: list[Args] | None = None,
) -> list[Args]:
    """Parameter tuples whose positive preconditions all are in ``facts``.

    ``members[i]``/``objects[i]`` are the objects of parameter ``i``'s type (as a set for
    tests, as a sequence for free parameters); with ``seed_facts`` the first step matches
    only those facts (semi-naive evaluation). ``tick`` is called once per candidate list.
    """
    n = len(members)
    values = [""] * n
    out: list[Args] = []
    steps = plan.steps
    depth = len(steps)
    by_arg = facts.by_arg
    by_pred = facts.by_pred

    def free(k: int) -> None:
        if k == len(plan.free):
            out.append(tuple(values))
            return
        slot = plan.free[k]
        for obj in objects[slot]:
            values[slot] = obj
            free(k + 1)

    def step(k: int) -> None:
        tick()
        if k == depth:
            free(0)
            return
        s = steps[k]
        candidates: list[Args] | None = None
        if k == 0 and seed_facts is not None:
            candidates = seed_facts
        else:
            for pos, slot, const in s.lookups:
                found = by_arg.get((s.pred, pos, values[slot] if slot >= 0 else const), [])
                if candidates is None or len(found) < len(candidates):
                    candidates = found
            if candidates is None:
                candidates = by_pred.get(s.pred, [])
        tests, binds, repeats = s.tests, s.binds, s.repeats
        for args in candidates:
            ok = True
            for pos, slot, const in tests:
                if args[pos] != (values[slot] if slot >= 0 else const):
                    ok = False
                    break
            if not ok:
                continue
            for pos, slot in binds:
                value = args[pos]
                if value not in members[slot]:
                    ok = False
                    break
                values[slot] = value
            if not ok:
                continue
            for pos, slot in repeats:
                if args[pos] != values[slot]:
                    ok = False
                    break
            if ok:
                step(k + 1)

    step(0)
    return out
