"""The landing and the PPC's pad state estimation, on the real node chain (chapter §5.4).

The perception kernel reports on ``ppc/pad_vision`` what it can do for a vision landing (a
colour camera and the ``pad_pose`` node in the ROS graph, the image processing function engaged,
the pipeline's results arriving); the control kernel's landing plans on it.

- Without cameras (``hdrc3 demo --basic``'s launch): ``fcl land`` 12 m over pad L1 lands on the
  pad's GIS position on GPS at once, and its acceptance and final reply say why; it never climbs
  to the search height (before: a 25 s search from 21 m for a pattern no camera could see).
- With cameras and the camera pointed down (``ppcl turn_to 0 90``) but no
  ``ppcl ip_state_estimation``: the landing engages the pad's pose itself (``ppc/image_processing``
  goes to state estimation, ``ppc/pad_vision`` to running), lands on vision, and releases it once
  landed (image processing idle again). At ``--speed 1``: the search's 25 s are sim time, and the
  renderer and the pad pose node work at wall-clock pace (on a loaded machine the first fixes
  take seconds).
"""

from __future__ import annotations

import math
import threading
from typing import Any

import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import UInt8

from hdrc3.cli.main import main as hdrc3_main
from hdrc3_control.perception_kernel_node import (
    IMAGE_PROCESSING_TOPIC,
    LATCHED,
    PAD_VISION_TOPIC,
)
from hdrc3_control.ppc_modes import ImageProcessing, PadVision
from sim.world_loader import load_world
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros

NODES = "world_sim,control_kernel,platform_server,perception_kernel"
OVER_L1 = ("13.466580713", "55.698544926", "107.0", "3")
"""lon, lat, altitude (m WGS84), speed (m/s): 12 m over the vision pad L1."""
TOUCHDOWN_BOUND = 0.5
"""m from the pad's centre (as ``test_vision_fusion.py``)."""
CLIMB_BOUND = 1.0
"""m above the height at the land command: no search climb (the search height is 21 m)."""


