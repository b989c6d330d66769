"""Cameras: intrinsics vs zoom, pose = aircraft pose o PTU angles, projection and geolocation."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, Camera, CameraParams, ZoomStatus
from sim.sensors.camera_model import Intrinsics, camera_pose, ground_point, pixel_ray, project
from sim.sensors.errors import SensorError
from sim.sensors.fake_truth import make_truth
from sim.sensors.ptu import PanTiltUnit

NO_OFFSET = replace(COLOR_CAMERA, mount_offset=(0.0, 0.0, 0.0))


def camera(params: CameraParams = NO_OFFSET, pan: float = 0.0, tilt: float = 0.0) -> Camera:
    ptu = PanTiltUnit()
    ptu.pan, ptu.tilt = pan, tilt
    return Camera(params, ptu)


@pytest.mark.parametrize(("heading", "roll"), [(0.0, 0.0), (1.0, 0.0), (4.0, 0.0)])
def test_point_straight_below_with_tilt_90_is_the_image_centre(heading: float, roll: float) -> None:
    cam = camera(tilt=math.pi / 2)
    truth = make_truth(position_enu=(10.0, 20.0, 30.0), heading=heading, roll=roll)
    pixel = project(cam.pose(truth), cam.intrinsics(), (10.0, 20.0, 0.0))
    assert pixel == pytest.approx((360.0, 288.0))


@pytest.mark.parametrize(
    ("heading", "pan", "target"),
    [
        (0.0, 0.0, (0.0, 50.0, 20.0)),  # ahead (north)
        (0.0, math.pi / 2, (50.0, 0.0, 20.0)),  # pan right -> east
        (math.pi / 2, 0.0, (50.0, 0.0, 20.0)),  # heading east
        (math.pi / 2, -math.pi / 2, (0.0, 50.0, 20.0)),  # heading east, pan left -> north
    ],
)
def test_boresight_follows_heading_and_pan(
    heading: float, pan: float, target: tuple[float, float, float]
) -> None:
    cam = camera(pan=pan)
    truth = make_truth(position_enu=(0.0, 0.0, 20.0), heading=heading)
    assert project(cam.pose(truth), cam.intrinsics(), target) == pytest.approx((360.0, 288.0))


def test_image_axes_right_and_down() -> None:
    cam = camera()
    pose = cam.pose(make_truth(position_enu=(0.0, 0.0, 20.0)))  # looking north
    right = project(pose, cam.intrinsics(), (5.0, 50.0, 20.0))
    below = project(pose, cam.intrinsics(), (0.0, 50.0, 15.0))
    assert right is not None and right[0] > 360.0 and right[1] == pytest.approx(288.0)
    assert below is not None and below[1] > 288.0 and below[0] == pytest.approx(360.0)
    assert project(pose, cam.intrinsics(), (0.0, -50.0, 20.0)) is None  # behind


def test_pitch_up_moves_the_nadir_point_down_in_the_image() -> None:
    # Nose up 10 deg turns the belly (and the tilt-90 camera) 10 deg forward of nadir; the image
    # top is the aircraft's forward side, so the point below the aircraft slides down.
    cam = camera(tilt=math.pi / 2)
    pose = cam.pose(make_truth(position_enu=(0.0, 0.0, 30.0), pitch=math.radians(10.0)))
    pixel = project(pose, cam.intrinsics(), (0.0, 0.0, 0.0))
    assert pixel is not None and pixel[0] == pytest.approx(360.0)
    assert pixel[1] == pytest.approx(288.0 + cam.intrinsics().fy * math.tan(math.radians(10.0)))


def test_mount_offset_moves_the_camera() -> None:
    cam = camera(params=COLOR_CAMERA)  # 0.45 m below, 0.3 m ahead of the CG
    pose = cam.pose(make_truth(position_enu=(0.0, 0.0, 20.0), heading=math.pi / 2))
    assert pose.position == pytest.approx((0.3, 0.0, 19.55))


@pytest.mark.parametrize(("zoom", "hfov_deg"), [(0.0, 48.0), (1.0, 2.0)])
def test_zoom_end_points_give_the_specified_fov(zoom: float, hfov_deg: float) -> None:
    assert math.degrees(camera().intrinsics(zoom).hfov) == pytest.approx(hfov_deg)


def test_focal_length_is_linear_and_fov_monotonic_in_zoom() -> None:
    cam = camera()
    focals = [cam.intrinsics(z).fx for z in np.linspace(0.0, 1.0, 11)]
    assert np.allclose(np.diff(focals), focals[1] - focals[0])
    fovs = [cam.intrinsics(z).hfov for z in np.linspace(0.0, 1.0, 11)]
    assert np.all(np.diff(fovs) < 0.0)


def test_zoom_commands_and_motor() -> None:
    cam = camera()
    assert cam.command_zoom(1.5) is ZoomStatus.CLAMPED
    assert cam.command_zoom(math.nan) is ZoomStatus.REJECTED
    assert cam.command_zoom(0.5) is ZoomStatus.ACCEPTED
    cam.step(1.0)
    assert cam.zoom == pytest.approx(0.33)
    cam.step(1.0)
    assert cam.zoom == pytest.approx(0.5)


def test_thermal_camera_has_fixed_optics() -> None:
    cam = camera(params=THERMAL_CAMERA)
    assert cam.intrinsics(0.0) == cam.intrinsics(1.0)
    assert (cam.intrinsics().width, cam.intrinsics().height) == (160, 120)


def test_pixel_ray_and_flat_world_geolocation_invert_projection() -> None:
    cam = camera(pan=0.4, tilt=1.1)
    truth = make_truth(position_enu=(5.0, -3.0, 40.0), heading=2.0, roll=0.05, pitch=-0.03)
    pose = cam.pose(truth)
    intrinsics = cam.intrinsics(0.3)
    for u, v in [(360.0, 288.0), (100.0, 50.0), (700.0, 500.0)]:
        point = ground_point(pose, intrinsics, u, v, ground_up=0.0)
        assert point is not None and point[2] == pytest.approx(0.0)
        assert project(pose, intrinsics, point) == pytest.approx((u, v), abs=1e-6)
    assert np.linalg.norm(pixel_ray(pose, intrinsics, 10.0, 10.0)) == pytest.approx(1.0)
    up_pose = camera_pose(truth, 0.0, -0.17, (0.0, 0.0, 0.0))  # looking above the horizon
    assert ground_point(up_pose, intrinsics, 360.0, 0.0, 0.0) is None


def test_intrinsics_from_fov_and_validation() -> None:
    k = Intrinsics.from_fov(640, 480, math.radians(90.0))
    assert k.fx == pytest.approx(320.0) and k.matrix()[0, 2] == 320.0
    with pytest.raises(SensorError):
        replace(COLOR_CAMERA, hfov_tele=math.radians(60.0))


def test_frames_carry_pose_zoom_and_angles() -> None:
    cam = camera(tilt=math.pi / 2)
    frame = cam.update(make_truth(position_enu=(0.0, 0.0, 30.0)))
    assert frame is not None
    assert frame.tilt == pytest.approx(math.pi / 2, abs=0.01)
    assert frame.intrinsics == cam.intrinsics(frame.zoom)
    assert frame.pose.optical_axis == pytest.approx([0.0, 0.0, -1.0], abs=0.01)
