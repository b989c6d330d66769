"""Roadmap query (chapter section 7.1.1-7.1.2): connect start and goal, then A* with constraints.

The runtime constraints are evaluated for the whole roadmap at the start of the query with
vectorised shapely/numpy tests (a few milliseconds for thousands of edges); edges near a runtime
obstacle are tested with FCL lazily, when the A* search first relaxes them. Written here rather
than with networkx because the search must honour a deadline and report the component it
reached (the input of the PRM+RRT reconnection).
"""

from __future__ import annotations

import heapq
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from hdrc3_navigation.cost import Criterion, FlightModel
from hdrc3_navigation.gis import Point3
from hdrc3_navigation.roadmap import Roadmap

SegmentTest = Callable[[Point3, Point3], bool]
CONNECT_NEIGHBOURS = 15
"""Roadmap nodes tried when connecting a start or goal configuration (nearest first)."""
CONNECT_LINKS = 6
"""Connections made at most for a start or goal configuration."""


def edge_costs(
    roadmap: Roadmap, model: FlightModel, criterion: Criterion, speed: float
) -> tuple[list[float], list[float]]:
    """Costs of every roadmap edge in both directions under a criterion."""
    a, b = roadmap.nodes[roadmap.edges[:, 0]], roadmap.nodes[roadmap.edges[:, 1]]
    return (
        model.cost(criterion, a, b, speed).tolist(),
        model.cost(criterion, b, a, speed).tolist(),
    )


class Deadline(Exception):
    """The query's time budget ran out."""


@dataclass
class Query:
    """One roadmap query: the roadmap plus start (index n) and goal (index n+1)."""

    roadmap: Roadmap
    start: NDArray[np.float64]
    goal: NDArray[np.float64]
    node_valid: NDArray[np.bool_]
    """Per roadmap node: satisfies the query's constraints (and runtime obstacles)."""
    edge_valid: tuple[NDArray[np.bool_], NDArray[np.bool_]]
    """Per roadmap edge, flown as stored and reversed: satisfies the query's constraints
    (climb and descent limits depend on the direction)."""
    edge_suspect: NDArray[np.bool_]
    """Per roadmap edge: near a runtime obstacle, to be tested with ``runtime_ok``."""
    runtime_ok: SegmentTest
    connect_ok: SegmentTest
    """Full test of a new connection (static world, obstacles and constraints)."""
    criterion: Criterion
    speed: float
    model: FlightModel
    deadline: float
    edge_cost: tuple[list[float], list[float]]
    """Per roadmap edge, flown as stored and reversed: its cost (see :func:`edge_costs`)."""
    _out: dict[int, list[int]] = field(default_factory=dict)
    _in: dict[int, list[int]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Connect start and goal to their nearest valid roadmap nodes (and to each other)."""
        n = len(self.roadmap.nodes)
        self.start_id, self.goal_id = n, n + 1
        self._suspect_memo: dict[int, bool] = {}
        self._all = np.vstack([self.roadmap.nodes, self.start, self.goal])
        if self.connect_ok(self.start, self.goal):
            self._link(n, n + 1)
        for vid, p in ((n, self.start), (n + 1, self.goal)):
            _, idx = self.roadmap.tree.query(p, k=min(CONNECT_NEIGHBOURS, n))
            linked = 0
            for j in np.atleast_1d(idx).tolist():
                self._tick()
                if linked >= CONNECT_LINKS:
                    break
                if not self.node_valid[j]:
                    continue
                q = self.roadmap.nodes[j]
                if vid == n and self.connect_ok(p, q):
                    self._link(n, j)
                    linked += 1
                elif vid == n + 1 and self.connect_ok(q, p):
                    self._link(j, n + 1)
                    linked += 1

    def _link(self, a: int, b: int) -> None:
        """A valid connection flown from a to b."""
        self._out.setdefault(a, []).append(b)
        self._in.setdefault(b, []).append(a)

    def _tick(self) -> None:
        if time.perf_counter() > self.deadline:
            raise Deadline

    def point(self, i: int) -> NDArray[np.float64]:
        """Position of node i (start and goal included)."""
        if i == self.start_id:
            return self.start
        if i == self.goal_id:
            return self.goal
        out: NDArray[np.float64] = self.roadmap.nodes[i]
        return out

    def _edge_ok(self, u: int, v: int, k: int, forward: bool) -> bool:
        if not (self.edge_valid[0 if forward else 1][k] and self.node_valid[v]):
            return False
        if not self.edge_suspect[k]:
            return True
        ok = self._suspect_memo.get(k)
        if ok is None:
            ok = self._suspect_memo[k] = self.runtime_ok(self.point(u), self.point(v))
        return ok

    def neighbours(self, u: int) -> list[tuple[int, float]]:
        """(v, cost) of the valid edges u -> v."""
        pu = self.point(u)
        out = [
            (v, float(self.model.cost(self.criterion, pu, self.point(v), self.speed)))
            for v in self._out.get(u, ())
        ]
        if u < len(self.roadmap.nodes):
            fwd, bwd = self.edge_cost
            out += [
                (v, fwd[k] if forward else bwd[k])
                for v, k, forward in self.roadmap.adjacency[u]
                if self._edge_ok(u, v, k, forward)
            ]
        return out

    def predecessors(self, u: int) -> list[int]:
        """The nodes v with a valid edge v -> u."""
        out = list(self._in.get(u, ()))
        if u < len(self.roadmap.nodes):
            out += [
                v
                for v, k, forward in self.roadmap.adjacency[u]
                if self._edge_ok(v, u, k, not forward) and self.node_valid[v]
            ]
        return out

    def astar(self, source: int, target: int) -> list[int] | None:
        """A* from source to target; None if unreachable. Raises Deadline."""
        h: list[float] = self.model.heuristic(
            self.criterion, self._all, self.point(target), self.speed
        ).tolist()
        g = {source: 0.0}
        parent: dict[int, int] = {}
        heap = [(h[source], source)]
        closed: set[int] = set()
        while heap:
            _, u = heapq.heappop(heap)
            if u in closed:
                continue
            if u == target:
                path = [u]
                while path[-1] != source:
                    path.append(parent[path[-1]])
                return path[::-1]
            closed.add(u)
            self._tick()
            gu = g[u]
            for v, step in self.neighbours(u):
                if v in closed:
                    continue
                cost = gu + step
                if cost < g.get(v, float("inf")):
                    g[v] = cost
                    parent[v] = u
                    heapq.heappush(heap, (cost + h[v], v))
        return None

    def component(self, source: int, reverse: bool = False) -> set[int]:
        """Nodes reachable from source (``reverse``: that reach source), breadth first."""
        seen = {source}
        frontier = [source]
        while frontier:
            self._tick()
            nxt = []
            for u in frontier:
                step = self.predecessors(u) if reverse else [v for v, _ in self.neighbours(u)]
                for v in step:
                    if v not in seen:
                        seen.add(v)
                        nxt.append(v)
            frontier = nxt
        return seen
