"""Map relations for control rules (``step|nearer NAME by REL`` in a control file).

Control formulas see only ``[t]``, ``[t+1]`` and the goal, so a rule cannot say "drive towards
the package" on a road map where the destination is several links away. Such relations are
computed from the problem's static map: ``step toward by link`` defines the static predicate
``toward(k.., x, y, g)``: ``link(k.., x, y)`` is a static fact and ``y`` is one link closer to
``g`` than ``x`` along a shortest ``link`` path (breadth-first search per key ``k..``, e.g.
per rover for ``can_traverse``). ``nearer closer by link`` defines ``closer(k.., x, a, b)``:
``a`` is strictly fewer links from ``x`` than ``b`` (rules use it to head for the nearest of
several targets, which makes every step shrink the distance to the nearest one). The
relations are declared in a copy of the ground task and tested from breadth-first distances
computed on first use (listing them would take cubic memory on large maps), so a rule may
use them only where its other atoms bind every argument (they never serve as a quantifier's
guard). Written here: a few lines of breadth-first search over the task's own static facts
need no graph library.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import replace

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import MapRelation, StepDecl
from hdrc3_deliberative.task import Task

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


class MapDistances:
    """Link counts over one static map ``REL(k.., x, y)``, computed per key on first use."""

    def __init__(self, edges: list[Args]) -> None:
        self._out: dict[Args, dict[str, list[str]]] = {}
        for args in edges:
            self._out.setdefault(args[:-2], {}).setdefault(args[-2], []).append(args[-1])
        self._edges = frozenset(edges)
        self._dist: dict[tuple[Args, str], dict[str, int]] = {}

    def between(self, key: Args, x: str, g: str) -> int | None:
        """Links from ``x`` to ``g`` on the map of ``key`` (None when unreachable)."""
        table = self._dist.get((key, x))
        if table is None:
            table = self._dist[(key, x)] = _distances(x, self._out.get(key, {}))
        return table.get(g)

    def step(self, args: Args) -> bool:
        """``(k.., x, y, g)``: the edge x->y lies on a shortest path from x to g."""
        key, x, y, g = args[:-3], args[-3], args[-2], args[-1]
        if (*key, x, y) not in self._edges:
            return False
        dx, dy = self.between(key, x, g), self.between(key, y, g)
        return dx is not None and dy is not None and dy == dx - 1

    def nearer(self, args: Args) -> bool:
        """``(k.., x, a, b)``: a is reachable from x in fewer links than b."""
        key, x, a, b = args[:-3], args[-3], args[-2], args[-1]
        da, db = self.between(key, x, a), self.between(key, x, b)
        return da is not None and (db is None or da < db)


MapTest = Callable[[Args], bool]


def map_relations(task: Task, steps: tuple[StepDecl, ...]) -> tuple[Task, dict[str, MapTest]]:
    """The declared relations as membership tests, and a copy of ``task`` that declares them.

    The relations are static predicates of the copy without listed facts: the compiler tests
    them only with all arguments bound and never enumerates them.
    """
    if not steps:
        return task, {}
    predicates = dict(task.domain.predicates)
    tests: dict[str, MapTest] = {}
    maps: dict[str, MapDistances] = {}
    for decl in steps:
        predicates[decl.name] = _check(task, predicates, decl)
        if decl.relation not in maps:
            edges = [args for pred, args in task.static_facts if pred == decl.relation]
            maps[decl.relation] = MapDistances(edges)
        graph = maps[decl.relation]
        tests[decl.name] = graph.step if decl.kind is MapRelation.STEP else graph.nearer
    copy = replace(
        task,
        domain=replace(task.domain, predicates=predicates),
        static_preds=task.static_preds | frozenset(tests),
    )
    return copy, tests
