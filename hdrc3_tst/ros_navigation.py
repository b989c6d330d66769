"""The executors' navigation port over ROS: one agent's ``path_planner`` node (§7).

Queries go to ``/<agent>/path_planner/plan`` asynchronously; a query made before the service is
up waits (a planner node may still be loading its roadmap) and is sent once it is, the
executor's own bound deciding how long that may take. The runtime world model is followed on
the planner's latched ``gis_state`` topic.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from rclpy.node import Node

from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import SERVICE_QOS
from hdrc3_interfaces.msg import GisState
from hdrc3_interfaces.srv import PlanPath
from hdrc3_navigation.messages import point_msg, segment_from_msg, vector_msg, world_from_msg
from hdrc3_navigation.node import GIS_STATE_QOS
from hdrc3_navigation.planner import PlanRequest, PlanResult, PlanStatus
from hdrc3_navigation.runtime_world import RuntimeWorld
from hdrc3_tst.navigation_port import PlanJob

RETRY_PERIOD_S = 0.2
"""How often queries waiting for the service are retried (wall seconds)."""


class RosNavigation:
    """:class:`~hdrc3_tst.navigation_port.NavigationPort` of ``agent`` for a node's executor."""

    def __init__(self, node: Node, agent: str, on_change: Callable[[], None]) -> None:
        """Create the plan client and follow the planner's world model.

        Args:
            node: The node whose executor runs the callbacks.
            agent: Whose path planner to use.
            on_change: Called when an answer or a world model arrives (the manager ticks).
        """
        self._on_change = on_change
        self._client = node.create_client(
            PlanPath, f"/{agent}/path_planner/plan", qos_profile=SERVICE_QOS
        )
        self._world = RuntimeWorld()
        self._waiting: list[PlanJob] = []
        node.create_subscription(
            GisState, f"/{agent}/path_planner/gis_state", self._on_world, GIS_STATE_QOS
        )
        node.create_timer(RETRY_PERIOD_S, self._send_waiting)

    def plan(self, request: PlanRequest) -> PlanJob:
        """Send the query now, or as soon as the planner's service is up."""
        job = PlanJob(request)
        self._waiting.append(job)
        self._send_waiting()
        return job

    def world(self) -> RuntimeWorld:
        """The latest runtime world model the planner published."""
        return self._world

    def _send_waiting(self) -> None:
        if not self._waiting or not self._client.service_is_ready():
            return
        for job in self._waiting:
            future: Any = self._client.call_async(request_msg(job.request))  # untyped Future
            future.add_done_callback(lambda f, job=job: self._answered(job, f.result()))
        self._waiting.clear()

    def _answered(self, job: PlanJob, response: Any) -> None:
        job.result = result_from_msg(response)
        self._on_change()

    def _on_world(self, msg: Any) -> None:
        self._world = world_from_msg(msg)
        self._on_change()


def request_msg(request: PlanRequest) -> Any:
    """``PlanPath.Request`` of a query (no runtime constraints: the planner's own world)."""
    nan = math.nan
    return PlanPath.Request(
        start=point_msg(request.start),
        goal=point_msg(request.goal),
        start_direction=vector_msg(request.start_direction or (0.0, 0.0, 0.0)),
        speed=float(request.speed),
        min_altitude=nan,
        max_altitude=nan,
        max_climb_rate=nan,
        max_descent_rate=nan,
        planner=request.planner.value,
        criterion=request.criterion.value,
        timeout=float(request.timeout),
    )


def result_from_msg(response: Any) -> PlanResult:
    """A ``PlanPath.Response`` as a result (a malformed answer is INVALID with the reason)."""
    try:
        status = PlanStatus(response.status_name)
        segments = tuple(segment_from_msg(m, i) for i, m in enumerate(response.segments))
    except (ValueError, ConfigError) as exc:
        return PlanResult(PlanStatus.INVALID, f"malformed planner answer: {exc}")
    return PlanResult(
        status,
        str(response.reason),
        segments,
        float(response.length),
        float(response.duration),
        planning_time=float(response.planning_time),
    )
