from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from hdrc3_navigation.audit import WorldAudit
from hdrc3_navigation.constraints import Constraints
from hdrc3_navigation.cost import Criterion
from hdrc3_navigation.elevation_map import ElevationMap
from hdrc3_navigation.planner import PathPlanner, PlannerKind, PlanRequest, PlanStatus
from hdrc3_navigation.roadmap import Roadmap
from sim.world import World

WEST, EAST = (-60.0, 0.0, 15.0), (60.0, 0.0, 15.0)
"""Either side of the wall (25 m high, 120 m long): a path must go around or over it."""
MARGIN = 6.0


def audit(world: World, result, clearance: float = MARGIN - 0.05, zones=()) -> list:  # type: ignore[no-untyped-def]
    return WorldAudit(world, zones).check_segments(result.segments, clearance)


def assert_continuous(result) -> None:  # type: ignore[no-untyped-def]
    segs = result.segments
    for a, b in itertools.pairwise(segs):
        assert a.end == b.start
        if a.end_velocity > 0.0:  # no stop: the tangents agree in direction
            da, db = np.array(a.end_direction), np.array(b.start_direction)
            assert float(da @ db) / (np.linalg.norm(da) * np.linalg.norm(db)) > 0.999
    assert segs[-1].end_velocity == 0.0


@pytest.mark.parametrize("kind", list(PlannerKind))
@pytest.mark.parametrize("criterion", list(Criterion))
def test_paths_around_the_wall_are_clear_of_the_world(
    planner: PathPlanner, small_world: World, kind: PlannerKind, criterion: Criterion
) -> None:
    result = planner.plan(
        PlanRequest(WEST, EAST, 8.0, planner=kind, criterion=criterion, timeout=5.0)
    )
    assert result.status is PlanStatus.SOLVED, result.reason
    assert result.segments[0].start == WEST and result.segments[-1].end == EAST
    assert_continuous(result)
    assert audit(small_world, result) == []
    assert result.length > math.dist(WEST, EAST)  # the wall is in the way
    assert result.duration > result.length / 8.0


def test_query_no_fly_zone_and_altitude_limits_are_honoured(
    planner: PathPlanner, small_world: World
) -> None:
    # the way around the south end of the wall is closed by a query no-fly zone, the way over
    # it by the ceiling: the path goes round the north end
    south = ((-30.0, -100.0), (30.0, -100.0), (30.0, -20.0), (-30.0, -20.0))
    constraints = Constraints(min_altitude=10.0, max_altitude=22.0, no_fly=(south,))
    result = planner.plan(PlanRequest(WEST, EAST, 8.0, constraints, timeout=5.0))
    assert result.status is PlanStatus.SOLVED, result.reason
    assert audit(small_world, result, zones=[("south", south, -math.inf, math.inf)]) == []
    heights = [seg.position(s)[2] for seg in result.segments for s in np.linspace(0, 1, 21)]
    assert min(heights) >= 10.0 - 1e-6 and max(heights) <= 22.0 + 1e-6
    ys = [seg.position(s)[1] for seg in result.segments for s in np.linspace(0, 1, 21)]
    assert max(ys) > 60.0  # north of the wall's end


def test_climb_rate_limit_bounds_the_vertical_speed(planner: PathPlanner) -> None:
    low, high = (-60.0, -80.0, 10.0), (-60.0, 40.0, 35.0)
    request = PlanRequest(low, high, 8.0, Constraints(max_climb_rate=1.5), timeout=5.0)
    result = planner.plan(request)
    assert result.status is PlanStatus.SOLVED, result.reason
    for seg in result.segments:
        for s in np.linspace(0.0, 1.0, 41):
            t = seg.tangent(float(s))
            assert 8.0 * t[2] <= 1.5 + 0.1


