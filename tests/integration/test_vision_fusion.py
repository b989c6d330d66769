"""Vision fixes in the control kernel's Kalman filter, on the real node chain (chapter §5.4).

Launched with the cameras: take off from H1, fly 12 m over the vision pad L1 (the e2e check's
``traj3d_flyto``), point the camera down (``ppcl turn_to 0 90``) and engage state estimation.
The pad_pose node turns each image into a helicopter fix; the control kernel fuses them.

Bounds. The filter's solution before the pad is seen is GPS/INS: the simulated GPS has a
Gauss-Markov error of 1.5 m per horizontal axis (``sim/sensors/gps.py``) and the height is the
barometer's, referenced on the ground before take-off (0.3 m noise, weather drift). So the fused
(vision) solution may differ from the GPS/INS one by up to 3 sigma of the GPS horizontally
(4.5 m) and 1.5 m vertically; and it must be much better than GPS against the ground truth:
a fix 12.5 m from the pad is within 0.2 m with 99 % (3.37 x ``fix_sigma`` = 6 cm,
``bench/landing.py``), and between fixes the filter dead-reckons: on the loaded machine the
renderer skips exposures (world_render never holds the simulation), so fixes can be a second or
two apart, 0.15-0.6 m of drift for 1-3 s (``test_state_estimator.py``). Hence at most 0.5 m
off the truth, 0.3 m on average over the last 2 s (measured: 0.09-0.11 m mean alone, 0.24-0.34
m while other launches ran on the two cores).

Then ``fcl land 30`` from there (§5.4): the landing mode sees fresh fixes (or, when the last one
is over a second old, finds the pattern in a short search) and the pad within 20 m, lands on
the pad's centre, holds the position on the fixes down to the skids, and its FCL_FINISHED says
so. The touchdown (ground truth, the centre of gravity) is within
``TOUCHDOWN_BOUND`` of the pad's centre (the issue's mean target is 0.2 m, `bench/landing.py`
measures the mean of many; the chapter's own was 0.42 m).
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String

from hdrc3.cli.main import main as hdrc3_main
from hdrc3_perception.node import RESULT_QOS
from sim.world_loader import load_world
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros

OVER_L1 = ("13.466580713", "55.698544926", "107.0", "3")
"""lon, lat, altitude (m WGS84), speed (m/s): 12 m over the vision pad L1."""
GPS_BOUND_H = 4.5
"""3 sigma of the simulated GPS's horizontal error per axis (1.5 m)."""
BARO_BOUND_V = 1.5
TRUTH_BOUND = 0.5
TRUTH_MEAN_BOUND = 0.3
TOUCHDOWN_BOUND = 0.5
FIXES_WAIT_S = 300.0
"""Wall-clock bound (s) on waiting for vision fixes: the camera renders at wall-clock pace."""


def _stamp(msg: Any) -> float:
    return float(msg.header.stamp.sec) + 1e-9 * float(msg.header.stamp.nanosec)


