"""ROS 2 adapter: the ``path_planner`` node (one per agent namespace).

Services (private names, e.g. ``/uav1/path_planner/plan``):

- ``~/plan`` (``PlanPath``): a segmented cubic path or a status with a reason;
- ``~/motion_plan_info`` (``MotionPlanInfo``): feasibility, length, duration, energy (§9.2);
- ``~/gis_update`` (``GisUpdate``): add/remove a no-fly zone or an obstacle at runtime;
- ``~/gis_elevation_map`` (``GisElevationMap``): store a laser elevation map (§11.2) in the GIS
  (replacing a map of the same name); later plans keep the margin from its surface.

Topic ``~/gis_state`` (``GisState``, reliable, transient local): what changed at runtime (and
the names of the elevation maps stored), after every update, so that a fly-to executor can tell
whether the path it flies is still valid (§7).

Parameters: ``world`` (shipped name or .toml path), ``margin`` (m), ``cache_dir`` (roadmap cache,
"" = default), ``roadmap_nodes``, ``max_timeout`` (s). The roadmap is loaded (or built) at start.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rclpy.context import Context
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.ros_runtime import run_node
from hdrc3_interfaces.msg import GisState
from hdrc3_interfaces.srv import GisElevationMap, GisUpdate, MotionPlanInfo, PlanPath
from hdrc3_navigation.constraints import Constraints
from hdrc3_navigation.cost import Criterion
from hdrc3_navigation.gis import DEFAULT_MARGIN, Zone
from hdrc3_navigation.messages import (
    elevation_map_from_msg,
    segment_to_msg,
    triple,
    world_to_msg,
)
from hdrc3_navigation.planner import PathPlanner, PlannerKind, PlanRequest, PlanResult, PlanStatus
from hdrc3_navigation.runtime_world import RuntimeWorld
from sim.world_loader import load_world

GIS_STATE_QOS = QoSProfile(
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
"""Latched: a subscriber that joins late gets the current runtime world model."""

STATUS_CODES: dict[PlanStatus, int] = {
    PlanStatus.SOLVED: PlanPath.Response.STATUS_SOLVED,
    PlanStatus.NO_PATH: PlanPath.Response.STATUS_NO_PATH,
    PlanStatus.TIMEOUT: PlanPath.Response.STATUS_TIMEOUT,
    PlanStatus.INVALID: PlanPath.Response.STATUS_INVALID,
    PlanStatus.START_OUTSIDE_WORLD: PlanPath.Response.STATUS_START_OUTSIDE_WORLD,
    PlanStatus.GOAL_OUTSIDE_WORLD: PlanPath.Response.STATUS_GOAL_OUTSIDE_WORLD,
    PlanStatus.START_IN_OBSTACLE: PlanPath.Response.STATUS_START_IN_OBSTACLE,
    PlanStatus.GOAL_IN_OBSTACLE: PlanPath.Response.STATUS_GOAL_IN_OBSTACLE,
    PlanStatus.START_IN_NO_FLY_ZONE: PlanPath.Response.STATUS_START_IN_NO_FLY_ZONE,
    PlanStatus.GOAL_IN_NO_FLY_ZONE: PlanPath.Response.STATUS_GOAL_IN_NO_FLY_ZONE,
}


def _limit(value: float) -> float | None:
    return None if math.isnan(value) else float(value)


def _polygons(
    sizes: Sequence[int], east: Sequence[float], north: Sequence[float]
) -> tuple[tuple[tuple[float, float], ...], ...]:
    if len(east) != len(north) or sum(sizes) != len(east):
        raise ValueError(
            f"no-fly polygons: {len(east)} east and {len(north)} north values for sizes "
            f"{list(sizes)}"
        )
    out, i = [], 0
    for n in sizes:
        out.append(tuple((float(east[i + k]), float(north[i + k])) for k in range(n)))
        i += n
    return tuple(out)


def request_from_msg(request: Any) -> PlanRequest:
    """Build a :class:`PlanRequest`; ValueError with a reason on malformed fields."""
    try:
        planner = PlannerKind(request.planner or "prm+rrt")
    except ValueError:
        raise ValueError(f"unknown planner {request.planner!r}: prm, rrt or prm+rrt") from None
    try:
        criterion = Criterion(request.criterion or "length")
    except ValueError:
        raise ValueError(
            f"unknown criterion {request.criterion!r}: length, time or energy"
        ) from None
    constraints = Constraints(
        _limit(request.min_altitude),
        _limit(request.max_altitude),
        _limit(request.max_climb_rate),
        _limit(request.max_descent_rate),
        _polygons(request.no_fly_sizes, request.no_fly_east, request.no_fly_north),
    )
    direction = triple(request.start_direction)
    return PlanRequest(
        triple(request.start),
        triple(request.goal),
        request.speed,
        constraints,
        planner,
        request.timeout,
        criterion,
        direction if any(direction) else None,
    )


class PathPlannerNode(Node):
    """Answers path-planning, motion-plan-info and GIS-update requests for one agent."""

    def __init__(self, context: Context | None = None, planner: PathPlanner | None = None):
        super().__init__("path_planner", context=context)
        world = str(self.declare_parameter("world", "revinge").value)
        margin = float(self.declare_parameter("margin", DEFAULT_MARGIN).value)
        cache_dir = str(self.declare_parameter("cache_dir", "").value)
        nodes = int(self.declare_parameter("roadmap_nodes", 2000).value)
        self._max_timeout = float(self.declare_parameter("max_timeout", 30.0).value)
        if planner is None:
            planner = PathPlanner(
                load_world(world), Path(cache_dir) if cache_dir else None, margin, nodes
            )
        self.planner = planner
        roadmap, built = planner.roadmap()
        self.get_logger().info(
            f"roadmap {'built' if built else 'loaded'}: {roadmap.size[0]} nodes, "
            f"{roadmap.size[1]} edges"
        )
        self.create_service(PlanPath, "~/plan", self._on_plan)
        self.create_service(MotionPlanInfo, "~/motion_plan_info", self._on_info)
        self.create_service(GisUpdate, "~/gis_update", self._on_gis_update)
        self.create_service(GisElevationMap, "~/gis_elevation_map", self._on_gis_elevation_map)
        self._gis_pub = self.create_publisher(GisState, "~/gis_state", GIS_STATE_QOS)
        self._gis_pub.publish(world_to_msg(RuntimeWorld.of(planner.gis)))

    def _run(self, request: PlanRequest) -> PlanResult:
        if request.timeout > self._max_timeout:
            return PlanResult(
                PlanStatus.INVALID,
                f"timeout {request.timeout} s exceeds max_timeout {self._max_timeout} s",
            )
        try:
            return self.planner.plan(request)
        except Exception as exc:  # the node must survive any request; the reason is returned
            self.get_logger().error(f"planner failed on a request: {exc!r}")
            return PlanResult(PlanStatus.INVALID, f"internal planner error: {exc!r}")

    def _on_plan(self, request: Any, response: Any) -> Any:
        try:
            result = self._run(request_from_msg(request))
        except (ValueError, Hdrc3Error) as exc:
            result = PlanResult(PlanStatus.INVALID, str(exc))
        response.status = STATUS_CODES[result.status]
        response.status_name = result.status.value
        response.reason = result.reason
        response.segments = [segment_to_msg(s) for s in result.segments]
        response.length = result.length
        response.duration = result.duration
        response.planning_time = result.planning_time
        self.get_logger().info(
            f"plan: {result.status.value} ({result.reason}) in {result.planning_time * 1e3:.0f} ms"
        )
        return response

    def _on_info(self, request: Any, response: Any) -> Any:
        plan_request = PlanRequest(
            (request.start.x, request.start.y, request.start.z),
            (request.goal.x, request.goal.y, request.goal.z),
            request.speed,
            timeout=request.timeout,
        )
        result = self._run(plan_request)
        response.feasible = result.ok
        response.status = STATUS_CODES[result.status]
        response.reason = result.reason
        response.length = result.length
        response.duration = result.duration
        response.energy = result.energy
        return response

    def _on_gis_update(self, request: Any, response: Any) -> Any:
        gis = self.planner.gis
        polygon = tuple(zip(request.polygon_east, request.polygon_north, strict=False))
        try:
            if len(request.polygon_east) != len(request.polygon_north):
                raise ValueError("polygon_east and polygon_north differ in length")
            if not request.name:
                raise ValueError("a name is required")
            op = request.operation
            if op == GisUpdate.Request.ADD_NO_FLY_ZONE:
                gis.add_no_fly_zone(Zone(request.name, polygon, request.floor, request.ceiling))
            elif op == GisUpdate.Request.REMOVE_NO_FLY_ZONE:
                gis.remove_no_fly_zone(request.name)
            elif op == GisUpdate.Request.ADD_OBSTACLE:
                gis.add_obstacle(request.name, polygon, request.floor, request.ceiling)
            elif op == GisUpdate.Request.REMOVE_OBSTACLE:
                gis.remove_obstacle(request.name)
            else:
                raise ValueError(f"unknown operation {op}")
        except (ValueError, Hdrc3Error) as exc:
            response.success = False
            response.reason = str(exc)
            return response
        response.success = True
        response.reason = f"GIS revision {gis.revision}"
        self._gis_pub.publish(world_to_msg(RuntimeWorld.of(gis)))
        return response

    def _on_gis_elevation_map(self, request: Any, response: Any) -> Any:
        gis = self.planner.gis
        parsed = elevation_map_from_msg(request.map)
        try:
            if isinstance(parsed, str):
                raise ValueError(parsed)
            triangles = gis.add_elevation_map(parsed)
        except (ValueError, Hdrc3Error) as exc:
            self.get_logger().warning(f"elevation map refused: {exc}")
            response.success = False
            response.reason = str(exc)
            response.triangles = 0
            response.revision = gis.revision
            return response
        response.success = True
        response.reason = (
            f"elevation map {parsed.name!r}: {triangles} triangles, GIS revision {gis.revision}"
        )
        response.triangles = triangles
        response.revision = gis.revision
        self.get_logger().info(response.reason)
        self._gis_pub.publish(world_to_msg(RuntimeWorld.of(gis)))
        return response


def main(argv: Sequence[str] | None = None) -> int:
    """Run the path planner node until shutdown."""
    return run_node(PathPlannerNode, argv)


if __name__ == "__main__":
    sys.exit(main())
