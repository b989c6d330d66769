"""A planned fly-to across revinge on the real node chain, with a no-fly zone declared mid-flight.

``hdrc3 tst run examples/tst/town_crossing.tst --launch`` flies uav0 from pad H1 through the town
(world_sim, control_kernel, platform_server, path_planner, tst_manager). When the aircraft is
west of the town, ``hdrc3 path gis add-zone`` closes a strip across its way. The recorded ground
truth of the flight is then checked with the independent audit (shapely footprints and heights):
it never comes near a building or the terrain, never enters the new zone or the fire training
ground, and the PFC never safety-braked. Every path the TST manager planned (``planned_path``) is
checked the same way, with the planner's margin.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hdrc3_base.stamps import stamp_s
from tests.integration.flight_runs import SEED, recorded

pytestmark = [pytest.mark.ros, pytest.mark.slow]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"
CLOSURE = [(150.0, -110.0), (175.0, -110.0), (175.0, 60.0), (150.0, 60.0)]
"""A strip across the east of the town (east 150-175 m, north -110..60 m): the way east."""
ADD_WHEN_EAST_OF = -150.0
"""The zone is declared once the aircraft flies east of this (m): well before the strip."""
MARGIN = 6.0
"""The path planner's safety margin (default)."""
CLEARANCE = 2.0
"""Least distance of the flown track to a building, trees or the terrain (planner margin 6 m)."""
WAIT_S = 600.0


def east_of(node: Any, executor: Any, frame: Any, bound: float, child: Any) -> None:
    """Spin until uav0's Data Interface says it flies east of ``bound`` (tst run still going)."""
    from hdrc3_interfaces.msg import HelicopterState
    from hdrc3_platform_server.node import STATE_QOS

    east: list[float] = []

    def on_state(msg: Any) -> None:
        if not msg.on_ground_flag:
            east.append(frame.to_enu(msg.longitude, msg.latitude, msg.altitude)[0])

    node.create_subscription(HelicopterState, "/uav0/helicopter_state", on_state, STATE_QOS)
    deadline = time.monotonic() + WAIT_S
    while not (east and east[-1] > bound):
        assert time.monotonic() < deadline, f"uav0 never flew east of {bound} m"
        assert child.proc.poll() is None, child.lines
        executor.spin_once(timeout_sec=0.2)
        child.poll_output(0)


@pytest.mark.timeout(900)
def test_a_fly_to_across_revinge_replans_around_a_zone_declared_in_flight(
    hdrc3_cli: Callable[..., Any], ros_domain: int, ros_context: Any, tmp_path: Path
) -> None:
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from hdrc3_navigation.audit import WorldAudit
    from hdrc3_navigation.messages import segment_from_msg
    from hdrc3_platform_server.geo_frame import frame_from_world
    from sim.world_loader import load_world

    out = tmp_path / "run"
    run = hdrc3_cli(
        "tst", "run", str(EXAMPLES / "town_crossing.tst"), "--launch", "--world", "revinge",
        "--out", str(out), "--domain-id", str(ros_domain), "--mission", "cross", "--seed", SEED,
    )  # fmt: skip
    node = Node("planned_flight_test", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    try:
        run.wait_for_line("uav0/cross fly-to running", timeout=WAIT_S)
        east_of(node, executor, frame_from_world("revinge"), ADD_WHEN_EAST_OF, run)
    finally:
        executor.shutdown()
        node.destroy_node()
    polygon = ";".join(f"{e},{n}" for e, n in CLOSURE)
    gis = hdrc3_cli("path", "gis", "add-zone", "--agent", "uav0", "--name", "closure",
                    "--polygon", polygon)  # fmt: skip
    assert gis.finish(timeout=60.0) == 0, gis.lines
    assert "add-zone closure: done" in "\n".join(gis.lines)

    code = run.finish(timeout=WAIT_S)
    text = "\n".join(run.lines)
    assert code == 0, text
    assert "mission cross succeeded" in text

    messages = recorded(
        out / "run.mcap",
        "/tst_status", "/uav0/ground_truth/state", "/uav0/platform_events", "/uav0/planned_path",
    )  # fmt: skip
    final = {s.node_id: s for s in messages["/tst_status"] if s.mission == "cross"}
    cross = final["cross"]  # times are mission seconds; the stamp is the sim time of the end
    end = stamp_s(cross.header.stamp)
    start = end - (cross.end - cross.start)
    track = np.array([
        m.position_enu for m in messages["/uav0/ground_truth/state"]
        if start + 5.0 <= stamp_s(m.header.stamp) <= end
    ])  # fmt: skip
    assert len(track) > 100
    world = load_world("revinge")
    zones = [("closure", tuple(CLOSURE), -1e3, 1e3)]
    assert WorldAudit(world, zones).check_points(track, CLEARANCE) == []
    assert track[:, 0].max() > 250.0  # it crossed the town to the east edge
    assert np.linalg.norm(track[-1] - np.array([275.0, 20.0, 20.0])) < 10.0
    # every planned path clears the world by the planner's margin; every replan the new zone too
    paths = [[segment_from_msg(m) for m in p.segments] for p in messages["/uav0/planned_path"]]
    assert len(paths) >= 2, "one plan, then at least one replan"
    first, *replans = paths
    assert WorldAudit(world).check_segments(first, MARGIN - 0.1) == []
    for path in replans:
        assert WorldAudit(world, zones).check_segments(path, MARGIN - 0.1) == []
    reasons = [e.reason for e in messages["/uav0/platform_events"]]
    assert not [r for r in reasons if "safety braking" in r], reasons
    replans = [line for line in run.lines if "cross/cross: replan" in line or "stop: " in line]
    assert replans, "the zone was declared on the path, but nothing was replanned"
    print("\n".join(replans))  # which way it replanned (shown with -s or on a failure)
