"""Geolocation round trips (project a known ground point, geolocate its pixel) on flat and sloped
ground, and the thermal -> colour correspondence."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_perception.camera import CameraPose, Intrinsics, NavPose
from hdrc3_perception.geolocation import Ground, correspond, flat_hit, geolocate
from sim.terrain import Terrain

COLOR = Intrinsics.from_fov(720, 576, math.radians(48.0))
THERMAL = Intrinsics.from_fov(160, 120, math.radians(25.0))
HILL = Terrain(
    -200.0,
    -200.0,
    50.0,
    tuple(tuple(3.0 * math.sin(c / 2.0) + 0.08 * 50.0 * r for c in range(9)) for r in range(9)),
)
GROUNDS = {
    "flat at 0": Ground(),
    "flat at 12 m": Ground(flat_up=12.0),
    "plane sloped 30 %": Ground(height=lambda e, n: 0.3 * e + 5.0, max_slope=0.5),
    "terrain grid": Ground(height=HILL.height, max_slope=0.5),
}
VIEWS = [
    # (nav, pan, tilt): nadir, oblique, banked and turned
    (NavPose((0.0, 0.0, 60.0), 0.0, 0.0, 0.0), 0.0, math.pi / 2),
    (NavPose((30.0, -20.0, 70.0), 0.0, 0.05, 0.7), 0.3, 0.9),
    (NavPose((-50.0, 40.0, 80.0), 0.1, -0.05, 4.0), -0.8, 1.2),
]
PIXELS = [(360.0, 288.0), (10.0, 20.0), (700.0, 560.0), (123.4, 456.7)]


@pytest.mark.parametrize("ground_name", sorted(GROUNDS))
@pytest.mark.parametrize("view", range(len(VIEWS)))
def test_round_trip_pixel_ground_pixel(ground_name: str, view: int) -> None:
    ground = GROUNDS[ground_name]
    nav, pan, tilt = VIEWS[view]
    pose = CameraPose.of(nav, pan, tilt)
    for u, v in PIXELS:
        point = geolocate(pose, COLOR, u, v, ground)
        assert point is not None
        assert point[2] == pytest.approx(ground.up(point[0], point[1]), abs=0.02)
        assert np.allclose(pose.project(COLOR, point)[0], (u, v), atol=0.05)


@pytest.mark.parametrize("ground_name", sorted(GROUNDS))
def test_known_ground_points_are_found_within_5_cm(ground_name: str) -> None:
    ground = GROUNDS[ground_name]
    nav, pan, tilt = VIEWS[1]
    pose = CameraPose.of(nav, pan, tilt)
    rng = np.random.default_rng(7)
    aim = pose.position + 70.0 * pose.rotation[:, 2]
    for east, north in aim[:2] + rng.uniform(-15.0, 15.0, (20, 2)):
        truth = np.array([east, north, ground.up(east, north)])
        u, v = pose.project(COLOR, truth)[0]
        found = geolocate(pose, COLOR, u, v, ground)
        assert found is not None
        assert np.linalg.norm(found - truth) < 0.05


def test_the_flat_world_is_wrong_on_a_slope_and_the_ray_cast_is_not() -> None:
    sloped = GROUNDS["plane sloped 30 %"]
    pose = CameraPose.of(*VIEWS[1])
    truth = np.array([60.0, 10.0, sloped.up(60.0, 10.0)])
    u, v = pose.project(COLOR, truth)[0]
    under = sloped.up(pose.position[0], pose.position[1])  # flat world: the ground below
    flat = geolocate(pose, COLOR, u, v, Ground(flat_up=under))
    cast = geolocate(pose, COLOR, u, v, sloped)
    assert flat is not None and cast is not None
    assert np.linalg.norm(flat - truth) > 1.0
    assert np.linalg.norm(cast - truth) < 0.05


@pytest.mark.parametrize(
    ("origin", "direction", "hit"),
    [
        ((0.0, 0.0, 10.0), (0.0, 0.0, -1.0), (0.0, 0.0, 0.0)),
        ((0.0, 0.0, 10.0), (1.0, 0.0, 0.0), None),  # level
        ((0.0, 0.0, 10.0), (0.0, 0.6, 0.8), None),  # upwards
        ((0.0, 0.0, -5.0), (0.0, 0.0, -1.0), None),  # below the plane already
    ],
)
def test_flat_hit(
    origin: tuple[float, ...], direction: tuple[float, ...], hit: tuple[float, ...] | None
) -> None:
    found = flat_hit(np.array(origin), np.array(direction), 0.0)
    assert (found is None) == (hit is None)
    if hit is not None:
        assert np.allclose(found, hit)  # type: ignore[arg-type]


def test_rays_above_the_horizon_find_no_ground() -> None:
    pose = CameraPose.of(NavPose((0.0, 0.0, 50.0), 0.0, 0.0, 0.0), 0.0, 0.0)  # looking level
    for ground in GROUNDS.values():
        assert geolocate(pose, COLOR, 360.0, 10.0, ground) is None


@pytest.mark.parametrize("ground_name", sorted(GROUNDS))
def test_thermal_pixels_correspond_to_the_colour_pixels_of_the_same_ground_point(
    ground_name: str,
) -> None:
    ground = GROUNDS[ground_name]
    nav = NavPose((5.0, 5.0, 60.0), 0.02, 0.01, 0.3)
    thermal_pose = CameraPose.of(nav, 0.1, 1.3, (0.3, 0.0, 0.45))
    color_pose = CameraPose.of(nav, 0.1, 1.3, (0.3, 0.1, 0.45))  # the colour camera sits aside
    for pixel in [(80.0, 60.0), (5.0, 5.0), (150.0, 110.0)]:
        found = correspond(thermal_pose, THERMAL, color_pose, COLOR, pixel, ground)
        assert found is not None
        truth = geolocate(thermal_pose, THERMAL, *pixel, ground)
        assert truth is not None
        assert np.allclose(found.color_pixel, color_pose.project(COLOR, truth)[0])
        assert found.range_m == pytest.approx(float(np.linalg.norm(truth - thermal_pose.position)))
    # the colour camera zoomed in sees only the middle: a corner pixel has no colour region
    zoomed = Intrinsics.from_fov(720, 576, math.radians(5.0))
    assert correspond(thermal_pose, THERMAL, color_pose, zoomed, (5.0, 5.0), ground) is None
