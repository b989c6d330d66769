"""Camera images end to end: `hdrc3 launch --cameras` renders the real world_sim's exposures.

Images and CameraInfo arrive stamped with the exposures' sim times, match world_sim's
CameraState of the same stamp, and follow the camera fault switches: a frozen camera repeats
its last image with fresh stamps, a dropped one publishes nothing.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image

from hdrc3_interfaces.msg import CameraState, SimResult
from hdrc3_interfaces.srv import SimInjectFault
from sim.render.imaging import CENTI_KELVIN
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, camera_intrinsics
from tests.integration.ros_wait import answer, spin_until

pytestmark = pytest.mark.ros

RELIABLE = QoSProfile(depth=200, reliability=ReliabilityPolicy.RELIABLE)
CLOCK_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
FRAME_NS = 40_000_000  # 25 Hz in sim time
FREEZE, DROP, NONE = 2, 1, 0


def _ns(stamp: Any) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def test_images_follow_sim_time_camera_state_and_faults(hdrc3_cli, ros_context) -> None:
    launch = hdrc3_cli(
        "launch", "--agents", "uav0", "--speed", "1", "--nodes", "world_sim", "--cameras"
    )
    launch.wait_for_line("READY", timeout=90)
    node = Node("world_render_test", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    clock = [0]
    images: dict[str, list[tuple[int, int, Image]]] = {"color": [], "thermal": []}
    infos: dict[int, CameraInfo] = {}
    zooms: dict[int, float] = {}

    def on_image(name: str) -> Callable[[Any], None]:
        def callback(m: Any) -> None:
            images[name].append((_ns(m.header.stamp), zlib.crc32(bytes(m.data)), m))

        return callback

    node.create_subscription(Clock, "/clock", lambda m: clock.append(_ns(m.clock)), CLOCK_QOS)
    for name in images:
        node.create_subscription(Image, f"/uav0/camera/{name}/image_raw", on_image(name), RELIABLE)
    node.create_subscription(
        CameraInfo,
        "/uav0/camera/color/camera_info",
        lambda m: infos.__setitem__(_ns(m.header.stamp), m),
        RELIABLE,
    )
    node.create_subscription(
        CameraState,
        "/uav0/sensors/color_camera",
        lambda m: zooms.__setitem__(_ns(m.header.stamp), m.zoom),
        RELIABLE,
    )
    # the stamps are compared with the clock below: /clock must be matched before images count
    # (topics of two nodes match in no fixed order; once seen an image could beat its first tick)
    assert spin_until(executor, lambda: len(clock) > 1, 60.0), "no /clock message"
    assert spin_until(executor, lambda: len(images["color"]) >= 5, 60.0), clock[-1]
    assert spin_until(executor, lambda: len(images["thermal"]) >= 5, 30.0), clock[-1]

    # stamps: exposure sim times on the 25 Hz grid, never ahead of the clock
    for name, params, encoding in (
        ("color", COLOR_CAMERA, "rgb8"),
        ("thermal", THERMAL_CAMERA, "mono16"),
    ):
        stamps = [s for s, _, _ in images[name]]
        assert stamps == sorted(stamps) and len(set(stamps)) == len(stamps)
        assert all(s % FRAME_NS == 0 for s in stamps), stamps[:5]
        assert stamps[-1] <= max(clock)
        m = images[name][-1][2]
        assert (m.width, m.height, m.encoding) == (params.width, params.height, encoding)
        assert m.header.frame_id == f"uav0/{name}_optical"
    thermal = images["thermal"][-1][2]
    kelvin = np.frombuffer(bytes(thermal.data), dtype=np.uint16) / CENTI_KELVIN
    # on the pad with the PTU level: the ground (near the 15 C air) below the cold sky (-20 C)
    assert float(np.percentile(kelvin, 5)) < 258.0 < 280.0 < float(np.percentile(kelvin, 95))
    assert kelvin.min() > 240.0 and kelvin.max() < 330.0

    # CameraInfo of the same stamp: K of the zoom world_sim reported for that exposure
    # (the test's CameraState subscription may match world_sim later than its image ones)
    def matched() -> list[int]:
        return [s for s, _, _ in images["color"] if s in infos and s in zooms]

    assert spin_until(executor, lambda: bool(matched()), 60.0), (sorted(zooms)[:3], clock[-1])
    stamp = matched()[-1]
    k = camera_intrinsics(COLOR_CAMERA, zooms[stamp]).matrix()
    assert np.allclose(np.reshape(infos[stamp].k, (3, 3)), k)
    assert infos[stamp].header.frame_id == "uav0/color_optical"

    def fault(mode: int) -> int:
        """Inject a fault into the colour camera; the sim time from which it surely holds."""
        client = node.create_client(SimInjectFault, "/world_sim/inject_fault")
        assert client.wait_for_service(timeout_sec=20.0)
        # setting a fault mode is idempotent: sent again until answered
        request = SimInjectFault.Request(agent="uav0", sensor="color_camera", mode=mode)
        response = answer(executor, client, request, 20.0)
        assert response is not None and response.result.code == SimResult.OK
        node.destroy_client(client)
        return max(clock) + 2 * FRAME_NS

    def frames_after(start: int, count: int) -> list[tuple[int, int, Image]]:
        assert spin_until(
            executor, lambda: sum(s > start for s, _, _ in images["color"]) >= count, 60.0
        ), (start, clock[-1])
        return [f for f in images["color"] if f[0] > start]

    frozen_from = fault(FREEZE)
    frozen = frames_after(frozen_from, 4)
    assert len({digest for _, digest, _ in frozen}) == 1  # the same image ...
    assert len({s for s, _, _ in frozen}) == len(frozen)  # ... with fresh stamps
    dropped_from = fault(DROP)
    assert spin_until(executor, lambda: max(clock) > dropped_from + 1_000_000_000, 30.0)
    resumed_from = fault(NONE)
    resumed = frames_after(resumed_from, 3)
    dropped_until = resumed_from - 2 * FRAME_NS
    assert not [s for s, _, _ in images["color"] if dropped_from < s <= dropped_until]
    assert len({digest for _, digest, _ in resumed}) == len(resumed)  # live again
    node.destroy_node()
    assert launch.interrupt() == 0


@pytest.mark.parametrize(
    ("param", "message"),
    [("world:=atlantis", "unknown world 'atlantis'"), ("world:=/nowhere/x.toml", "cannot read")],
)
def test_bad_parameters_exit_2_with_one_line(ros_domain: int, param: str, message: str) -> None:
    import subprocess
    import sys
    from pathlib import Path

    exe = Path(sys.executable).parent / "hdrc3-world-render"
    done = subprocess.run(
        [str(exe), "--ros-args", "-p", param], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2, done.stderr
    assert message in done.stderr and "Traceback" not in done.stderr
