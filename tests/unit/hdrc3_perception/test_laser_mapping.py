"""Laser map building: registration with the navigation pose, the grid, what is dropped and why."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_perception.camera import NavPose
from hdrc3_perception.laser_mapping import (
    Drop,
    LaserMapper,
    MapperConfig,
    ScanLine,
    TimedPose,
    interpolate,
)
from sim.airframe import scan_rays
from sim.sensors.laser import LaserConfig
from sim.world import World
from sim.world_geometry import WorldGeometry
from sim.world_loader import load_world

BEAMS = LaserConfig().beam_angles()
AREA = (10.0, -70.0, 60.0, -15.0)
"""Around building B05 (east 19.8..48.7, north -62.3..-22.7, 5 m high)."""


@functools.cache
def world() -> World:
    return load_world("revinge")


@functools.cache
def geometry() -> WorldGeometry:
    return WorldGeometry(world())


def scan(time: float, pose: NavPose, rotation: float) -> ScanLine:
    """The scan line the true world returns for a pose (no range noise)."""
    origin, directions = scan_rays(
        pose.position, (pose.roll, pose.pitch, pose.heading), rotation, BEAMS
    )
    ranges = geometry().ray_cast_many(tuple(origin), directions, 80.0)
    return ScanLine(time, rotation, float(BEAMS[0]), float(BEAMS[1] - BEAMS[0]), ranges)


def fly_over(mapper: LaserMapper, offset: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
    """North along east 34 at 25 m, 13 ms scans, a state every 40 ms (``offset``: its error)."""
    for k in range(1500):
        t = 0.013 * k
        true = NavPose((34.0, -80.0 + 4.0 * t, 25.0), 0.0, 0.0, 0.0)
        mapper.add_scan(scan(t, true, (3.0 * t) % math.tau))
        if k % 3 == 0:
            p = true.position
            nav = NavPose((p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]), 0.0, 0.0, 0.0)
            mapper.add_state(t, nav)


def test_a_pass_over_a_building_maps_its_roof_and_the_ground_around_it() -> None:
    mapper = LaserMapper(AREA)
    fly_over(mapper)
    m = mapper.snapshot("b05")
    err = (m.heights - m.cell_tops(world().surface_heights))[m.mapped]
    assert m.mapped.mean() > 0.9
    assert float(np.sqrt(np.mean(err**2))) < 0.3
    roof = m.heights_at(np.array([34.0]), np.array([-40.0]))[0]
    assert roof == pytest.approx(world().surface_heights(np.array(34.0), np.array(-40.0)), abs=0.1)


def test_the_map_carries_the_navigation_error_not_the_truth() -> None:
    mapper = LaserMapper(AREA)
    fly_over(mapper, offset=(0.0, 0.0, 0.8))  # the filter believes it is 0.8 m higher
    m = mapper.snapshot("high")
    roof = m.heights_at(np.array([34.0]), np.array([-40.0]))[0]
    assert roof - float(world().surface_heights(np.array(34.0), np.array(-40.0))) == (
        pytest.approx(0.8, abs=0.1)
    )


def pose(east: float, heading_deg: float) -> NavPose:
    return NavPose((east, 0.0, 10.0), 0.0, 0.0, math.radians(heading_deg))


@pytest.mark.parametrize(
    ("a", "b", "time", "east", "heading_deg"),
    [
        (pose(0.0, 10.0), pose(4.0, 30.0), 0.5, 2.0, 20.0),
        (pose(0.0, 350.0), pose(4.0, 10.0), 0.25, 1.0, 355.0),  # across north, not the long way
        (pose(0.0, 10.0), pose(4.0, 30.0), 2.0, 4.0, 30.0),  # clamped to the later state
    ],
)
def test_the_pose_at_a_scans_time_is_interpolated_between_two_states(
    a: NavPose, b: NavPose, time: float, east: float, heading_deg: float
) -> None:
    got = interpolate(TimedPose(0.0, a), TimedPose(1.0, b), time)
    assert got.position[0] == pytest.approx(east)
    assert math.degrees(got.heading) == pytest.approx(heading_deg)


FLAT = NavPose((34.0, -40.0, 25.0), 0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("events", "drop"),
    [
        ([("scan", 0.0), ("state", 0.1)], Drop.BEFORE_FIRST_STATE),
        ([("state", 0.0), ("scan", 0.5), ("state", 1.0)], Drop.STATE_GAP),
        ([("state", 1.0), ("scan", 0.2)], Drop.STATE_GAP),  # far older than the last state
        ([("state", 0.0), ("nan", 0.01)], Drop.MALFORMED),
    ],
)
def test_scans_that_cannot_be_registered_are_counted_by_reason(
    events: list[tuple[str, float]], drop: Drop
) -> None:
    mapper = LaserMapper(AREA)
    for kind, t in events:
        if kind == "state":
            mapper.add_state(t, FLAT)
        else:
            line = scan(t, FLAT, 0.0)
            if kind == "nan":
                line = ScanLine(t, math.nan, line.angle_min, line.angle_increment, line.ranges)
            mapper.add_scan(line)
    assert mapper.dropped[drop] == 1
    assert mapper.points == 0


def test_a_full_queue_drops_the_oldest_scan() -> None:
    mapper = LaserMapper(AREA, MapperConfig(queue=3))
    mapper.add_state(0.0, FLAT)
    for k in range(4):
        mapper.add_scan(scan(0.01 * (k + 1), FLAT, 0.0))
    assert mapper.dropped[Drop.QUEUE_FULL] == 1
    assert len(mapper.add_state(0.05, FLAT)) == 3


@pytest.mark.parametrize(
    ("bounds", "config", "reason"),
    [
        (AREA, MapperConfig(resolution=0.0), "resolution must be within"),
        (AREA, MapperConfig(max_range_used=90.0), "max_range_used <= 80"),
        (AREA, MapperConfig(min_returns=0), "must be positive"),
        ((0.0, 0.0, -1.0, 5.0), MapperConfig(), "min < max"),
        ((0.0, 0.0, math.inf, 5.0), MapperConfig(), "finite"),
    ],
)
def test_impossible_mappers_are_refused_with_a_reason(
    bounds: tuple[float, float, float, float], config: MapperConfig, reason: str
) -> None:
    with pytest.raises(ConfigError, match=reason):
        LaserMapper(bounds, config)
