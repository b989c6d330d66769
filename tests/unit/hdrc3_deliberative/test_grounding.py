from __future__ import annotations

import math

import pytest

from hdrc3_deliberative.errors import GroundingTimeout, PlanningInputError
from hdrc3_deliberative.generators import (
    LOGISTICS_DOMAIN,
    UAV_DOMAIN,
    UAV_SCENARIO,
    LogisticsSize,
    logistics_problem,
)
from hdrc3_deliberative.grounding import Grounder
from hdrc3_deliberative.motion_plan_info import StraightLineMotionPlanInfo
from hdrc3_deliberative.pddl import PddlReader
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_deliberative.task import Task

MINI = """domain mini
type place
type robot
predicate at(r: robot, p: place)
predicate linked(a: place, b: place)
function battery(r: robot)
operator go(r: robot, a: place, b: place)
  agent r
  duration 2
  pre at(r, a) and linked(a, b) and battery(r) >= 1
  effect [t'] not at(r, a), at(r, b), battery(r) -= 1
end
"""


def ground(domain: str, problem: str, planner: TaskPlanner | None = None) -> Task:
    tp = planner or TaskPlanner()
    d, p, _ = tp.read(PlanRequest(domain, problem, "", "d.tal", "p.tal"))
    return tp.ground(d, p)


def test_static_predicates_and_reachability_prune_instances() -> None:
    task = ground(
        MINI,
        "problem p for mini\nobject a, b, c, d: place\nobject r1: robot\n"
        "init at(r1, a), linked(a, b), linked(b, a), linked(c, d), battery(r1) = 3\n"
        "goal at(r1, b)\n",
    )
    labels = sorted(op.label for op in task.ops)
    # c -> d is linked but r1 can never reach c
    assert labels == ["(go r1 a b)", "(go r1 b a)"]
    assert "linked" in task.static_preds
    assert task.ops[0].duration == 2.0
    assert task.init_nums == (3.0,)


def test_logistics_drive_only_within_city() -> None:
    size = LogisticsSize(4, 3, 1, locations_per_city=3)
    task = ground(LOGISTICS_DOMAIN.read_text(), logistics_problem(size, seed=1))
    drives = [op for op in task.ops if op.name == "drive-truck"]
    # one truck per city, 3 places per city: 3 * 3 ordered pairs (including staying)
    assert len(drives) == size.cities * 9
    for op in drives:
        assert op.args[1].split("-")[0].removeprefix("pos").removeprefix("apt")[0] == op.args[3][3]


def test_flights_come_from_motion_plan_info() -> None:
    task = ground(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text())
    fly = next(op for op in task.ops if op.label == "(fly-to heli1 supply1 body1)")
    expected = math.dist((0, 0, 0), (320, 140, 0)) / 10.0 + 5.0
    assert fly.duration == pytest.approx(expected)
    short_range = TaskPlanner(StraightLineMotionPlanInfo(max_range=200.0))
    limited = ground(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text(), short_range)
    assert not any(op.label == "(fly-to heli1 supply1 body1)" for op in limited.ops)
    assert any(op.label == "(fly-to heli1 supply1 carrierdepot1)" for op in limited.ops)


def test_agents_are_exclusive_tokens() -> None:
    task = ground(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text())
    a = next(op for op in task.ops if op.label == "(pick-up-box heli1 food1 supply1)")
    b = next(op for op in task.ops if op.label == "(fly-to heli1 supply1 body1)")
    c = next(op for op in task.ops if op.label == "(fly-to heli2 supply1 body1)")
    assert a.writes & b.writes  # same agent
    assert not (b.writes & c.writes)


@pytest.mark.parametrize(
    ("domain", "problem", "message"),
    [
        (
            MINI.replace("at(r, a) and", "att(r, a) and"),
            "problem p for mini",
            "undefined predicate 'att'",
        ),
        (
            MINI.replace("r: robot, a: place", "r: robot, a: plaice"),
            "problem p for mini",
            "undefined type 'plaice'",
        ),
        (
            MINI,
            "problem p for mini\nobject r: robot\ninit at(r, nowhere)",
            "undefined object or variable 'nowhere'",
        ),
        (MINI, "problem p for mini\nobject r: robot\ninit at(r)", "takes 2 arguments, got 1"),
        (MINI, "problem p for other", "not 'mini'"),
        (MINI, "problem p for mini\nobject x: blob", "undefined type 'blob'"),
        (MINI.replace("type robot", "type robot: machine"), "problem p for mini", "'machine'"),
        (
            MINI,
            "problem p for mini\nobject a: place\nobject r: robot\ninit at(r, a), linked(a, a)",
            "no initial value",
        ),
        (
            MINI.replace("effect [t']", "effect [t'] speed(r) := 1,"),
            "problem p for mini",
            "undefined function 'speed'",
        ),
        (
            MINI.replace("agent r", "agent q"),
            "problem p for mini",
            "agent 'q' of 'go' is not a parameter",
        ),
    ],
)
def test_undefined_names_are_reported(domain: str, problem: str, message: str) -> None:
    with pytest.raises(PlanningInputError, match=message):
        ground(domain, problem)


def test_undefined_predicate_error_has_position() -> None:
    with pytest.raises(PlanningInputError) as err:
        ground(MINI.replace("at(r, a) and", "att(r, a) and"), "problem p for mini")
    assert str(err.value).startswith("d.tal:10:7:")


def test_flight_needs_positions() -> None:
    problem = UAV_SCENARIO.read_text().replace(
        "object body4: body @ (-150, 300, 0)", "object body4: body"
    )
    with pytest.raises(PlanningInputError, match="'body4' has no position"):
        ground(UAV_DOMAIN.read_text(), problem)


def test_grounder_rejects_nonpositive_duration() -> None:
    tp = TaskPlanner()
    d, p, _ = tp.read(
        PlanRequest(
            MINI.replace("duration 2", "duration 0"),
            "problem p for mini\nobject a, b: place\nobject r: robot\n"
            "init at(r, a), linked(a, b), battery(r) = 1",
        )
    )
    with pytest.raises(PlanningInputError, match="non-positive duration"):
        Grounder(d, p).ground()


def test_grounding_stops_at_the_deadline() -> None:
    """A clock past the deadline interrupts grounding; the planner reports TIMEOUT."""
    reader = PddlReader()
    domain = reader.read_domain(LOGISTICS_DOMAIN.read_text())
    problem = reader.read_problem(logistics_problem(LogisticsSize(30, 10, 3), 1))
    ticks = iter(range(10**9))
    with pytest.raises(GroundingTimeout):
        Grounder(domain, problem, deadline=3.0, clock=lambda: float(next(ticks))).ground()
    full = Grounder(domain, problem, deadline=100.0, clock=lambda: 0.0).ground()
    assert len(full.ops) > 1000
    text = logistics_problem(LogisticsSize(30, 10, 3), 1)
    result = TaskPlanner().plan(PlanRequest(LOGISTICS_DOMAIN.read_text(), text), timeout=0.0)
    assert result.status is PlanStatus.TIMEOUT and "grounding" in result.reason
