from __future__ import annotations

import time

import numpy as np

from hdrc3_navigation.gis import Gis
from hdrc3_navigation.ompl_space import OmplSpace
from hdrc3_navigation.rrt import rrt_connect
from sim.world import World


def test_rrt_connect_finds_a_clear_path_round_the_wall(small_world: World) -> None:
    gis = Gis(small_world)
    space = OmplSpace(gis)
    path = rrt_connect(
        space, [np.array([-60.0, 0, 15])], [np.array([60.0, 0, 15])], time.perf_counter() + 10
    )
    assert path is not None
    assert list(path[0]) == [-60.0, 0, 15] and list(path[-1]) == [60.0, 0, 15]
    assert all(gis.segment_free(path[i], path[i + 1]) for i in range(len(path) - 1))


def test_several_starts_and_goals_and_an_extra_segment_test(small_world: World) -> None:
    gis = Gis(small_world)
    low = OmplSpace(
        gis, point_ok=lambda p: p[2] <= 20.0, segment_ok=lambda a, b: max(a[2], b[2]) <= 20.0
    )
    starts = [np.array([-60.0, y, 15]) for y in (-20.0, 20.0)]
    goals = [np.array([60.0, y, 15]) for y in (-20.0, 20.0)]
    path = rrt_connect(low, starts, goals, time.perf_counter() + 10)
    assert path is not None
    assert any(np.array_equal(path[0], s) for s in starts)
    assert any(np.array_equal(path[-1], g) for g in goals)
    assert path[:, 2].max() <= 20.0  # round the wall's ends, not over it
    assert np.abs(path[:, 1]).max() > 60.0


def test_no_time_left_is_no_path(small_world: World) -> None:
    space = OmplSpace(Gis(small_world))
    assert (
        rrt_connect(
            space, [np.array([-60.0, 0, 15])], [np.array([60.0, 0, 15])], time.perf_counter() - 1
        )
        is None
    )
