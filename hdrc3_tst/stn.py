"""Simple Temporal Network on a distance graph, with incremental propagation (section 6.3.1).

Written here rather than taken from networkx: the network must (a) keep single-source distances
from and to the mission origin ``Z`` up to date when one edge is added (mixed-initiative
``set``), touching only the variables whose bounds change, (b) carry strict bounds (``TS < TE``
in Example 6.2) exactly, and (c) name the constraints on a negative cycle. networkx recomputes
from scratch (Bellman-Ford over the whole graph per query, far above the 1 ms target for a
1,000-node tree) and has neither strictness nor undo.

An edge ``u -> v`` with bound ``(w, s)`` means ``v - u <= w`` (``< w`` when ``s`` is -1).
Bounds add with ``(w1 + w2, min(s1, s2))`` and compare lexicographically, so a cycle is
inconsistent when its bound is below ``(0, 0)``: ``x - x < 0`` as well as ``x - x <= -1``.
Every variable gets ``v - Z <= HORIZON`` and ``Z - v <= 0`` (all times after the origin), so
every negative cycle is reachable from ``Z`` in both directions.

Distances are summed in whole nanoseconds (Python integers, exact): float sums of seconds
round, and at the horizon's 1e9 s a cycle of equalities (``t1 = t``, ``t3 = t2``, ``t7 = t2`` of
a ``monitor-single``) came out 1e-7 s negative, an inconsistency that was not there (and the
predecessor walk that names a cycle then never ended).
"""

from __future__ import annotations

import heapq
import math
from collections import deque
from dataclasses import dataclass
from typing import NamedTuple

Bound = tuple[float, int]
"""(value, strictness): strictness -1 for ``<``, 0 for ``<=``."""
Weight = tuple[float, int]
"""A bound in whole nanoseconds (an ``int``; ``math.inf`` when unbounded), and its strictness."""
TICKS_PER_S = 1_000_000_000

ORIGIN = "Z"
HORIZON = 1.0e9
"""Seconds; a latest time beyond half the horizon is shown as unbounded."""
_INF: Weight = (math.inf, 0)
_ZERO: Weight = (0, 0)
_HORIZON: Bound = (HORIZON, 0)
_NOT_BEFORE: Bound = (0.0, 0)


def _add(a: Weight, b: Weight) -> Weight:
    return (a[0] + b[0], min(a[1], b[1]))


def _ticks(seconds: float) -> float:
    """Whole nanoseconds (an ``int``), or the infinity itself."""
    return round(seconds * TICKS_PER_S) if math.isfinite(seconds) else seconds


_HORIZON_WEIGHT: Weight = (_ticks(HORIZON), 0)


class _EdgeFields(NamedTuple):
    source: str
    target: str
    bound: Bound
    label: str
    weight: Weight
    """The bound in whole nanoseconds: what propagation adds."""


class Edge(_EdgeFields):
    """One distance-graph edge and the constraint it comes from (immutable).

    ``Edge(source, target, bound, label)``; the weight is the bound quantised once. A named
    tuple rather than a frozen dataclass: a mission makes one edge per bound and equality
    (26,000 for the 1,000-node benchmark), and a frozen dataclass takes three times as long
    to make (``object.__setattr__`` per field).
    """

    __slots__ = ()

    def __new__(cls, source: str, target: str, bound: Bound, label: str) -> Edge:  # noqa: D102
        value = bound[0]
        ticks = round(value * TICKS_PER_S) if math.isfinite(value) else value
        return tuple.__new__(cls, (source, target, bound, label, (ticks, bound[1])))


@dataclass(frozen=True)
class Window:
    """Earliest and latest time of a variable (open ends when strict)."""

    earliest: float
    latest: float
    earliest_strict: bool = False
    latest_strict: bool = False

    def __str__(self) -> str:
        lo = "(" if self.earliest_strict else "["
        unbounded = self.latest >= HORIZON / 2
        hi = ")" if self.latest_strict or unbounded else "]"
        latest = "inf" if unbounded else f"{self.latest:g}"
        return f"{lo}{self.earliest:g}, {latest}{hi}"


class Inconsistent(Exception):
    """A negative cycle: the edges on it name the conflicting constraints."""

    def __init__(self, cycle: tuple[Edge, ...]) -> None:
        super().__init__(", ".join(e.label for e in cycle))
        self.cycle = cycle


