"""Laser range finder: section 11.2 configurations, rotation mechanism, ray-cast ranges."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.geodesy import GeodeticOrigin
from sim.sensors.errors import SensorError
from sim.sensors.fake_truth import make_truth
from sim.sensors.laser import (
    LaserConfig,
    LaserConfigStatus,
    LaserParams,
    LaserRangeFinder,
    RangeMode,
)
from sim.terrain import Terrain
from sim.world import Building, World
from sim.world_geometry import WorldGeometry

WALL = World(
    name="wall",
    origin=GeodeticOrigin(55.7, 13.47, 95.0),
    terrain=Terrain.flat(-200.0, -200.0, 200.0, 200.0),
    buildings=(
        Building("wall", ((-50.0, 30.0), (50.0, 30.0), (50.0, 31.0), (-50.0, 31.0)), 40.0, 0.0),
    ),
)
FRONT = LaserParams(mount_offset=(0.0, 0.0, 0.0))


@pytest.mark.parametrize(
    ("config", "beams", "scan_time"),
    [
        (LaserConfig(180.0, 1.0), 181, 0.013),
        (LaserConfig(180.0, 0.5), 361, 0.026),
        (LaserConfig(100.0, 0.25), 401, 0.053),
        (LaserConfig(100.0, 1.0, RangeMode.MM_8M), 101, 0.013),
    ],
)
def test_configurations_of_section_11_2(config: LaserConfig, beams: int, scan_time: float) -> None:
    assert config.problem() is None
    assert len(config.beam_angles()) == beams
    assert config.scan_time == scan_time


@pytest.mark.parametrize(
    "config", [LaserConfig(90.0, 1.0), LaserConfig(180.0, 0.3), LaserConfig(180.0, 0.25)]
)
def test_impossible_configurations_are_rejected(config: LaserConfig) -> None:
    lrf = LaserRangeFinder(WorldGeometry(WALL))
    status, reason = lrf.configure(config)
    assert status is LaserConfigStatus.REJECTED and reason
    with pytest.raises(SensorError):
        LaserRangeFinder(WorldGeometry(WALL), config=config)


def test_rotation_mechanism_speed_and_angle() -> None:
    lrf = LaserRangeFinder(WorldGeometry(WALL))
    assert lrf.set_rotation_speed(10.0) is LaserConfigStatus.CLAMPED
    assert lrf.set_rotation_speed(math.nan) is LaserConfigStatus.REJECTED
    assert lrf.set_rotation_speed(math.pi / 2) is LaserConfigStatus.ACCEPTED
    lrf.step(1.0)
    assert lrf.rotation_angle == pytest.approx(math.pi / 2)
    lrf.step(4.0)
    assert lrf.rotation_angle == pytest.approx(math.pi / 2)  # wrapped after a full turn


def test_horizontal_scan_sees_the_wall_at_the_right_ranges() -> None:
    lrf = LaserRangeFinder(WorldGeometry(WALL), FRONT, seed=1)
    scan = lrf.update(make_truth(position_enu=(0.0, 0.0, 10.0)))  # heading north, wall at 30 m
    assert scan is not None
    angles = np.array(scan.beam_angles)
    ranges = np.array(scan.ranges)
    expected = 30.0 / np.cos(angles)
    sees = np.abs(np.tan(angles) * 30.0) <= 50.0
    assert np.allclose(ranges[sees], expected[sees], atol=0.05)
    assert np.all(np.isinf(ranges[~sees]))  # nothing else within 80 m on flat ground at 10 m
    centimetres = ranges[sees] * 100.0
    assert np.allclose(centimetres, np.round(centimetres), atol=1e-6)  # 1 cm resolution


def test_rotated_scan_plane_looks_down_to_the_ground() -> None:
    lrf = LaserRangeFinder(WorldGeometry(WALL), FRONT, seed=1)
    lrf.rotation_angle = math.pi / 2  # scan plane vertical: beams sweep forward-down to forward-up
    scan = lrf.update(make_truth(position_enu=(0.0, 0.0, 10.0)))
    assert scan is not None
    angles = np.array(scan.beam_angles)
    ranges = np.array(scan.ranges)
    down = angles > math.radians(30.0)  # below the horizon: ground before the wall
    assert np.allclose(ranges[down], 10.0 / np.sin(angles[down]), atol=0.05)
    assert scan.rotation_angle == pytest.approx(math.pi / 2)


def test_short_range_mode_limits_range() -> None:
    lrf = LaserRangeFinder(WorldGeometry(WALL), FRONT, LaserConfig(180.0, 1.0, RangeMode.MM_8M))
    scan = lrf.update(make_truth(position_enu=(0.0, 0.0, 10.0)))
    assert scan is not None and all(math.isinf(r) for r in scan.ranges)
