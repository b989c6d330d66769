"""The saliency node over real rclpy/DDS: image pairs, Data Interface state and PTU in; the map
(GeoJSON, markers) and per-pair results out; bad images answered with a status; the PPC's
image processing mode engages and stops it."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hdrc3_control.ppc_modes import ImageProcessing

pytestmark = pytest.mark.ros

MAX_SPINS = 400
SPIN_TIMEOUT = 0.02
BODY = (12.0, -30.0)
"""Where the synthetic body lies in revinge (ENU, m)."""


@dataclass
class Rig:
    executor: Any
    node: Any
    pubs: dict[str, Any]
    results: list[dict[str, Any]]
    maps: list[str]
    markers: list[Any]
    engaged: list[bool]

    def spin_until(self, done: Callable[[], bool]) -> bool:
        for _ in range(MAX_SPINS):
            if done():
                return True
            self.executor.spin_once(timeout_sec=SPIN_TIMEOUT)
        return done()


def image_msg(array: np.ndarray, encoding: str, t: float) -> Any:
    from sensor_msgs.msg import Image

    msg = Image()
    stamped(msg, t)
    msg.height, msg.width = array.shape[:2]
    msg.encoding = encoding
    msg.step = array.strides[0]
    msg.data = array.tobytes()
    return msg


@pytest.fixture
def rig(ros_context: object, tmp_path: Path) -> Iterator[Rig]:
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import CameraInfo, Image
    from std_msgs.msg import Bool, String, UInt8
    from visualization_msgs.msg import MarkerArray

    from hdrc3_control.perception_kernel_node import IMAGE_PROCESSING_TOPIC
    from hdrc3_interfaces.msg import CameraState, HelicopterState
    from hdrc3_perception.image_gate import LATCHED
    from hdrc3_perception.node import RESULT_QOS, STATE_QOS, SaliencyNode

    node = SaliencyNode(
        context=ros_context,
        namespace="/uav0",
        parameter_overrides=[
            Parameter("world", value="revinge"),
            Parameter("detector", value="hog_people"),
            Parameter("geojson_path", value=str(tmp_path / "saliency.geojson")),
        ],
    )
    tester = Node("saliency_tester", context=ros_context)
    results: list[dict[str, Any]] = []
    maps: list[str] = []
    markers: list[Any] = []
    engaged: list[bool] = []
    tester.create_subscription(
        Bool, "/uav0/saliency/engaged", lambda m: engaged.append(m.data), LATCHED
    )
    tester.create_subscription(
        String,
        "/uav0/saliency/pair_result",
        lambda m: results.append(json.loads(m.data)),
        RESULT_QOS,
    )
    tester.create_subscription(String, "/uav0/saliency/map", lambda m: maps.append(m.data), LATCHED)
    tester.create_subscription(MarkerArray, "/uav0/saliency/markers", markers.append, LATCHED)
    pubs = {
        "color": tester.create_publisher(
            Image, "/uav0/camera/color/image_raw", qos_profile_sensor_data
        ),
        "thermal": tester.create_publisher(
            Image, "/uav0/camera/thermal/image_raw", qos_profile_sensor_data
        ),
        "color_info": tester.create_publisher(
            CameraInfo, "/uav0/camera/color/camera_info", qos_profile_sensor_data
        ),
        "thermal_info": tester.create_publisher(
            CameraInfo, "/uav0/camera/thermal/camera_info", qos_profile_sensor_data
        ),
        "state": tester.create_publisher(HelicopterState, "/uav0/helicopter_state", STATE_QOS),
        "ptu": tester.create_publisher(CameraState, "/uav0/camera_state", STATE_QOS),
        "mode": tester.create_publisher(UInt8, f"/uav0/{IMAGE_PROCESSING_TOPIC}", LATCHED),
    }
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    executor.add_node(tester)
    rig = Rig(executor, node, pubs, results, maps, markers, engaged)
    set_mode(rig, ImageProcessing.SALIENCY)
    try:
        yield rig
    finally:
        executor.shutdown()
        tester.destroy_node()
        node.destroy_node()


def set_mode(rig: Rig, mode: ImageProcessing) -> None:
    """Publish the PPC's image processing mode and wait until the node follows it."""
    from std_msgs.msg import UInt8

    rig.pubs["mode"].publish(UInt8(data=int(mode)))
    on = mode is ImageProcessing.SALIENCY
    assert rig.spin_until(lambda: rig.node.engaged is on and rig.engaged[-1:] == [on])


