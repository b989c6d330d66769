"""The ``color_tracker`` node: engaged by the PPC, seeded on its latched topic, one ColorTrack per
image with the target's direction and ground point from helicopter_state and the PTU."""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from geometry_msgs.msg import PointStamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Bool, UInt8

from hdrc3_control.perception_kernel_node import IMAGE_PROCESSING_TOPIC
from hdrc3_control.ppc_modes import ImageProcessing
from hdrc3_interfaces.msg import ColorTrack, HelicopterState, PtuState
from hdrc3_perception.camera import CameraPose, Intrinsics, NavPose
from hdrc3_perception.colour_node import (
    SEED_QOS,
    SEED_TOPIC,
    TRACK_QOS,
    TRACK_TOPIC,
    ColorTrackerNode,
)
from hdrc3_perception.colour_tracking import TrackStatus
from hdrc3_perception.image_gate import LATCHED
from hdrc3_perception.node import STATE_QOS
from hdrc3_platform_server.geo_frame import WorldFrame
from sim.world_loader import load_world
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros
K = Intrinsics.from_fov(320, 240, math.radians(48.0))
WORLD = load_world("revinge")
TARGET = (20.0, -3.0)  # on the road where revinge's car1 stands
PTU = (0.05, 0.85)
"""Pan right a little, tilted 49 deg down: the target near the image centre."""


def nav(t: float) -> NavPose:
    """Hovering 30 m up, 25 m south of the target, facing north (drifting east 1 m/s)."""
    up = WORLD.terrain.height(*TARGET) + 30.0
    return NavPose((TARGET[0] - 3.0 + t, TARGET[1] - 25.0, up), 0.01, -0.02, 0.0)


def ground_point(east: float, north: float) -> np.ndarray:
    return np.array([east, north, WORLD.terrain.height(east, north)])


def scene(t: float, rng: np.random.Generator, car: np.ndarray | None) -> tuple[np.ndarray, Any]:
    """Grass with a red car centred on the projection of ``car`` (ENU); the car's pixel."""
    img = np.empty((K.height, K.width, 3), np.float64)
    img[:] = (84, 116, 58)
    img += rng.normal(0.0, 10.0, img.shape)
    uv = None
    if car is not None:
        uv = CameraPose.of(nav(t), *PTU).project(K, car)[0]
        x0, y0 = round(uv[0]) - 12, round(uv[1]) - 6
        img[y0 : y0 + 12, x0 : x0 + 24] = (200, 25, 25)
    return np.clip(img, 0, 255).astype(np.uint8), uv


@dataclass
class Rig:
    executor: SingleThreadedExecutor
    node: ColorTrackerNode
    pubs: dict[str, Any]
    tracks: list[ColorTrack]
    engaged: list[bool]
    frame: WorldFrame

    def mode(self, mode: ImageProcessing) -> None:
        self.pubs["mode"].publish(UInt8(data=int(mode)))
        on = mode is ImageProcessing.COLOR_TRACKER
        assert spin_until(self.executor, lambda: self.engaged[-1:] == [on], 10.0), self.engaged

    def seed(self, x: float, y: float, t: int) -> None:
        msg = PointStamped()
        msg.header.stamp.sec = t
        msg.point.x, msg.point.y = x, y
        self.pubs["seed"].publish(msg)
        key = (t * 1_000_000_000, x, y)
        assert spin_until(self.executor, lambda: self.node._last_seed == key, 5.0)

    def state(self, t: float) -> None:
        """The Data Interface's state and the PTU read-out stamped ``t``; both taken."""
        pose = nav(t)
        msg = HelicopterState()
        msg.header.stamp.sec = int(t)
        msg.longitude, msg.latitude, msg.altitude = self.frame.to_wgs84(*pose.position)
        msg.roll, msg.pitch, msg.heading = pose.roll, pose.pitch, pose.heading
        self.pubs["state"].publish(msg)
        ptu = PtuState(pan=PTU[0], tilt=PTU[1])
        ptu.header.stamp.sec = int(t)
        self.pubs["ptu"].publish(ptu)
        node = self.node
        assert spin_until(
            self.executor,
            lambda: node._nav.at(t) is not None and node._ptu.at(t) is not None,
            5.0,
        )

    def image(
        self, t: int, pixels: np.ndarray, encoding: str = "rgb8", calibrated: bool = True
    ) -> ColorTrack:
        """Publish calibration (unless not ``calibrated``) and one image stamped ``t`` s; the
        node's track of it."""
        info = CameraInfo(width=K.width, height=K.height, k=list(K.k()))
        msg = Image(height=K.height, width=K.width, encoding=encoding, step=3 * K.width)
        msg.header.stamp.sec = t
        msg.data = pixels.tobytes()
        for _ in range(5):  # sensor-data QoS is best effort: publish until one is taken
            if calibrated:
                self.pubs["info"].publish(info)
            self.pubs["image"].publish(msg)
            if spin_until(self.executor, lambda: self._track(t) is not None, 2.0):
                break
        track = self._track(t)
        assert track is not None, self.tracks
        return track

    def _track(self, t: int) -> ColorTrack | None:
        return next((m for m in self.tracks if m.header.stamp.sec == t), None)


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    node = ColorTrackerNode(context=ros_context, namespace="/uav0")
    tester = Node("color_tester", context=ros_context)
    tracks: list[ColorTrack] = []
    engaged: list[bool] = []
    tester.create_subscription(ColorTrack, f"/uav0/{TRACK_TOPIC}", tracks.append, TRACK_QOS)

    def on_engaged(msg: Bool) -> None:
        engaged.append(bool(msg.data))

    tester.create_subscription(Bool, "/uav0/color_tracker/engaged", on_engaged, LATCHED)
    pubs = {
        "mode": tester.create_publisher(UInt8, f"/uav0/{IMAGE_PROCESSING_TOPIC}", LATCHED),
        "seed": tester.create_publisher(PointStamped, f"/uav0/{SEED_TOPIC}", SEED_QOS),
        "state": tester.create_publisher(HelicopterState, "/uav0/helicopter_state", STATE_QOS),
        "ptu": tester.create_publisher(PtuState, "/uav0/sensors/ptu", 10),
        "info": tester.create_publisher(
            CameraInfo, "/uav0/camera/color/camera_info", qos_profile_sensor_data
        ),
        "image": tester.create_publisher(
            Image, "/uav0/camera/color/image_raw", qos_profile_sensor_data
        ),
    }
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    executor.add_node(tester)
    origin = WORLD.origin
    frame = WorldFrame(origin.latitude, origin.longitude, origin.altitude)
    try:
        yield Rig(executor, node, pubs, tracks, engaged, frame)
    finally:
        executor.shutdown()
        tester.destroy_node()  # type: ignore[no-untyped-call]
        node.destroy_node()  # type: ignore[no-untyped-call]


