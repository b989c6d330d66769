"""The task_planner node answers plan requests over real rclpy/DDS (in-process)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from hdrc3_deliberative.generators import (
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    LogisticsSize,
    logistics_problem,
)

pytestmark = pytest.mark.ros

WAIT_S = 30.0


@pytest.fixture
def planner_client(ros_context: Any) -> Iterator[tuple[Any, Any]]:
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from hdrc3_deliberative.task_planner_node import TaskPlannerNode
    from hdrc3_interfaces.srv import Plan

    server = TaskPlannerNode(context=ros_context)
    client_node = Node("plan_client", context=ros_context)
    client = client_node.create_client(Plan, "plan")
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(server)
    executor.add_node(client_node)
    try:
        yield executor, client
    finally:
        executor.shutdown()
        client_node.destroy_node()
        server.destroy_node()


def _call(executor: Any, client: Any, **fields: Any) -> Any:
    from hdrc3_interfaces.srv import Plan

    # a request sent before the client has matched the server is lost: wait for the match
    assert client.wait_for_service(timeout_sec=WAIT_S), "plan service not discovered"
    request = Plan.Request()
    request.timeout = 20.0
    for key, value in fields.items():
        setattr(request, key, value)
    future = client.call_async(request)
    executor.spin_until_future_complete(future, timeout_sec=WAIT_S)
    assert future.done(), "no answer within the bounded wait"
    return future.result()


def test_solves_uav_scenario(planner_client: tuple[Any, Any]) -> None:
    from hdrc3_interfaces.srv import Plan

    executor, client = planner_client
    response = _call(
        executor,
        client,
        domain=UAV_DOMAIN.read_text(),
        problem=UAV_SCENARIO.read_text(),
        control=UAV_CONTROL.read_text(),
    )
    assert response.status == Plan.Response.STATUS_SOLVED, response.reason
    assert len(response.plan) == len(response.actions) == len(response.starts) > 0
    assert set(response.agents) == {"heli1", "heli2"}
    assert response.makespan == pytest.approx(
        max(s + d for s, d in zip(response.starts, response.durations, strict=True))
    )


def test_logistics_plan_validates(planner_client: tuple[Any, Any]) -> None:
    from hdrc3_deliberative.result import Occurrence
    from hdrc3_deliberative.validation import validate_pddl_plan
    from hdrc3_interfaces.srv import Plan

    executor, client = planner_client
    problem = logistics_problem(LogisticsSize(6, 3, 1), seed=4)
    domain = LOGISTICS_DOMAIN.read_text()
    response = _call(
        executor, client, domain=domain, problem=problem, control=LOGISTICS_CONTROL.read_text()
    )
    assert response.status == Plan.Response.STATUS_SOLVED, response.reason
    plan = tuple(
        Occurrence(s, s + d, label.strip("()").split()[0], tuple(label.strip("()").split()[1:]))
        for label, s, d in zip(response.actions, response.starts, response.durations, strict=True)
    )
    assert validate_pddl_plan(domain, problem, plan).valid


@pytest.mark.parametrize(
    ("fields", "reason_part"),
    [
        ({"domain": "(define (domain x", "problem": "(define)"}, "end of file"),
        ({"domain": "", "problem": ""}, "must not be empty"),
        ({"domain": "domain d", "problem": "problem p for d", "timeout": -1.0}, "timeout"),
        ({"domain": "domain d", "problem": "problem p for d", "timeout": float("nan")}, "timeout"),
        (
            {
                "domain": "(define (domain d) (:requirements :timed-initial-literals))",
                "problem": "(define (problem p) (:domain d))",
            },
            ":timed-initial-literals",
        ),
    ],
)
def test_bad_requests_get_reasons_and_node_survives(
    planner_client: tuple[Any, Any], fields: dict[str, Any], reason_part: str
) -> None:
    from hdrc3_interfaces.srv import Plan

    executor, client = planner_client
    response = _call(executor, client, **fields)
    assert response.status == Plan.Response.STATUS_INVALID_INPUT
    assert reason_part in response.reason
    # the node still answers afterwards
    again = _call(
        executor,
        client,
        domain=UAV_DOMAIN.read_text(),
        problem=UAV_SCENARIO.read_text(),
        control=UAV_CONTROL.read_text(),
    )
    assert again.status == Plan.Response.STATUS_SOLVED