def stamped(msg: Any, t: float) -> Any:
    msg.header.stamp.sec, msg.header.stamp.nanosec = int(t), round((t % 1.0) * 1e9)
    return msg


def send_frame(
    rig: Rig, i: int, broken: bool = False, state_lag: float = 0.0, moved_on: float = 0.0
) -> float:
    """Publish state, PTU, calibration and one synthetic pair flying north over BODY.

    ``state_lag``: the state and PTU read-out are stamped this long before the image.
    ``moved_on``: then a state stamped 0.06 s after the image, this far east, arrives before
    the image does (the aircraft moved on while the image was in transit).
    """
    import pymap3d
    from sensor_msgs.msg import CameraInfo

    from hdrc3_interfaces.msg import CameraState, HelicopterState
    from hdrc3_perception.camera import NavPose
    from hdrc3_perception.geolocation import Ground
    from hdrc3_perception.synthetic import COLOR_K, THERMAL_K, Body, render_pair
    from sim.world_loader import load_world

    world = load_world("revinge")
    ground = Ground(height=world.terrain.height, max_slope=1.0)
    t = 10.0 + 0.04 * i
    east, north = BODY[0] - 2.0, BODY[1] - 3.0 + 0.3 * i
    nav = NavPose((east, north, ground.up(east, north) + 35.0), 0.02, -0.01, 0.1)
    pair = render_pair(
        t, nav, 0.0, math.pi / 2, [Body(*BODY, 0.8)], ground, np.random.default_rng(i)
    )
    o = world.origin
    lat, lon, alt = pymap3d.enu2geodetic(*nav.position, o.latitude, o.longitude, o.altitude)
    state = HelicopterState()
    state.latitude, state.longitude, state.altitude = float(lat), float(lon), float(alt)
    state.roll, state.pitch, state.heading = nav.roll, nav.pitch, nav.heading
    rig.pubs["state"].publish(stamped(state, t - state_lag))
    ptu = CameraState()
    ptu.pan, ptu.tilt = 0.0, math.pi / 2
    rig.pubs["ptu"].publish(stamped(ptu, t - state_lag))
    if moved_on:
        ahead = pymap3d.enu2geodetic(
            nav.position[0] + moved_on, *nav.position[1:], o.latitude, o.longitude, o.altitude
        )
        state.latitude, state.longitude, state.altitude = (float(v) for v in ahead)
        rig.pubs["state"].publish(stamped(state, t + 0.06))
    for cam, k in (("color", COLOR_K), ("thermal", THERMAL_K)):
        info = CameraInfo()
        info.width, info.height, info.k = k.width, k.height, list(k.k())
        rig.pubs[f"{cam}_info"].publish(info)
    nav_at, ptu_at = rig.node._nav.at, rig.node._ptu.at
    seen = t + 0.06 if moved_on else t - state_lag
    assert rig.spin_until(lambda: nav_at(seen) is not None and ptu_at(t - state_lag) is not None)
    rig.executor.spin_once(timeout_sec=SPIN_TIMEOUT)
    rig.pubs["color"].publish(image_msg(np.asarray(pair.color.data), "rgb8", t))
    thermal = np.asarray(pair.thermal.data)
    if broken:
        rig.pubs["thermal"].publish(image_msg(thermal.astype(np.uint8), "mono8", t))
    else:
        rig.pubs["thermal"].publish(image_msg(thermal, "mono16", t))
    return t


