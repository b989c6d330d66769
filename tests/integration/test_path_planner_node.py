"""A launched path_planner node answers plan, motion_plan_info, gis_update and gis_elevation_map
over real DDS."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.integration.ros_wait import answer

pytestmark = pytest.mark.ros

WORLD = Path(__file__).parents[1] / "unit" / "hdrc3_navigation" / "small_world.toml"
AGENT = "uav0"
WAIT_S = 60.0
NAN = math.nan


def _call(node: Any, executor: Any, srv: Any, service: str, **fields: Any) -> Any:
    client = node.create_client(srv, f"/{AGENT}/path_planner/{service}")
    assert client.wait_for_service(timeout_sec=WAIT_S), f"{service} not discovered"
    request = srv.Request()
    for key, value in fields.items():
        setattr(request, key, value)
    response = answer(executor, client, request, WAIT_S)  # queries: sent again until answered
    assert response is not None, f"no answer from {service} within the bounded wait"
    return response


def _plan_fields(start: tuple[float, ...], goal: tuple[float, ...], **extra: Any) -> dict[str, Any]:
    from geometry_msgs.msg import Point

    fields: dict[str, Any] = {
        "start": Point(x=start[0], y=start[1], z=start[2]),
        "goal": Point(x=goal[0], y=goal[1], z=goal[2]),
        "speed": 8.0,
        "min_altitude": NAN,
        "max_altitude": NAN,
        "max_climb_rate": NAN,
        "max_descent_rate": NAN,
        "timeout": 10.0,
    }
    fields.update(extra)
    return fields


@pytest.mark.slow
def test_plan_service_of_a_launched_node(
    hdrc3_cli: Callable[..., Any],
    ros_context: Any,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from hdrc3_interfaces.msg import GisState
    from hdrc3_interfaces.srv import GisElevationMap, GisUpdate, MotionPlanInfo, PlanPath
    from hdrc3_navigation.audit import WorldAudit
    from hdrc3_navigation.elevation_map import ElevationMap
    from hdrc3_navigation.messages import elevation_map_to_msg, segment_from_msg, world_from_msg
    from hdrc3_navigation.node import GIS_STATE_QOS
    from sim.world_loader import load_world

    monkeypatch.setenv("HDRC3_CACHE_DIR", str(tmp_path))
    launch = hdrc3_cli(
        "launch", "--agents", AGENT, "--nodes", "path_planner", "--world", str(WORLD)
    )
    launch.wait_for_line("READY", timeout=90)
    node = Node("path_client", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    try:
        west, east = (-60.0, 0.0, 15.0), (60.0, 0.0, 15.0)
        answer = _call(node, executor, PlanPath, "plan", **_plan_fields(west, east))
        assert answer.status == PlanPath.Response.STATUS_SOLVED, answer.reason
        assert answer.status_name == "solved" and answer.planning_time > 0.0
        segments = [segment_from_msg(s) for s in answer.segments]
        assert segments[0].start == west and segments[-1].end == east
        assert sum(s.arc_length() for s in segments) == pytest.approx(answer.length, rel=1e-6)
        assert WorldAudit(load_world(WORLD)).check_segments(segments, 5.9) == []

        # a no-fly zone added at runtime (with the CLI) is published on gis_state (latched) and
        # honoured by the next query
        worlds: list[Any] = []
        node.create_subscription(
            GisState, f"/{AGENT}/path_planner/gis_state",
            lambda m: worlds.append(world_from_msg(m)), GIS_STATE_QOS,
        )  # fmt: skip
        gis = hdrc3_cli(
            "path", "gis", "add-zone", "--agent", AGENT, "--name", "fire",
            "--polygon", "50,-10;70,-10;70,10;50,10", "--floor=-10", "--ceiling", "100",
        )  # fmt: skip
        assert gis.finish(timeout=WAIT_S) == 0, gis.lines
        assert "add-zone fire: done: GIS revision" in "\n".join(gis.lines)
        deadline = time.monotonic() + WAIT_S
        while not any(w.no_fly_zones for w in worlds):
            assert time.monotonic() < deadline, "no gis_state with the new zone"
            executor.spin_once(timeout_sec=0.2)
        (fire,) = worlds[-1].no_fly_zones
        assert (fire.name, fire.floor, fire.ceiling) == ("fire", -10.0, 100.0)
        assert worlds[-1].revision > 0
        blocked = _call(node, executor, PlanPath, "plan", **_plan_fields(west, east))
        assert blocked.status == PlanPath.Response.STATUS_GOAL_IN_NO_FLY_ZONE
        assert "fire" in blocked.reason and not blocked.segments

        info = _call(
            node, executor, MotionPlanInfo, "motion_plan_info",
            **{k: v for k, v in _plan_fields(west, (80.0, 20.0, 15.0)).items()
               if k in ("start", "goal", "speed", "timeout")},
        )  # fmt: skip
        assert info.feasible and info.length > 120.0 and info.duration > info.length / 8.0
        assert info.energy > 0.0

        # malformed requests are answered, and the node keeps serving
        bad = _call(node, executor, PlanPath, "plan", **_plan_fields(west, east, planner="astar"))
        assert bad.status == PlanPath.Response.STATUS_INVALID and "astar" in bad.reason
        bad = _call(
            node, executor, PlanPath, "plan",
            **_plan_fields(west, east, no_fly_sizes=[3], no_fly_east=[0.0], no_fly_north=[0.0]),
        )  # fmt: skip
        assert bad.status == PlanPath.Response.STATUS_INVALID
        bad_zone = _call(
            node, executor, GisUpdate, "gis_update",
            operation=GisUpdate.Request.REMOVE_OBSTACLE, name="nothing",
        )  # fmt: skip
        assert not bad_zone.success and "nothing" in bad_zone.reason

        # a laser elevation map (§11.2) is stored in the GIS and named on gis_state; a malformed
        # one is refused with the reason
        heights = np.zeros((30, 30))  # east -95..-65, north 20..50, a 10 m block in it
        heights[10:15, 10:15] = 10.0
        scan = elevation_map_to_msg(ElevationMap("scan", -95.0, 20.0, 1.0, heights))
        before = worlds[-1].revision
        stored = _call(node, executor, GisElevationMap, "gis_elevation_map", map=scan)
        assert stored.success, stored.reason
        assert stored.triangles == 2 * 30 * 30 and stored.revision > before  # two per cell
        deadline = time.monotonic() + WAIT_S
        while "scan" not in worlds[-1].elevation_maps:
            assert time.monotonic() < deadline, "no gis_state with the elevation map"
            executor.spin_once(timeout_sec=0.2)
        scan.heights = scan.heights[:-1]
        refused = _call(node, executor, GisElevationMap, "gis_elevation_map", map=scan)
        assert not refused.success and "899 heights" in refused.reason
        assert refused.triangles == 0 and refused.revision >= stored.revision
        again = _call(node, executor, PlanPath, "plan", **_plan_fields(west, (80.0, 20.0, 15.0)))
        assert again.status == PlanPath.Response.STATUS_SOLVED, again.reason
    finally:
        executor.shutdown()
        node.destroy_node()
    assert launch.interrupt(timeout=30.0) == 0