def test_vision_fixes_are_fused_over_the_pad_and_land_the_aircraft_on_it(
    hdrc3_cli: Any, ros_context: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    from hdrc3_interfaces.msg import PfcState, TruthState

    launch = hdrc3_cli(
        "launch", "--agents", "uav0", "--speed", "2", "--cameras",
        "--nodes", "world_sim,control_kernel,platform_server,perception_kernel",
    )  # fmt: skip
    launch.wait_for_line("READY", timeout=120)
    node = Node("vision_fusion_test", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    pfc: list[Any] = []
    truth: list[Any] = []
    aiding: list[dict[str, Any]] = []
    fixes: list[dict[str, Any]] = []
    node.create_subscription(PfcState, "/uav0/pfc/state", pfc.append, 50)
    node.create_subscription(TruthState, "/uav0/ground_truth/state", truth.append, 50)
    node.create_subscription(
        String, "/uav0/pfc/aiding", lambda m: aiding.append(json.loads(m.data)), 10
    )
    node.create_subscription(
        String, "/uav0/pad_pose/result",
        lambda m: fixes.append(json.loads(m.data)) if "fix" in m.data else None, RESULT_QOS,
    )  # fmt: skip
    assert hdrc3_main(["rc", "uav0", "--engine", "on", "--mode", "autonomous"]) == 0
    ready = spin_until(
        executor,
        lambda: bool(pfc) and pfc[-1].auto_flag and pfc[-1].mode == PfcState.MODE_GROUND_IDLE,
        90.0,
    )
    assert ready, pfc[-1:] or "no pfc/state"
    assert hdrc3_main(["fcl", "uav0", "takeoff", "--timeout", "120"]) == 0
    assert hdrc3_main(["fcl", "uav0", "traj3d_flyto", *OVER_L1, "--timeout", "120"]) == 0
    assert hdrc3_main(["ppcl", "uav0", "request", "ptu", "--owner", "test"]) == 0
    assert hdrc3_main(["ppcl", "uav0", "turn_to", "0", "90", "--timeout", "60"]) == 0
    spin_until(executor, lambda: False, 0.5)
    assert aiding and "vision" not in aiding[-1]["used"], aiding[-1:]
    gps_ins = np.array(pfc[-1].position_enu)  # the filter's GPS/INS solution, hovering
    engaged_at = _stamp(pfc[-1])

    assert hdrc3_main(["ppcl", "uav0", "request", "ip", "--owner", "test"]) == 0
    assert hdrc3_main(["ppcl", "uav0", "ip_state_estimation", "--timeout", "60"]) == 0

    def vision_accepted() -> int:
        if not aiding:
            return 0
        return int(aiding[-1]["sources"].get("vision", {}).get("accepted", 0))

    # bounded generously: the camera renders at wall-clock pace, the fixes follow it, and two
    # suites sharing 2 cores slowed it below 15 fixes in 90 s (fresh-clone run P2, stop 39)
    assert spin_until(executor, lambda: vision_accepted() >= 15, FIXES_WAIT_S), (
        aiding[-1:],
        fixes[-3:],
    )
    # the first fixes may be rejected: the GPS/INS solution is metres off, the filter takes them
    # once a run of them agrees (StateEstimator.update_vision); from then on they pass the gate
    early = aiding[-1]["sources"]["vision"]

    def on_vision() -> bool:  # 40 fixes in, and the last 2 s (the window checked) free of GPS
        gps_age = aiding[-1]["sources"].get("gps", {}).get("age_s")
        return vision_accepted() >= 40 and (gps_age is None or gps_age >= 2.0)

    assert spin_until(executor, on_vision, FIXES_WAIT_S), (aiding[-1:], fixes[-3:])
    report = aiding[-1]
    assert "vision" in report["used"] and "gps" not in report["used"], report
    assert "gps_velocity" in report["used"], report  # GPS gives only its velocity meanwhile
    late = report["sources"]["vision"]
    accepted, rejected = (late[k] - early[k] for k in ("accepted", "rejected"))
    assert rejected <= 0.2 * accepted, (early, late)

    fused = np.array(pfc[-1].position_enu)
    t = _stamp(pfc[-1])
    assert t > engaged_at
    jump = fused - gps_ins
    assert math.hypot(jump[0], jump[1]) <= GPS_BOUND_H and abs(jump[2]) <= BARO_BOUND_V, jump
    truth_at = {round(_stamp(m), 2): np.array(m.position_enu) for m in truth}
    errors = [
        float(np.linalg.norm(np.array(m.position_enu) - truth_at[round(_stamp(m), 2)]))
        for m in pfc
        if t - 2.0 <= _stamp(m) <= t and round(_stamp(m), 2) in truth_at
    ]
    print(f"GPS/INS -> fused: {np.round(jump, 2)} m; fused vs truth over the last 2 s: "
          f"mean {np.mean(errors):.3f} m, max {max(errors):.3f} m ({len(errors)} ticks); "
          f"vision {late}")  # fmt: skip
    assert len(errors) >= 20 and max(errors) <= TRUTH_BOUND, errors
    assert float(np.mean(errors)) <= TRUTH_MEAN_BOUND, errors
    assert all(f["fix"]["pad"] == "L1" for f in fixes if f["fix"]["status"] == "ok")

    capsys.readouterr()
    assert hdrc3_main(["fcl", "uav0", "land", "30", "--timeout", "180"]) == 0
    said = capsys.readouterr().out
    # a vision landing, straight away or (when the last fix was over 1 s old at the command, as
    # under load, where the renderer skips exposures) after a short search that found the pattern
    assert "FCL_FINISHED" in said and "landed on vision: pad L1" in said, said
    assert "fixes down to" in said, said
    assert spin_until(executor, lambda: bool(truth) and truth[-1].on_ground, 10.0)
    pad = load_world("revinge").pad("L1")
    down = truth[-1].position_enu
    miss = math.hypot(down[0] - pad.east, down[1] - pad.north)
    print(f"touchdown {miss:.3f} m from the pad's centre; {said.strip().splitlines()[-1]}")
    assert miss <= TOUCHDOWN_BOUND, (miss, said)
    node.destroy_node()
    assert launch.interrupt() == 0