def test_the_seeded_car_is_tracked_and_located_on_the_ground(rig: Rig) -> None:
    rng = np.random.default_rng(3)
    rig.mode(ImageProcessing.COLOR_TRACKER)
    for t in range(5, 9):
        car = ground_point(TARGET[0] + 0.4 * (t - 5), TARGET[1] + 0.8 * (t - 5))  # it drives
        pixels, uv = scene(t, rng, car)
        if t == 5:
            rig.seed(float(uv[0]) + 3.0, float(uv[1]) - 2.0, t)  # an operator's click on it
        rig.state(t)
        track = rig.image(t, pixels)
        assert track.status == ColorTrack.STATUS_TRACKING, track.reason
        assert track.header.stamp.sec == t and track.header.frame_id
        assert (track.x, track.y) == pytest.approx(uv, abs=1.0)
        assert track.area == pytest.approx(24 * 12, rel=0.1)
        d = track.direction
        assert (d.x, d.y, d.z) == pytest.approx(tuple(K.direction(track.x, track.y)))
        assert track.located, track.reason
        p = track.position
        assert np.hypot(p.x - car[0], p.y - car[1]) < 0.3 and abs(p.z - car[2]) < 0.3


def test_a_seed_waits_for_an_image_taken_at_or_after_it(rig: Rig) -> None:
    """An image older than the command (queued on a loaded machine) is not the one clicked on."""
    rig.mode(ImageProcessing.COLOR_TRACKER)
    pixels, uv = scene(5, np.random.default_rng(6), ground_point(*TARGET))
    rig.seed(float(uv[0]), float(uv[1]), 6)
    early = rig.image(5, pixels)
    assert early.status == ColorTrack.STATUS_LOST and "no seed" in early.reason
    assert rig.image(6, pixels).status == ColorTrack.STATUS_TRACKING


@pytest.mark.parametrize(
    ("with_state", "calibrated", "why"),
    [(False, True, "helicopter_state"), (True, False, "no usable camera_info")],
)
def test_without_state_or_calibration_the_track_is_not_located(
    rig: Rig, with_state: bool, calibrated: bool, why: str
) -> None:
    rig.mode(ImageProcessing.COLOR_TRACKER)
    pixels, uv = scene(5, np.random.default_rng(4), ground_point(*TARGET))
    rig.seed(float(uv[0]), float(uv[1]), 5)
    if with_state:
        rig.state(5)
    track = rig.image(5, pixels, calibrated=calibrated)
    assert track.status == ColorTrack.STATUS_TRACKING and not track.located
    assert why in track.reason and math.isnan(track.position.x)
    assert track.direction.z > 0.0 if calibrated else math.isnan(track.direction.z)


def test_bad_seeds_and_images_get_a_status(rig: Rig) -> None:
    rng = np.random.default_rng(5)
    rig.mode(ImageProcessing.COLOR_TRACKER)
    pixels, _ = scene(5, rng, ground_point(*TARGET))
    assert "no seed" in rig.image(4, pixels).reason
    assert rig.tracks[-1].status == ColorTrack.STATUS_LOST
    rig.seed(10.0, 10.0, 5)  # on the grass
    track = rig.image(5, pixels)
    assert track.status == ColorTrack.STATUS_BAD_SEED and "background" in track.reason
    assert math.isnan(track.x) and not track.located
    rig.seed(-4.0, 1e9, 6)  # outside
    assert "outside" in rig.image(6, pixels).reason
    track = rig.image(7, pixels, encoding="bgr8")
    assert track.status == ColorTrack.STATUS_LOST and "bad image" in track.reason
    assert rig.node.results[TrackStatus.BAD_SEED] == 2


def test_the_node_follows_the_ppc(rig: Rig) -> None:
    assert spin_until(rig.executor, lambda: rig.engaged[-1:] == [False], 10.0)
    rig.mode(ImageProcessing.STATE_ESTIMATION)  # another function: not engaged
    assert not rig.node.gate.engaged
    pixels, uv = scene(5, np.random.default_rng(6), ground_point(*TARGET))
    rig.seed(float(uv[0]), float(uv[1]), 5)  # the seed may come before the engagement
    rig.mode(ImageProcessing.COLOR_TRACKER)
    assert rig.image(5, pixels).status == ColorTrack.STATUS_TRACKING
    rig.mode(ImageProcessing.IDLE)  # the tracker forgets its target
    assert rig.node.tracker.model is None
    rig.mode(ImageProcessing.COLOR_TRACKER)
    assert "no seed" in rig.image(6, pixels).reason