def test_runtime_obstacle_and_no_fly_zone_change_the_answer(
    planner: PathPlanner, small_world: World
) -> None:
    a, b = (-60.0, -80.0, 12.0), (-60.0, 40.0, 12.0)
    straight = planner.plan(PlanRequest(a, b, 8.0, timeout=5.0))
    assert straight.ok and len(straight.segments) == 1
    block = ((-80.0, -25.0), (-40.0, -25.0), (-40.0, -15.0), (-80.0, -15.0))
    planner.gis.add_obstacle("truck", block, 0.0, 30.0)
    around = planner.plan(PlanRequest(a, b, 8.0, timeout=5.0))
    assert around.ok, around.reason
    assert around.length > straight.length + 1.0
    gone = WorldAudit(small_world).check_segments(around.segments, MARGIN - 0.05)
    assert gone == []
    pts = np.array([seg.position(s) for seg in around.segments for s in np.linspace(0, 1, 81)])
    # round it or over it (top 30 m): 3D distance to the prism
    clearance = [
        np.hypot(Polygon(block).distance(Point(p[0], p[1])), max(0.0, p[2] - 30.0)) for p in pts
    ]
    assert min(clearance) >= MARGIN - 0.05
    planner.gis.remove_obstacle("truck")
    again = planner.plan(PlanRequest(a, b, 8.0, timeout=5.0))
    assert again.ok and len(again.segments) == 1


WALL_TOP = 30.0
WALL_CELLS = (slice(23, 27), slice(5, 65))
"""A laser-mapped wall 4 m thick, 30 m high: east -90..-30, north -22..-18 (map cells)."""


def walled_map() -> ElevationMap:
    heights = np.zeros((40, 70))  # east -95..-25, north -45..-5, 1 m cells
    heights[WALL_CELLS] = WALL_TOP
    return ElevationMap("scan", -95.0, -45.0, 1.0, heights)


@pytest.mark.parametrize("kind", [PlannerKind.PRM_RRT, PlannerKind.RRT])
def test_a_stored_elevation_map_changes_the_answer(
    planner: PathPlanner, small_world: World, kind: PlannerKind
) -> None:
    a, b = (-60.0, -80.0, 12.0), (-60.0, 40.0, 12.0)
    straight = planner.plan(PlanRequest(a, b, 8.0, planner=kind, timeout=5.0))
    assert straight.ok and len(straight.segments) == 1, straight.reason
    m = walled_map()
    planner.gis.add_elevation_map(m)
    around = planner.plan(PlanRequest(a, b, 8.0, planner=kind, timeout=10.0))
    assert around.ok, around.reason
    assert len(around.segments) > 1 and around.length > straight.length + 1.0
    assert WorldAudit(small_world).check_segments(around.segments, MARGIN - 0.05) == []
    pts = np.array([seg.position(s) for seg in around.segments for s in np.linspace(0, 1, 201)])
    # 3D distance to the box of the wall's cells; the surface joins cell centres, so a path may
    # come half a cell closer to a cell's outer edge than the margin
    r = m.resolution
    rows, cols = WALL_CELLS
    lo = np.array([m.east0 + cols.start * r, m.north0 + rows.start * r, -np.inf])
    hi = np.array([m.east0 + cols.stop * r, m.north0 + rows.stop * r, WALL_TOP])
    clearance = np.linalg.norm(np.maximum(0.0, np.maximum(lo - pts, pts - hi)), axis=1)
    assert clearance.min() >= MARGIN - r / 2.0 - 0.05
    ground = m.heights_at(pts[:, 0], pts[:, 1])
    assert not np.any(pts[:, 2] < np.nan_to_num(ground, nan=-np.inf) + MARGIN - 0.05)
    planner.gis.remove_elevation_map("scan")
    again = planner.plan(PlanRequest(a, b, 8.0, planner=kind, timeout=5.0))
    assert again.ok and len(again.segments) == 1


