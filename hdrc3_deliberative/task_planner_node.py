"""ROS 2 adapter: the ``task_planner`` node offering TALplanner as the ``plan`` service."""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from typing import Any

from rclpy.context import Context
from rclpy.node import Node

from hdrc3_base.ros_runtime import run_node
from hdrc3_deliberative.motion_plan_info import PlannedMotionPlanInfo
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanResult, PlanStatus
from hdrc3_interfaces.srv import Plan
from hdrc3_navigation.planner import PathPlanner
from sim.world_loader import load_world

_STATUS = {
    PlanStatus.SOLVED: Plan.Response.STATUS_SOLVED,
    PlanStatus.UNSOLVABLE_PROVEN: Plan.Response.STATUS_UNSOLVABLE,
    PlanStatus.TIMEOUT: Plan.Response.STATUS_TIMEOUT,
    PlanStatus.INVALID_INPUT: Plan.Response.STATUS_INVALID_INPUT,
}


class TaskPlannerNode(Node):
    """Answers ``plan`` requests; bad requests get STATUS_INVALID_INPUT and a reason."""

    def __init__(
        self,
        context: Context | None = None,
        planner: TaskPlanner | None = None,
        namespace: str | None = None,
    ) -> None:
        """Serve ``plan`` (in ``namespace``, e.g. an agent's, when given)."""
        super().__init__("task_planner", context=context, namespace=namespace)
        world = str(self.declare_parameter("world", "").value)
        if planner is None:
            motion = None
            if world:  # flights planned by the path planner in this world (§9.2, Figure 27)
                motion = PlannedMotionPlanInfo(PathPlanner(load_world(world)))
                self.get_logger().info(f"motion plan info: path planner in world {world!r}")
            planner = TaskPlanner(motion)
        self._planner = planner
        self._max_timeout = float(self.declare_parameter("max_timeout", 120.0).value)
        self.create_service(Plan, "plan", self._on_plan)

    def _on_plan(self, request: Any, response: Any) -> Any:
        timeout = request.timeout
        if not math.isfinite(timeout) or timeout <= 0.0:
            return _reject(
                response, f"timeout must be a positive finite number of seconds, got {timeout}"
            )
        if timeout > self._max_timeout:
            return _reject(
                response, f"timeout {timeout} s exceeds max_timeout {self._max_timeout} s"
            )
        if not request.domain.strip() or not request.problem.strip():
            return _reject(response, "domain and problem texts must not be empty")
        plan_request = PlanRequest(request.domain, request.problem, request.control)
        try:
            result = self._planner.plan(
                plan_request, timeout=timeout, sequential=request.sequential
            )
        except Exception as exc:  # the node must survive any request; the reason is returned
            self.get_logger().error(f"planner failed on a request: {exc!r}")
            return _reject(response, f"internal planner error: {exc!r}")
        self.get_logger().info(
            f"plan request: {result.status.value}, {len(result.plan)} actions, "
            f"makespan {result.makespan:.3f}"
        )
        return _fill(response, result)


def _reject(response: Any, reason: str) -> Any:
    response.status = Plan.Response.STATUS_INVALID_INPUT
    response.reason = reason
    return response


def _fill(response: Any, result: PlanResult) -> Any:
    response.status = _STATUS[result.status]
    response.reason = result.reason
    response.plan = result.ipc_lines()
    response.actions = [occ.label for occ in result.plan]
    response.agents = [occ.agent or "" for occ in result.plan]
    response.starts = [occ.start for occ in result.plan]
    response.durations = [occ.duration for occ in result.plan]
    response.makespan = result.makespan
    response.nodes_expanded = min(result.stats.nodes_expanded, 2**32 - 1)
    response.pruned_by_control = min(result.stats.pruned_by_control, 2**32 - 1)
    response.planning_time = result.stats.grounding_seconds + result.stats.search_seconds
    return response


def main(argv: Sequence[str] | None = None) -> int:
    """Run the task planner node until shutdown."""
    return run_node(TaskPlannerNode, argv)


if __name__ == "__main__":
    sys.exit(main())
