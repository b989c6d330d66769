from __future__ import annotations

import time

import numpy as np
import pytest

from hdrc3_navigation.cost import Criterion, FlightModel
from hdrc3_navigation.roadmap import Roadmap
from hdrc3_navigation.search import Deadline, Query, edge_costs

# a diamond: 0 -> 3 either over the hill (node 1, short but steep) or round it (node 2, level)
NODES = np.array([[0.0, 0, 10], [50, 0, 60], [50, 60, 10], [100, 0, 10]])
EDGES = np.array([[0, 1], [1, 3], [0, 2], [2, 3]])


def query(criterion: Criterion = Criterion.LENGTH, **kw) -> Query:  # type: ignore[no-untyped-def]
    roadmap = Roadmap(NODES, EDGES, "diamond", 0.0)
    fields = {
        "node_valid": np.ones(4, bool),
        "edge_valid": (np.ones(4, bool), np.ones(4, bool)),
        "edge_suspect": np.zeros(4, bool),
        "runtime_ok": lambda a, b: True,
        "connect_ok": lambda a, b: float(np.linalg.norm(np.asarray(a) - np.asarray(b))) < 1.0,
        "deadline": time.perf_counter() + 10.0,
    }
    fields.update(kw)
    costs = edge_costs(roadmap, FlightModel(), criterion, 10.0)
    return Query(roadmap, NODES[0] + 0.1, NODES[3] + 0.1, criterion=criterion, speed=10.0,
                 model=FlightModel(), edge_cost=costs, **fields)  # fmt: skip


def test_length_takes_the_hill_and_time_goes_round_it() -> None:
    by_length = query(Criterion.LENGTH)
    assert by_length.astar(by_length.start_id, by_length.goal_id) == [4, 0, 1, 3, 5]
    by_time = query(Criterion.TIME)  # 50 m climb at 3 m/s takes longer than the detour
    assert by_time.astar(by_time.start_id, by_time.goal_id) == [4, 0, 2, 3, 5]


def test_invalid_edges_are_avoided_per_direction() -> None:
    forward = np.array([True, True, True, False])  # 2 -> 3 not allowed as stored
    backward = np.array([True, True, False, True])  # nor 2 -> 0: 2 is a dead end
    q = query(Criterion.TIME, edge_valid=(forward, backward))
    assert q.astar(q.start_id, q.goal_id) == [4, 0, 1, 3, 5]
    assert 2 not in q.component(q.goal_id, reverse=True)  # 2 cannot reach the goal
    assert 2 in q.component(q.start_id)


def test_suspect_edges_are_tested_once_with_the_runtime_check() -> None:
    calls = []

    def runtime_ok(a, b) -> bool:  # type: ignore[no-untyped-def]
        calls.append(1)
        return False

    q = query(edge_suspect=np.array([True, False, False, False]), runtime_ok=runtime_ok)
    assert q.astar(q.start_id, q.goal_id) == [4, 0, 2, 3, 5]
    q.astar(q.start_id, q.goal_id)
    assert len(calls) == 1


def test_unreachable_goal_and_deadline() -> None:
    q = query(node_valid=np.array([True, False, False, True]))
    assert q.astar(q.start_id, q.goal_id) is None
    with pytest.raises(Deadline):
        query(deadline=time.perf_counter() - 1.0)