def result_at(rig: Rig, t: float) -> dict[str, Any] | None:
    return next((r for r in rig.results if abs(r["time"] - t) < 1e-6), None)


@pytest.mark.parametrize("moved_on", [0.0, 10.0])
def test_a_body_flown_over_ends_confirmed_in_the_map_and_the_file(
    rig: Rig, tmp_path: Path, moved_on: float
) -> None:
    """With ``moved_on``, a newer state 10 m away has arrived before each image: the body is
    still placed where it lies, from the state of the image's own time."""
    confirmed: list[dict[str, Any]] = []
    for i in range(40):
        t = send_frame(rig, i, moved_on=moved_on)
        rig.spin_until(lambda t=t: result_at(rig, t) is not None)  # a lost image is no failure
        features = json.loads(rig.maps[-1])["features"] if rig.maps else []
        confirmed = [f for f in features if f["properties"]["confirmed"]]
        if confirmed and i >= 10:
            break
    processed = [r for r in rig.results if r["status"] == "processed"]
    assert len(processed) >= 6
    assert any(r["candidates"] == 1 and r["positives"] == 1 for r in processed)
    assert len(confirmed) == 1
    props = confirmed[0]["properties"]
    assert props["p_body"] > 0.5 and props["t_frame"] >= 5
    assert math.dist((props["east"], props["north"]), BODY) < 0.5
    assert rig.markers and rig.markers[-1].markers[0].color.g == 1.0
    assert rig.spin_until(lambda: (tmp_path / "saliency.geojson").exists())
    written = json.loads((tmp_path / "saliency.geojson").read_text())
    assert written["type"] == "FeatureCollection" and written["features"]


def test_a_bad_image_gets_a_status_and_the_node_goes_on(rig: Rig) -> None:
    t = send_frame(rig, 0, broken=True)
    assert rig.spin_until(lambda: result_at(rig, t) is not None), "no result for the bad pair"
    bad = result_at(rig, t)
    assert bad is not None and bad["status"] == "bad_encoding" and "mono8" in bad["reason"]
    for i in range(1, 10):
        t = send_frame(rig, i)
        if rig.spin_until(lambda t=t: result_at(rig, t) is not None):
            break
    good = result_at(rig, t)
    assert good is not None and good["status"] == "processed"


def test_an_image_without_a_state_of_its_time_is_not_processed(rig: Rig) -> None:
    t = send_frame(rig, 0, state_lag=0.5)
    assert rig.spin_until(lambda: result_at(rig, t) is not None), "no result for the pair"
    result = result_at(rig, t)
    assert result is not None and result["status"] == "no_state"
    assert "helicopter_state" in result["reason"] and f"{t:.3f}" in result["reason"]
    assert not rig.node.pipeline.map


def test_the_pipeline_runs_only_while_the_ppc_engages_it(rig: Rig) -> None:
    first = send_frame(rig, 0)
    assert rig.spin_until(lambda: result_at(rig, first) is not None)
    set_mode(rig, ImageProcessing.IDLE)
    idle = [send_frame(rig, i) for i in range(1, 4)]
    for _ in range(20):
        rig.executor.spin_once(timeout_sec=SPIN_TIMEOUT)
    assert all(result_at(rig, t) is None for t in idle)
    set_mode(rig, ImageProcessing.SALIENCY)
    for i in range(4, 14):
        t = send_frame(rig, i)
        if rig.spin_until(lambda t=t: result_at(rig, t) is not None):
            break
    assert result_at(rig, t) is not None


def test_an_ungated_node_takes_images_without_a_ppc(ros_context: object) -> None:
    from rclpy.parameter import Parameter

    from hdrc3_perception.node import SaliencyNode

    ungated = [Parameter("gated", value=False)]
    node = SaliencyNode(context=ros_context, namespace="/uav9", parameter_overrides=ungated)
    try:
        assert node.engaged  # subscribed to the images at once: no ppc/image_processing needed
    finally:
        node.destroy_node()
