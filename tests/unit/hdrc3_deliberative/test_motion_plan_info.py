from __future__ import annotations

import math
from pathlib import Path

import pytest

from hdrc3_deliberative.generators import UAV_DOMAIN, UAV_SCENARIO
from hdrc3_deliberative.motion_plan_info import PlannedMotionPlanInfo, StraightLineMotionPlanInfo
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_navigation.planner import PathPlanner
from sim.world_loader import load_world


@pytest.mark.parametrize(
    ("start", "goal", "duration", "cost", "feasible"),
    [
        ((0, 0, 0), (30, 40, 0), 5.0 + 5.0, 50.0, True),
        ((0, 0, 0), (0, 0, 0), 5.0, 0.0, True),
        ((0, 0, 0), (300, 400, 0), 55.0, 500.0, False),
    ],
)
def test_straight_line(
    start: tuple[float, float, float],
    goal: tuple[float, float, float],
    duration: float,
    cost: float,
    feasible: bool,
) -> None:
    info = StraightLineMotionPlanInfo(speed=10.0, overhead=5.0, max_range=100.0).query(
        "h", start, goal
    )
    assert info.duration == pytest.approx(duration)
    assert info.cost == pytest.approx(cost)
    assert info.feasible is feasible


SMALL_WORLD = Path(__file__).parents[1] / "hdrc3_navigation" / "small_world.toml"


@pytest.fixture(scope="module")
def planned(tmp_path_factory: pytest.TempPathFactory) -> PlannedMotionPlanInfo:
    planner = PathPlanner(load_world(SMALL_WORLD), tmp_path_factory.mktemp("rm"), roadmap_nodes=300)
    return PlannedMotionPlanInfo(planner, speed=8.0, cruise_agl=15.0)


def test_planned_flights_go_around_the_wall_and_climb_from_the_ground(
    planned: PlannedMotionPlanInfo,
) -> None:
    start, goal = (-60.0, 0.0, 0.0), (60.0, 0.0, 0.0)
    info = planned.query("h", start, goal)
    assert info.feasible
    climb_and_descent = 2 * 15.0 + 1.0  # terrain at the goal is about 1 m higher
    assert info.cost > math.dist(start, goal) + climb_and_descent
    straight = StraightLineMotionPlanInfo(speed=8.0, overhead=0.0).query("h", start, goal)
    assert info.duration > straight.duration
    assert planned.query("h", start, goal) is info  # memoised


@pytest.mark.parametrize(
    "goal",
    [(65.0, -65.0, 0.0), (0.0, 0.0, 0.0), (500.0, 0.0, 0.0)],  # no-fly zone, wall, outside
)
def test_unreachable_places_are_infeasible(planned: PlannedMotionPlanInfo, goal) -> None:  # type: ignore[no-untyped-def]
    assert not planned.query("h", (-60.0, 0.0, 0.0), goal).feasible


def test_task_planner_grounds_flights_with_the_path_planner(planned: PlannedMotionPlanInfo) -> None:
    # the leg II scenario moved into the small world: body1 is behind the wall, body2 in the
    # no-fly zone (no fly-to there), body3 and body4 in the open
    scenario = UAV_SCENARIO.read_text()
    for old, new in [
        ("(0, 0, 0)", "(-60, -20, 0)"), ("(60, -40, 0)", "(-60, 20, 0)"),
        ("(320, 140, 0)", "(60, 0, 0)"), ("(350, 210, 0)", "(65, -65, 0)"),
        ("(-180, 260, 0)", "(-80, -80, 0)"), ("(-150, 300, 0)", "(-80, 40, 0)"),
    ]:  # fmt: skip
        scenario = scenario.replace(old, new)
    tp = TaskPlanner(planned)
    domain, problem, _ = tp.read(
        PlanRequest(UAV_DOMAIN.read_text(), scenario, "", "d.tal", "p.tal")
    )
    task = tp.ground(domain, problem)
    fly = next(op for op in task.ops if op.label == "(fly-to heli1 supply1 body1)")
    info = planned.query("heli1", (-60.0, -20.0, 0.0), (60.0, 0.0, 0.0))
    assert fly.duration == pytest.approx(info.duration)
    assert not any("body2" in op.label for op in task.ops if op.name == "fly-to")
    assert any(op.label == "(fly-to heli1 supply1 body3)" for op in task.ops)