class Watch:
    """The PPC's latched reports and the ground truth, for one agent."""

    def __init__(self, ros_context: Any) -> None:
        from hdrc3_interfaces.msg import PfcState, TruthState

        self.node = Node("pad_vision_test", context=ros_context)
        self.executor = SingleThreadedExecutor(context=ros_context)
        self.executor.add_node(self.node)
        self.pad_vision: list[PadVision] = []
        self.functions: list[ImageProcessing] = []
        self.pfc: list[Any] = []
        self.truth: list[Any] = []
        self.node.create_subscription(
            UInt8, f"/uav0/{PAD_VISION_TOPIC}",
            lambda m: self._add(self.pad_vision, PadVision(m.data)), LATCHED,
        )  # fmt: skip
        self.node.create_subscription(
            UInt8, f"/uav0/{IMAGE_PROCESSING_TOPIC}",
            lambda m: self._add(self.functions, ImageProcessing(m.data)), LATCHED,
        )  # fmt: skip
        self.node.create_subscription(PfcState, "/uav0/pfc/state", self.pfc.append, 50)
        self.node.create_subscription(TruthState, "/uav0/ground_truth/state", self.truth.append, 50)

    @staticmethod
    def _add(into: list[Any], value: Any) -> None:
        if not into or into[-1] is not value:
            into.append(value)

    def until(self, done: Any, timeout: float) -> bool:
        return spin_until(self.executor, done, timeout)

    def airborne_over_l1(self) -> None:
        from hdrc3_interfaces.msg import PfcState

        assert hdrc3_main(["rc", "uav0", "--engine", "on", "--mode", "autonomous"]) == 0
        ready = self.until(
            lambda: (
                bool(self.pfc)
                and self.pfc[-1].auto_flag
                and self.pfc[-1].mode == PfcState.MODE_GROUND_IDLE
            ),
            90.0,
        )
        assert ready, self.pfc[-1:] or "no pfc/state"
        assert hdrc3_main(["fcl", "uav0", "takeoff", "--timeout", "120"]) == 0
        assert hdrc3_main(["fcl", "uav0", "traj3d_flyto", *OVER_L1, "--timeout", "120"]) == 0

    def land(self, timeout: float) -> int:
        """``hdrc3 fcl uav0 land 30`` while this node spins (the truth of the whole landing)."""
        code: list[int] = []
        cli = threading.Thread(
            target=lambda: code.append(
                hdrc3_main(["fcl", "uav0", "land", "30", "--timeout", str(timeout)])
            )
        )
        cli.start()
        self.until(lambda: not cli.is_alive(), timeout + 30.0)
        cli.join()
        return code[0]

    def sim_time(self) -> float:
        stamp = self.truth[-1].header.stamp
        return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def test_without_a_camera_the_landing_lands_on_gps_at_once_and_says_why(
    hdrc3_cli: Any, ros_context: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    launch = hdrc3_cli("launch", "--agents", "uav0", "--speed", "max", "--nodes", NODES)
    launch.wait_for_line("READY", timeout=120)
    w = Watch(ros_context)
    w.airborne_over_l1()
    assert w.until(lambda: bool(w.truth and w.functions and w.pad_vision), 10.0)
    assert w.pad_vision == [PadVision.NONE]
    w.until(lambda: False, 2.0)  # take the samples queued since the fly-to: hovering now
    start_up, start_t, mark = w.truth[-1].position_enu[2], w.sim_time(), len(w.truth)

    capsys.readouterr()
    assert w.land(180.0) == 0
    said = capsys.readouterr().out
    why = (
        "no vision fix of pad L1: no vision pipeline (the PPC has no colour camera or pad pose"
        " node)"
    )
    assert f"accepted by the PFC: landing on GPS and barometer: {why}" in said, said
    assert f"landed on GPS and barometer: {why}" in said, said
    assert w.until(lambda: w.truth[-1].on_ground, 10.0)
    highest = max(m.position_enu[2] for m in w.truth[mark:])
    pad = load_world("revinge").pad("L1")
    down = w.truth[-1].position_enu
    miss = math.hypot(down[0] - pad.east, down[1] - pad.north)
    print(
        f"landed on GPS {w.sim_time() - start_t:.1f} s of sim time after the command, "
        f"{miss:.2f} m from the pad's centre; highest {highest - start_up:+.2f} m"
    )
    assert highest <= start_up + CLIMB_BOUND, (highest, start_up)  # no search climb
    assert w.functions == [ImageProcessing.IDLE]  # nothing was engaged
    w.node.destroy_node()
    assert launch.interrupt() == 0


def test_the_landing_engages_the_pads_pose_itself_and_releases_it(
    hdrc3_cli: Any, ros_context: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    launch = hdrc3_cli(
        "launch", "--agents", "uav0", "--speed", "1", "--cameras", "--nodes", NODES
    )  # fmt: skip
    launch.wait_for_line("READY", timeout=120)
    w = Watch(ros_context)
    w.airborne_over_l1()
    assert hdrc3_main(["ppcl", "uav0", "request", "ptu", "--owner", "test"]) == 0
    assert hdrc3_main(["ppcl", "uav0", "turn_to", "0", "90", "--timeout", "60"]) == 0
    # the PPC sees the camera and the pad_pose node in the graph (checked once a second)
    ready = w.until(lambda: w.pad_vision[-1:] == [PadVision.READY] and bool(w.functions), 30.0)
    assert ready, w.pad_vision
    assert w.functions == [ImageProcessing.IDLE]

    capsys.readouterr()
    assert w.land(300.0) == 0
    said = capsys.readouterr().out
    assert "accepted by the PFC: landing on vision: pad L1, its pose engaged by the landing; " \
        "searching for the pattern from" in said, said  # fmt: skip
    assert "landed on vision: pad L1, its pose engaged by the landing (found after" in said, said
    assert w.until(lambda: w.truth[-1].on_ground, 10.0)
    pad = load_world("revinge").pad("L1")
    down = w.truth[-1].position_enu
    miss = math.hypot(down[0] - pad.east, down[1] - pad.north)
    # released once landed: idle again, and the PPC ready for the next landing
    released = w.until(
        lambda: w.functions[-1] is ImageProcessing.IDLE and w.pad_vision[-1] is PadVision.READY,
        20.0,
    )
    print(f"touchdown {miss:.3f} m from the pad's centre; {said.strip().splitlines()[-1]}")
    print(f"image processing {[f.name for f in w.functions]}, pad vision "
          f"{[p.name for p in w.pad_vision]}")  # fmt: skip
    assert released, (w.functions, w.pad_vision)
    assert w.functions == [
        ImageProcessing.IDLE,
        ImageProcessing.STATE_ESTIMATION,
        ImageProcessing.IDLE,
    ]
    assert PadVision.RUNNING in w.pad_vision, w.pad_vision
    assert miss <= TOUCHDOWN_BOUND, (miss, said)
    w.node.destroy_node()
    assert launch.interrupt() == 0