BAD = [
    ((-60.0, 0.0, 15.0), (0.0, 0.0, 10.0), {}, PlanStatus.GOAL_IN_OBSTACLE),
    ((0.0, 0.0, 10.0), EAST, {}, PlanStatus.START_IN_OBSTACLE),
    ((-60.0, 0.0, 2.0), EAST, {}, PlanStatus.START_IN_OBSTACLE),  # too near the ground
    (WEST, (65.0, -65.0, 20.0), {}, PlanStatus.GOAL_IN_NO_FLY_ZONE),
    ((65.0, -65.0, 20.0), WEST, {}, PlanStatus.START_IN_NO_FLY_ZONE),
    (WEST, (0.0, 500.0, 20.0), {}, PlanStatus.GOAL_OUTSIDE_WORLD),
    ((-60.0, 0.0, 900.0), EAST, {}, PlanStatus.START_OUTSIDE_WORLD),
    (
        WEST,
        EAST,
        {"constraints": Constraints(min_altitude=30.0, max_altitude=20.0)},
        PlanStatus.INVALID,
    ),
    (WEST, EAST, {"constraints": Constraints(max_altitude=12.0)}, PlanStatus.INVALID),
    (WEST, EAST, {"constraints": Constraints(max_climb_rate=-1.0)}, PlanStatus.INVALID),
    (
        WEST,
        EAST,
        {"constraints": Constraints(no_fly=(((0.0, 0.0), (1.0, 1.0)),))},
        PlanStatus.INVALID,
    ),
    (WEST, EAST, {"speed": 0.0}, PlanStatus.INVALID),
    (WEST, EAST, {"speed": math.nan}, PlanStatus.INVALID),
    (WEST, EAST, {"timeout": -1.0}, PlanStatus.INVALID),
    (WEST, WEST, {}, PlanStatus.INVALID),
    ((math.inf, 0.0, 10.0), EAST, {}, PlanStatus.INVALID),
]


@pytest.mark.parametrize(("start", "goal", "extra", "status"), BAD)
def test_bad_requests_get_a_defined_status_and_reason(
    planner: PathPlanner,
    start,
    goal,
    extra,
    status,  # type: ignore[no-untyped-def]
) -> None:
    result = planner.plan(PlanRequest(start, goal, **{"speed": 8.0, **extra}))
    assert result.status is status
    assert result.reason and not result.segments


def test_query_no_fly_zone_around_the_goal_is_named(planner: PathPlanner) -> None:
    box = ((50.0, -10.0), (70.0, -10.0), (70.0, 10.0), (50.0, 10.0))
    result = planner.plan(PlanRequest(WEST, EAST, 8.0, Constraints(no_fly=(box,))))
    assert result.status is PlanStatus.GOAL_IN_NO_FLY_ZONE
    assert "query no-fly 0" in result.reason


@pytest.mark.parametrize("kind", list(PlannerKind))
def test_a_tiny_timeout_returns_timeout_not_a_hang(planner: PathPlanner, kind: PlannerKind) -> None:
    result = planner.plan(PlanRequest(WEST, EAST, 8.0, planner=kind, timeout=1e-6))
    assert result.status is PlanStatus.TIMEOUT
    assert result.planning_time < 1.0


def test_enclosed_goal_is_no_path_for_prm_and_timeout_for_rrt(planner: PathPlanner) -> None:
    # a ring of no-fly zones around the goal: the roadmap query proves it disconnected; the
    # RRT can only run out of time
    goal = (-60.0, -60.0, 15.0)
    ring = (
        ((-85.0, -85.0), (-35.0, -85.0), (-35.0, -80.0), (-85.0, -80.0)),
        ((-85.0, -40.0), (-35.0, -40.0), (-35.0, -35.0), (-85.0, -35.0)),
        ((-85.0, -85.0), (-80.0, -85.0), (-80.0, -35.0), (-85.0, -35.0)),
        ((-40.0, -85.0), (-35.0, -85.0), (-35.0, -35.0), (-40.0, -35.0)),
    )
    c = Constraints(no_fly=ring)
    prm = planner.plan(PlanRequest((-60.0, 40.0, 15.0), goal, 8.0, c, PlannerKind.PRM, timeout=5.0))
    assert prm.status is PlanStatus.NO_PATH
    rrt = planner.plan(PlanRequest((-60.0, 40.0, 15.0), goal, 8.0, c, PlannerKind.RRT, timeout=0.5))
    assert rrt.status is PlanStatus.TIMEOUT


