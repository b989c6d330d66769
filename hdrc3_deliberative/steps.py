"""Map relations for control rules (``step|nearer NAME by REL`` in a control file).

Control formulas see only ``[t]``, ``[t+1]`` and the goal, so a rule cannot say "drive towards
the package" on a road map where the destination is several links away. TALplanner in IPC-2002
(Kvarnström & Magnusson, JAIR 20) solved this for Rovers and DriverLog with relations computed
from the problem's static map. Here ``step toward by link`` defines the static predicate
``toward(k.., x, y, g)``: ``link(k.., x, y)`` is a static fact and ``y`` is one link closer to
``g`` than ``x`` along a shortest ``link`` path (breadth-first search per key ``k..``, e.g.
per rover for ``can_traverse``). ``nearer closer by link`` defines ``closer(k.., x, a, b)``:
``a`` is strictly fewer links from ``x`` than ``b`` (rules use it to head for the nearest of
several targets, which makes every step shrink the distance to the nearest one). The
relations are added to a copy of the ground task before the
rules are compiled, so rules use it like any static predicate. Written here (a few lines of
breadth-first search over the task's own static facts; no graph library needed).
"""

from __future__ import annotations

from collections import deque
from dataclasses import replace

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import MapRelation, StepDecl
from hdrc3_deliberative.task import GroundAtom, Task

Args = tuple[str, ...]


def _check(task: Task, preds: dict[str, tuple[str, ...]], decl: StepDecl) -> tuple[str, ...]:
    """Signature of the relation ``decl`` defines; raises PlanningInputError when misused."""

    def fail(message: str) -> PlanningInputError:
        p = decl.pos
        what = f"'{decl.kind.value} {decl.name} by {decl.relation}'"
        return PlanningInputError(f"{what}: {message}", p.source, p.line, p.column)

    if decl.name in preds or decl.name in task.domain.types:
        raise fail(f"'{decl.name}' is already a predicate or type")
    signature = preds.get(decl.relation)
    if signature is None:
        raise fail(f"undefined predicate '{decl.relation}'")
    if decl.relation not in task.static_preds:
        raise fail(f"'{decl.relation}' is changed by an action (not a static map)")
    if len(signature) < 2 or signature[-1] != signature[-2]:
        raise fail(f"'{decl.relation}' must end with two arguments of one type (an edge)")
    return (*signature, signature[-1])


def _distances(start: str, adjacent: dict[str, list[str]]) -> dict[str, int]:
    """Breadth-first link counts from ``start`` over ``adjacent``."""
    dist = {start: 0}
    queue = deque([start])
    while queue:
        node = queue.popleft()
        for nxt in adjacent.get(node, ()):
            if nxt not in dist:
                dist[nxt] = dist[node] + 1
                queue.append(nxt)
    return dist


def _map_facts(decl: StepDecl, edges: list[Args]) -> set[GroundAtom]:
    """Facts of ``decl`` over the edges ``(k.., x, y)``, one map per key ``k..``."""
    maps: dict[Args, tuple[dict[str, list[str]], dict[str, list[str]]]] = {}
    for args in edges:
        out, incoming = maps.setdefault(args[:-2], ({}, {}))
        out.setdefault(args[-2], []).append(args[-1])
        incoming.setdefault(args[-1], []).append(args[-2])
    facts: set[GroundAtom] = set()
    name = decl.name
    for key, (out, incoming) in maps.items():
        if decl.kind is MapRelation.NEARER:
            for x in out:
                dist = _distances(x, out)
                facts.update(
                    (name, (*key, x, a, b)) for a, da in dist.items() for b, db in dist.items()
                    if da < db
                )
            continue
        for goal in incoming:
            dist = _distances(goal, incoming)  # links from each place to goal
            for x, d in dist.items():
                facts.update(
                    (name, (*key, x, y, goal)) for y in out.get(x, ()) if dist.get(y) == d - 1
                )
    return facts


def with_steps(task: Task, steps: tuple[StepDecl, ...]) -> Task:
    """A copy of ``task`` where every declared map relation is a static predicate."""
    if not steps:
        return task
    predicates = dict(task.domain.predicates)
    facts = set(task.static_facts)
    for decl in steps:
        predicates[decl.name] = _check(task, predicates, decl)
        edges = [args for pred, args in task.static_facts if pred == decl.relation]
        facts |= _map_facts(decl, edges)
    names = frozenset(d.name for d in steps)
    return replace(
        task,
        domain=replace(task.domain, predicates=predicates),
        static_facts=frozenset(facts),
        static_preds=task.static_preds | names,
    )
