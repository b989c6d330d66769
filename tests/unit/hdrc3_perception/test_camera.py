"""The PPC's camera geometry agrees with the simulator's camera model and the image contract."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_perception.camera import MOUNT_OFFSET, CameraPose, Intrinsics, NavPose
from hdrc3_perception.geolocation import Ground, geolocate
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA
from sim.sensors.camera_model import Intrinsics as SimIntrinsics
from sim.sensors.camera_model import camera_pose, project
from sim.truth_state import TruthState

POSES = [
    # (position, roll, pitch, heading, pan, tilt)
    ((0.0, 0.0, 30.0), 0.0, 0.0, 0.0, 0.0, math.pi / 2),
    ((12.0, -40.0, 55.0), 0.05, -0.03, 1.2, 0.4, 1.1),
    ((-100.0, 7.0, 20.0), -0.1, 0.08, -2.5, -1.3, 0.6),
]


def test_the_mounting_calibration_is_the_simulated_platform_s() -> None:
    assert MOUNT_OFFSET == COLOR_CAMERA.mount_offset == THERMAL_CAMERA.mount_offset


@pytest.mark.parametrize(("position", "roll", "pitch", "heading", "pan", "tilt"), POSES)
def test_pose_matches_the_simulator_s_camera_model(
    position: tuple[float, float, float],
    roll: float,
    pitch: float,
    heading: float,
    pan: float,
    tilt: float,
) -> None:
    truth = TruthState(
        time=0.0,
        position_enu=position,
        velocity_enu=(0.0, 0.0, 0.0),
        roll=roll,
        pitch=pitch,
        heading=heading,
        body_rates=(0.0, 0.0, 0.0),
        specific_force_body=(0.0, 0.0, -9.81),
        rotor_rpm=1500.0,
        engine_running=True,
        on_ground=False,
        height_above_ground=position[2],
        mass=80.0,
    )
    sim_pose = camera_pose(truth, pan, tilt, COLOR_CAMERA.mount_offset)
    ours = CameraPose.of(NavPose(position, roll, pitch, heading), pan, tilt)
    assert np.allclose(ours.position, sim_pose.position)
    assert np.allclose(ours.rotation, sim_pose.matrix())
    k = Intrinsics.from_fov(720, 576, math.radians(48.0))
    point = ours.position + 25.0 * ours.ray(k, 200.0, 410.0)
    assert np.allclose(ours.project(k, point)[0], (200.0, 410.0))
    sim_k = SimIntrinsics.from_fov(720, 576, math.radians(48.0))
    assert project(sim_pose, sim_k, tuple(point)) == pytest.approx((200.0, 410.0))


def test_points_behind_the_camera_do_not_project() -> None:
    pose = CameraPose.of(NavPose((0.0, 0.0, 30.0), 0.0, 0.0, 0.0), 0.0, math.pi / 2)
    k = Intrinsics.from_fov(160, 120, math.radians(25.0))
    pixels = pose.project(k, np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 60.0], [300.0, 0.0, 0.0]]))
    assert np.allclose(pixels[0], (80.0, 60.0), atol=5.0)  # the mount is 0.3 m forward
    assert np.isnan(pixels[1]).all()
    assert pose.sees(
        k, np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 60.0], [300.0, 0.0, 0.0]])
    ).tolist() == [
        True,
        False,
        False,
    ]


@pytest.mark.parametrize(
    ("width", "height", "k", "usable"),
    [
        (720, 576, (800.0, 0, 360, 0, 800.0, 288, 0, 0, 1), True),
        (720, 576, (0.0,) * 9, False),  # an unset CameraInfo
        (720, 576, (800.0, 0, 360, 0, math.nan, 288, 0, 0, 1), False),
        (720, 576, (800.0, 0, 360), False),
        (0, 576, (800.0, 0, 360, 0, 800.0, 288, 0, 0, 1), False),
    ],
)
def test_calibration_from_camera_info(
    width: int, height: int, k: tuple[float, ...], usable: bool
) -> None:
    intrinsics = Intrinsics.from_k(width, height, k)
    assert (intrinsics is not None) == usable
    if intrinsics is not None:
        assert intrinsics.k() == pytest.approx(k)


@pytest.mark.parametrize(
    ("u", "margin_m", "seen"),
    [
        (2.0, 0.0, True),
        (2.0, 1.0, False),  # 0.17 m inside the border on the ground
        (20.0, 1.0, True),  # 1.7 m inside
        (158.0, 1.0, False),
        (140.0, 1.0, True),
        (80.0, 4.5, True),  # the centre is 6.6 m from the sides, 5 m from top and bottom
        (80.0, 5.5, False),
    ],
)
def test_a_view_margin_is_a_ground_distance_from_the_border(
    u: float, margin_m: float, seen: bool
) -> None:
    pose = CameraPose.of(NavPose((0.0, 0.0, 30.0), 0.0, 0.0, 0.0), 0.0, math.pi / 2)
    k = Intrinsics.from_fov(160, 120, math.radians(25.0))
    point = geolocate(pose, k, u, 60.0, Ground())
    assert point is not None
    assert pose.sees(k, point[None, :], margin_m).tolist() == [seen]
