"""Driving cars: positions on straights, bounded accelerations, continuity, laps, bad drives."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.drive import (
    ACCELERATION,
    CORNER_CUT,
    LATERAL_ACCELERATION,
    DrivePlan,
    drive_pose,
    drive_problem,
)
from sim.world import Drive

STRAIGHT = Drive(((0.0, 0.0), (0.0, 100.0)), 10.0)
"""North 100 m: 25 m to reach 10 m/s (5 s), 50 m at 10 m/s (5 s), 25 m of braking (5 s)."""
SHORT = Drive(((0.0, 0.0), (16.0, 0.0)), 10.0, depart=2.0)
"""East 16 m: peaks at sqrt(32) m/s half way, never at cruise."""
SQUARE = Drive(
    ((0.0, -50.0), (50.0, -50.0), (50.0, 50.0), (-50.0, 50.0), (-50.0, -50.0)), 10.0, True
)
"""A 400 m square loop of left turns, starting half way along its south side."""
ZIGZAG = Drive(
    ((0.0, 0.0), (0.0, 60.0), (30.0, 100.0), (30.0, 160.0), (-40.0, 120.0), (-40.0, 200.0)), 12.0
)
"""Turns of 37, 37, 150 and 150 degrees, left and right, then a stop."""
TRIANGLE = Drive(((0.0, 0.0), (30.0, 0.0), (0.0, 40.0), (0.0, 0.0)), 15.0, True, 1.0)
"""A small loop (closing point repeated) too short to reach cruise on any side."""
DRIVES = {"straight": STRAIGHT, "short": SHORT, "square": SQUARE, "zigzag": ZIGZAG}
DRIVES["triangle"] = TRIANGLE
DT = 0.01


def _samples(plan: DrivePlan, seconds: float) -> dict[str, np.ndarray]:
    times = np.arange(0.0, seconds, DT)
    poses = [plan.pose(float(t)) for t in times]
    return {
        "t": times,
        "e": np.array([p.east for p in poses]),
        "n": np.array([p.north for p in poses]),
        "h": np.array([p.heading for p in poses]),
        "v": np.array([p.speed for p in poses]),
        "s": np.array([p.distance for p in poses]),
    }


def _horizon(plan: DrivePlan) -> float:
    return plan.drive.depart + plan.start_time + 1.5 * plan.lap_time + 2.0


@pytest.mark.parametrize(
    ("drive", "t", "east", "north", "speed"),
    [
        (STRAIGHT, 0.0, 0.0, 0.0, 0.0),
        (STRAIGHT, 1.0, 0.0, 1.0, 2.0),
        (STRAIGHT, 5.0, 0.0, 25.0, 10.0),
        (STRAIGHT, 7.5, 0.0, 50.0, 10.0),
        (STRAIGHT, 11.0, 0.0, 84.0, 8.0),
        (STRAIGHT, 15.0, 0.0, 100.0, 0.0),
        (STRAIGHT, 99.0, 0.0, 100.0, 0.0),
        (SHORT, 1.9, 0.0, 0.0, 0.0),
        (SHORT, 2.0 + math.sqrt(8.0), 8.0, 0.0, math.sqrt(32.0)),
        (SHORT, 2.0 + 2.0 * math.sqrt(8.0), 16.0, 0.0, 0.0),
        (SQUARE, 3.0, 9.0, -50.0, 6.0),
    ],
)
def test_positions_and_speeds_on_straights(
    drive: Drive, t: float, east: float, north: float, speed: float
) -> None:
    pose = drive_pose(drive, t)
    assert (pose.east, pose.north, pose.speed) == pytest.approx((east, north, speed), abs=1e-9)


def test_a_car_waits_facing_along_its_route() -> None:
    pose = DrivePlan.of(ZIGZAG).pose(-5.0)
    assert (pose.east, pose.north, pose.heading, pose.speed) == (0.0, 0.0, 0.0, 0.0)
    assert DrivePlan.of(SQUARE).pose(0.0).heading == pytest.approx(math.pi / 2)


@pytest.mark.parametrize("name", sorted(DRIVES))
def test_speed_and_accelerations_stay_within_bounds(name: str) -> None:
    plan = DrivePlan.of(DRIVES[name])
    x = _samples(plan, _horizon(plan))
    assert x["v"].min() >= 0.0 and x["v"].max() <= plan.drive.speed + 1e-9
    dv = np.diff(x["v"]) / DT
    assert np.abs(dv).max() <= ACCELERATION + 1e-6
    ds = np.diff(x["s"])
    step = np.hypot(np.diff(x["e"]), np.diff(x["n"]))
    assert np.all(step <= ds + 1e-9)  # no jumps: the car never moves further than it drives
    assert np.all(ds >= -1e-12)
    turn = np.abs((np.diff(x["h"]) + math.pi) % math.tau - math.pi)
    moving = ds > 1e-6
    curvature = turn[moving] / ds[moving]
    v_mid = (x["v"][:-1] + x["v"][1:])[moving] / 2.0
    assert np.max(v_mid**2 * curvature) <= LATERAL_ACCELERATION * 1.01


@pytest.mark.parametrize("name", sorted(DRIVES))
def test_heading_is_continuous(name: str) -> None:
    plan = DrivePlan.of(DRIVES[name])
    x = _samples(plan, _horizon(plan))
    turn = np.abs((np.diff(x["h"]) + math.pi) % math.tau - math.pi)
    # at most v / r_min per step: 15 m/s on a 5 m radius for 10 ms is 0.03 rad
    assert turn.max() < 0.03
    assert np.all((x["h"] >= 0.0) & (x["h"] < math.tau))


@pytest.mark.parametrize("name", ["square", "triangle"])
def test_laps_repeat_and_join_without_a_seam(name: str) -> None:
    plan = DrivePlan.of(DRIVES[name])
    lap, t0 = plan.lap_time, plan.drive.depart + plan.start_time
    assert lap > 0.0
    for t in np.linspace(t0, t0 + lap, 37):
        a, b = plan.pose(float(t)), plan.pose(float(t) + 3.0 * lap)
        assert (b.east, b.north, b.speed) == pytest.approx((a.east, a.north, a.speed), abs=1e-6)
        assert b.distance == pytest.approx(a.distance + 3.0 * plan.length, abs=1e-6)
    start = plan.pose(t0)  # back where the first lap began, at the periodic speed
    first = plan.pose(plan.drive.depart)
    assert (start.east, start.north) == pytest.approx((first.east, first.north), abs=1e-6)


def test_the_square_lap_has_its_expected_length_and_time() -> None:
    plan = DrivePlan.of(SQUARE)
    r = CORNER_CUT / (math.sqrt(2.0) - 1.0)
    assert plan.length == pytest.approx(400.0 - 4.0 * (2.0 * r - math.pi * r / 2.0))
    corner = math.sqrt(LATERAL_ACCELERATION * r)
    brake = (10.0**2 - corner**2) / (2.0 * ACCELERATION)
    arc = math.pi * r / 2.0
    side = 100.0 - 2.0 * r
    expected = 4.0 * (arc / corner + 2.0 * (10.0 - corner) / ACCELERATION)
    expected += 4.0 * (side - 2.0 * brake) / 10.0
    assert plan.lap_time == pytest.approx(expected)


def test_a_right_angle_corner_passes_its_cut_inside_the_waypoint_at_corner_speed() -> None:
    plan = DrivePlan.of(SQUARE)
    x = _samples(plan, plan.start_time + plan.lap_time)
    distance = np.hypot(x["e"] - 50.0, x["n"] + 50.0)
    k = int(np.argmin(distance))
    assert distance[k] == pytest.approx(CORNER_CUT, abs=0.01)
    r = CORNER_CUT / (math.sqrt(2.0) - 1.0)
    assert x["v"][k] == pytest.approx(math.sqrt(LATERAL_ACCELERATION * r))
    assert x["h"][k] == pytest.approx(math.pi / 4.0, abs=0.01)


def test_poses_are_a_function_of_time_alone() -> None:
    times = [float(t) for t in np.random.default_rng(1).uniform(-5.0, 300.0, 200)]
    plan = DrivePlan.of(ZIGZAG)
    forward = [plan.pose(t) for t in times]
    backward = [DrivePlan.of(ZIGZAG).pose(t) for t in reversed(times)]
    assert forward == list(reversed(backward))


@pytest.mark.parametrize(
    ("drive", "reason"),
    [
        (Drive(((0.0, 0.0), (0.0, 10.0)), 0.0), "speed must be > 0"),
        (Drive(((0.0, 0.0), (0.0, 10.0)), 15.5), "speed must be > 0 and <= 15.0"),
        (Drive(((0.0, 0.0), (0.0, math.nan)), 5.0), "finite"),
        (Drive(((0.0, 0.0), (0.0, 10.0)), math.inf), "finite"),
        (Drive(((0.0, 0.0), (0.0, 10.0)), 5.0, depart=-1.0), "depart must be >= 0"),
        (Drive(((0.0, 0.0),), 5.0), "at least 2 distinct waypoints"),
        (Drive(((0.0, 0.0), (0.0, 0.0)), 5.0), "at least 2 distinct waypoints"),
        (Drive(((0.0, 0.0), (0.0, 10.0), (0.0, 0.0)), 5.0, True), "at least 3 distinct"),
        (Drive(((0.0, 0.0), (0.0, 10.0), (0.0, 10.05)), 5.0), "closer than 0.1 m"),
        (Drive(((0.0, 0.0), (0.0, 10.0), (1.0, 0.0)), 5.0), "turns by 174 deg at waypoint 1"),
    ],
)
def test_undrivable_drives_are_refused_with_a_reason(drive: Drive, reason: str) -> None:
    problem = drive_problem(drive)
    assert problem is not None and reason in problem
    with pytest.raises(ValueError, match=reason.split(" ")[0]):
        DrivePlan.of(drive)