class SimpleTemporalNetwork:
    """Time variables, difference constraints and the windows they leave."""

    def __init__(self) -> None:
        self._out: dict[str, dict[str, Edge]] = {ORIGIN: {}}
        self._in: dict[str, dict[str, Edge]] = {ORIGIN: {}}
        self._from: dict[str, Weight] = {ORIGIN: _ZERO}
        """Shortest distance Z -> v: the latest time of v."""
        self._to: dict[str, Weight] = {ORIGIN: _ZERO}
        """Shortest distance v -> Z: minus the earliest time of v."""

    def copy(self) -> SimpleTemporalNetwork:
        """An independent network with the same variables, edges and windows (edges are frozen)."""
        out = SimpleTemporalNetwork()
        out._out = {v: dict(edges) for v, edges in self._out.items()}
        out._in = {v: dict(edges) for v, edges in self._in.items()}
        out._from = dict(self._from)
        out._to = dict(self._to)
        return out

    @property
    def variables(self) -> tuple[str, ...]:
        """Every time variable except the origin."""
        return tuple(v for v in self._out if v != ORIGIN)

    @property
    def edge_count(self) -> int:
        """Edges of the distance graph (two per equality, one per bound)."""
        return sum(len(e) for e in self._out.values())

    def edges(self) -> tuple[Edge, ...]:
        """Every edge of the distance graph (the tightest one per ordered pair)."""
        return tuple(e for out in self._out.values() for e in out.values())

    def add_variable(self, name: str) -> None:
        """A new time point in ``[0, HORIZON]``."""
        if name in self._out:
            return
        # Two edges per variable, their weights known: made without quantising them again.
        horizon = Edge._make((ORIGIN, name, _HORIZON, "horizon", _HORIZON_WEIGHT))
        after_origin = Edge._make((name, ORIGIN, _NOT_BEFORE, f"{name} >= 0", _ZERO))
        self._out[name] = {ORIGIN: after_origin}
        self._in[name] = {ORIGIN: horizon}
        self._out[ORIGIN][name] = horizon
        self._in[ORIGIN][name] = after_origin
        self._from[name] = _INF
        self._to[name] = _INF

    def _store(self, edge: Edge) -> bool:
        old = self._out[edge.source].get(edge.target)
        if old is not None and old.weight <= edge.weight:
            return False
        self._out[edge.source][edge.target] = edge
        self._in[edge.target][edge.source] = edge
        return True

    def constrain(self, later: str, earlier: str, bound: float, strict: bool, label: str) -> None:
        """Record ``later - earlier <= bound`` (``<`` when strict) without propagating."""
        edge = Edge(earlier, later, (bound, -1 if strict else 0), label)
        out = self._out[earlier]
        old = out.get(later)
        if old is None or edge.weight < old.weight:  # as _store, inlined: one call per bound
            out[later] = edge
            self._in[later][earlier] = edge

    # --- propagation --------------------------------------------------------------------
    def order(self, names: list[str]) -> None:
        """Sweep the variables in this order (the rest after them).

        For a TST: a node's start before its children's variables and its end after them, so
        that earliest times flow forward and latest times backward through one sweep each.
        """
        ranked = dict.fromkeys([ORIGIN, *(n for n in names if n in self._out), *self._out])
        self._out = {name: self._out[name] for name in ranked}

    def propagate(self) -> None:
        """Recompute every window from scratch (raises :class:`Inconsistent`).

        Bellman-Ford in the spirit of Yen's ordering: the variables in temporal order (see
        :meth:`order`, so most constraints point one way), each pass a forward and a backward
        sweep over them. A tree-shaped STN settles in a few passes; a cycle in the
        predecessor graph is a negative cycle.
        """
        names = list(self._out)
        index = {name: i for i, name in enumerate(names)}
        # The graph's own dictionaries are the adjacency (no list per variable and direction:
        # fewer objects for the garbage collector, which the benchmark's full heap feels);
        # their keys are the edges' far ends.
        self._from = self._sweeps(names, index, list(self._out.values()), "target")
        self._to = self._sweeps(names, index, [self._in[name] for name in names], "source")

    def _sweeps(
        self,
        names: list[str],
        index: dict[str, int],
        adjacency: list[dict[str, Edge]],
        end: str,
    ) -> dict[str, Weight]:
        """Bellman-Ford, each pass a forward and a backward sweep over the variables."""
        n = len(names)
        value = [math.inf] * n
        strict = [0] * n
        pred: list[Edge | None] = [None] * n
        value[index[ORIGIN]] = 0
        # A variable's edges are relaxed again only when its distance changed since they last
        # were: an unchanged distance cannot improve anything. An improvement is carried on
        # in the same sweep when it reaches a variable later in the sweep's direction.
        stale = [False] * n
        stale[index[ORIGIN]] = True
        for _ in range(n + 1):
            changed = False
            for order in (range(n), range(n - 1, -1, -1)):
                for i in order:
                    if not stale[i]:
                        continue
                    stale[i] = False
                    base, sbase = value[i], strict[i]
                    for far, edge in adjacency[i].items():
                        j = index[far]
                        w, s = edge.weight
                        cand = base + w
                        cs = sbase if sbase < s else s
                        if cand < value[j] or (cand == value[j] and cs < strict[j]):
                            value[j], strict[j], pred[j] = cand, cs, edge
                            stale[j] = changed = True
            if not changed:
                return {name: (value[i], strict[i]) for i, name in enumerate(names)}
            cycle = self._pred_cycle(names, index, pred, end)
            if cycle:
                raise Inconsistent(cycle)
        raise AssertionError("Bellman-Ford did not settle in n passes without a cycle")

    @staticmethod
    def _pred_cycle(
        names: list[str], index: dict[str, int], pred: list[Edge | None], end: str
    ) -> tuple[Edge, ...]:
        """The edges of a cycle in the predecessor graph, if there is one."""
        back = "source" if end == "target" else "target"
        state = [0] * len(names)  # 0 unseen, 1 on the current walk, 2 done
        for start in range(len(names)):
            walk: list[int] = []
            i = start
            while state[i] == 0 and pred[i] is not None:
                state[i] = 1
                walk.append(i)
                i = index[getattr(pred[i], back)]
            if state[i] == 1:  # came back onto this walk: a cycle
                edges = [e for k in walk[walk.index(i) :] if (e := pred[k]) is not None]
                return tuple(sorted(edges, key=lambda e: e.label))
            for k in walk:
                state[k] = 2
        return ()

    def add(self, later: str, earlier: str, bound: float, strict: bool, label: str) -> None:
        """Add ``later - earlier <= bound`` and update only what changes.

        On a negative cycle nothing changes and :class:`Inconsistent` is raised.
        """
        self._add_undoable(Edge(earlier, later, (bound, -1 if strict else 0), label))

    def fix(self, var: str, value: float, label: str) -> None:
        """``var = value`` (two edges to the origin), all or nothing."""
        first = self._add_undoable(Edge(ORIGIN, var, (value, 0), label))
        try:
            self._add_undoable(Edge(var, ORIGIN, (-value, 0), label))
        except Inconsistent:
            self._revert(first)
            raise

    _Undo = tuple[Edge, "Edge | None", dict[str, Weight], dict[str, Weight]]

    def _add_undoable(self, edge: Edge) -> _Undo:
        earlier, later = edge.source, edge.target
        old = self._out[earlier].get(later)
        undo: SimpleTemporalNetwork._Undo = (edge, old, {}, {})
        if old is not None and old.weight <= edge.weight:
            return undo
        self._store(edge)
        try:
            if _add(self._from[earlier], edge.weight) < self._from[later]:
                undo[2][later] = self._from[later]
                self._from[later] = _add(self._from[earlier], edge.weight)
                self._relax(self._from, self._out, "target", edge, undo[2])
            if _add(self._to[later], edge.weight) < self._to[earlier]:
                undo[3][earlier] = self._to[earlier]
                self._to[earlier] = _add(self._to[later], edge.weight)
                self._relax(self._to, self._in, "source", edge, undo[3])
        except Inconsistent:
            self._revert(undo)
            raise
        return undo

    def _revert(self, undo: _Undo) -> None:
        edge, old, undo_from, undo_to = undo
        self._from.update(undo_from)
        self._to.update(undo_to)
        if old is None:
            self._out[edge.source].pop(edge.target, None)
            self._in[edge.target].pop(edge.source, None)
        else:
            self._out[edge.source][edge.target] = old
            self._in[edge.target][edge.source] = old

    def _relax(
        self,
        dist: dict[str, Weight],
        graph: dict[str, dict[str, Edge]],
        end: str,
        edge: Edge,
        undo: dict[str, Weight],
    ) -> None:
        """Propagate what the new ``edge`` improved, over the changed region only (FIFO).

        The graph was consistent before, so a new negative cycle runs through ``edge``: it
        exists exactly when the propagation comes back and improves the edge's near end. That
        also catches zero-weight cycles with a strict edge, which never stop improving by an
        amount a counter would notice.
        """
        back = "source" if end == "target" else "target"
        first, stop = getattr(edge, end), getattr(edge, back)
        pred: dict[str, Edge] = {first: edge}
        queue = deque([first])
        queued = {first}
        while queue:
            node = queue.popleft()
            queued.discard(node)
            base = dist[node]
            for out in graph[node].values():
                nxt = getattr(out, end)
                cand = (base[0] + out.weight[0], min(base[1], out.weight[1]))
                if cand < dist[nxt]:
                    undo.setdefault(nxt, dist[nxt])
                    dist[nxt] = cand
                    pred[nxt] = out
                    if nxt == stop:
                        raise Inconsistent(self._back_to(pred, stop, first, back))
                    if nxt not in queued:
                        queued.add(nxt)
                        queue.append(nxt)

    @staticmethod
    def _back_to(pred: dict[str, Edge], stop: str, first: str, back: str) -> tuple[Edge, ...]:
        cycle = [pred[stop]]
        node = getattr(pred[stop], back)
        while node != stop:
            cycle.append(pred[node])
            node = getattr(pred[node], back)
        return tuple(sorted(cycle, key=lambda e: e.label))

    # --- queries ------------------------------------------------------------------------
    def no_later_than(self, source: str) -> dict[str, Weight]:
        """The variables the constraints force no later than ``source``, with the distance.

        ``{v: d}`` for every ``v`` (not the origin, not ``source``) whose shortest distance
        ``source -> v`` is ``d <= 0``: ``v - source <= d``, so ``v`` happens at least ``-d``
        before ``source`` (at the same time when ``d`` is ``(0, 0)``; ``d`` is in whole
        nanoseconds with its strictness). A dispatcher must not start ``source`` before these.

        Dijkstra on Johnson-reweighted edges: the latest times (distances from the origin) are
        a feasible potential, so ``w + latest(u) - latest(v) >= 0``. A vertex farther than
        ``latest(source)`` in reduced distance cannot lead to ``d <= 0`` (latest times are
        not negative) and is not expanded.
        """
        if any(d[0] == math.inf for d in self._from.values()):
            self.propagate()  # variables added since the last propagation have no latest time
        potential = {v: d[0] for v, d in self._from.items()}
        limit = potential[source]
        reduced: dict[str, float] = {source: 0}
        strict: dict[str, int] = {source: 0}
        heap: list[tuple[float, int, str]] = [(0, 0, source)]
        done: set[str] = set()
        while heap:
            dist, _, node = heapq.heappop(heap)
            if node in done:
                continue
            done.add(node)
            if dist > limit:
                continue
            for edge in self._out[node].values():
                nxt = edge.target
                cand = dist + edge.weight[0] + potential[node] - potential[nxt]
                cand_strict = min(strict[node], edge.weight[1])
                old = reduced.get(nxt)
                if old is None or cand < old or (cand == old and cand_strict < strict[nxt]):
                    reduced[nxt], strict[nxt] = cand, cand_strict
                    heapq.heappush(heap, (cand, cand_strict, nxt))
        found = {}
        for v, dist in reduced.items():
            if v in (source, ORIGIN):
                continue
            d: Weight = (dist - potential[source] + potential[v], strict[v])
            if d <= _ZERO:
                found[v] = d
        return found

    def window(self, name: str) -> Window:
        """Earliest and latest time of ``name`` after the last propagation."""
        lo, hi = self._to[name], self._from[name]
        return Window(-lo[0] / TICKS_PER_S + 0.0, hi[0] / TICKS_PER_S, lo[1] < 0, hi[1] < 0)
