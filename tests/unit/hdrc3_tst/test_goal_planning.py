"""Goal nodes as planning problems, and plans as steps; the problem solves with TALplanner."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_tst.goal_planning import StepsStatus, domain_text, goal_problem, plan_steps
from hdrc3_tst.model import Node, NodeKind

GOAL = Node("g", NodeKind.GOAL, {}, action="at", goal_args=("uav0", "Square"))
POINTS = {"Square": (100.0, 50.0, 30.0), "Depot": (10.0, 20.0, 25.0)}


def test_the_problem_names_where_the_aircraft_is_and_every_point() -> None:
    problem = goal_problem(GOAL, "uav0", (-150.0, 0.0, 30.0), POINTS)
    assert problem.splitlines() == [
        "problem goal_g for uav-logistics",
        "object here_uav0: location @ (-150.000, 0.000, 30.000)",
        "object Depot: location @ (10.000, 20.000, 25.000)",
        "object Square: location @ (100.000, 50.000, 30.000)",
        "object uav0: helicopter",
        "init at(uav0, here_uav0), free(uav0), hovering(uav0), lift-capacity(uav0) = 30, "
        "fuel(uav0) = 3000",
        "goal at(uav0, Square)",
    ]


def test_talplanner_solves_it_with_one_fly_to() -> None:
    problem = goal_problem(GOAL, "uav0", (-150.0, 0.0, 30.0), POINTS)
    result = TaskPlanner().plan(PlanRequest(domain_text(), problem, ""), timeout=30.0)
    assert result.status is PlanStatus.SOLVED
    steps = plan_steps(
        [o.label for o in result.plan],
        [o.agent or "" for o in result.plan],
        [o.start for o in result.plan],
        [o.duration for o in result.plan],
    )
    assert steps.status is StepsStatus.OK
    assert [(s.action, s.agent, dict(s.args)) for s in steps.steps] == [
        ("fly-to", "uav0", {"destination": "Square"})
    ]


@pytest.mark.parametrize(
    ("label", "reason"),
    [
        ("(drop-box uav0 b1 Sq)", "the plan needs (drop-box uav0 b1 Sq), and no RMAX executor"),
        ("()", "empty plan action '()'"),
    ],
)
def test_plans_with_actions_nobody_executes_are_refused(label: str, reason: str) -> None:
    steps = plan_steps([label], ["uav0"], [0.0], [1.0])
    assert steps.status is StepsStatus.NOT_EXECUTABLE
    assert steps.reason.startswith(reason)