def chain_roadmap() -> Roadmap:
    """A roadmap of one line of nodes west -> east along north = -80 (south of the wall)."""
    xs = np.linspace(-80.0, 80.0, 17)
    nodes = np.array([[x, -80.0, 15.0] for x in xs])
    edges = np.array([[i, i + 1] for i in range(len(xs) - 1)])
    return Roadmap(nodes, edges, "chain", 0.0)


def test_prm_rrt_reconnects_a_roadmap_cut_by_a_no_fly_zone(small_world: World, tmp_path) -> None:  # type: ignore[no-untyped-def]
    planner = PathPlanner(small_world, tmp_path)
    planner.use_roadmap(chain_roadmap())
    start, goal = (-80.0, -80.0, 15.0), (30.0, -80.0, 15.0)
    cut = ((15.0, -100.0), (20.0, -100.0), (20.0, -65.0), (15.0, -65.0))
    constraints = Constraints(no_fly=(cut,))
    prm = planner.plan(PlanRequest(start, goal, 8.0, constraints, PlannerKind.PRM, timeout=5.0))
    assert prm.status is PlanStatus.NO_PATH
    both = planner.plan(
        PlanRequest(start, goal, 8.0, constraints, PlannerKind.PRM_RRT, timeout=10.0)
    )
    assert both.status is PlanStatus.SOLVED, both.reason
    assert both.reconnected
    assert audit(small_world, both, zones=[("cut", cut, -math.inf, math.inf)]) == []


NEAR_WALL, LOW = (-20.0, 0.0, 15.0), (-60.0, 0.0, 7.0)
# (start, start direction, status, reason); the goal is EAST
JOINS = {
    "along the way": (WEST, (1.0, 0.0, 0.0), PlanStatus.SOLVED, ""),
    "sideways": (WEST, (0.0, 1.0, 0.0), PlanStatus.SOLVED, ""),
    "climbing": (WEST, (1.0, 0.0, 0.4), PlanStatus.SOLVED, ""),
    "backwards (a stop 20 m on)": (WEST, (-1.0, 0.0, 0.0), PlanStatus.SOLVED, ""),
    "straight at the wall 4 m off its margin": (
        NEAR_WALL, (1.0, 0.0, 0.0), PlanStatus.NO_PATH, "start direction (1.0, 0.0, 0.0) cannot be"
    ),
    "down into the ground margin": (
        LOW, (0.0, 0.0, -1.0), PlanStatus.NO_PATH, "start direction (0.0, 0.0, -1.0) cannot be"
    ),
    "not finite": (WEST, (math.nan, 0.0, 0.0), PlanStatus.INVALID, "three finite numbers"),
    "not three numbers": (WEST, (1.0, 0.0), PlanStatus.INVALID, "three finite numbers"),
}  # fmt: skip


@pytest.mark.parametrize(("start", "direction", "status", "reason"), JOINS.values(), ids=JOINS)
def test_a_replan_leaves_the_start_along_the_start_direction(
    planner: PathPlanner,
    small_world: World,
    start: tuple[float, float, float],
    direction: tuple[float, ...],
    status: PlanStatus,
    reason: str,
) -> None:
    request = PlanRequest(start, EAST, 8.0, timeout=5.0, start_direction=direction)  # type: ignore[arg-type]
    result = planner.plan(request)
    assert result.status is status, result.reason
    assert reason in result.reason
    if status is not PlanStatus.SOLVED:
        assert not result.segments
        return
    first = result.segments[0]
    assert first.start == start and result.segments[-1].end == EAST
    unit = np.array(direction) / np.linalg.norm(direction)
    assert first.tangent(0.0) == pytest.approx(unit, abs=1e-9)
    assert_continuous(result)
    assert audit(small_world, result) == []  # the independent check: footprints and heights


def test_a_zero_start_direction_is_free(planner: PathPlanner) -> None:
    free = planner.plan(PlanRequest(WEST, EAST, 8.0, planner=PlannerKind.PRM))
    zero = planner.plan(
        PlanRequest(WEST, EAST, 8.0, planner=PlannerKind.PRM, start_direction=(0.0, 0.0, 0.0))
    )
    assert free.status is zero.status is PlanStatus.SOLVED
    assert zero.segments == free.segments
