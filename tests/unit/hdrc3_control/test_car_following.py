"""The car's estimate and the following law of fcl_track (pure core, point-mass closed loop)."""

from __future__ import annotations

import dataclasses
import itertools
import math
import random
import statistics
from collections.abc import Callable

import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_control.car_following import (
    CarFollower,
    CarFollowingConfig,
    FixVerdict,
    FollowMode,
    TargetEstimate,
    TargetEstimator,
    TargetFix,
)
from hdrc3_control.commands import EstimatedState
from hdrc3_control.outer_loop import Reference
from sim.drive import DrivePlan, DrivePose
from sim.world import Drive
from sim.world_loader import load_world

FIX_PERIOD = 0.2
"""s between two colour images (the tracker's rate)."""
LATENCY = 0.15
"""s from an image to the control tick that reads its fix."""
TICK = 0.02


def chase_plan(depart: float = 0.0) -> DrivePlan:
    """The drive of car chase1 in world revinge_chase (10 m/s laps, 90 degree corners)."""
    (car,) = [o for o in load_world("revinge_chase").objects if o.id == "chase1"]
    assert car.drive is not None
    return DrivePlan.of(dataclasses.replace(car.drive, depart=depart))


def straight_plan() -> DrivePlan:
    """10 m/s due east (from rest at t = 0)."""
    return DrivePlan.of(Drive(((0.0, 0.0), (2000.0, 0.0)), 10.0))


def fixes(plan: DrivePlan, until: float, sigma: float, seed: int = 1) -> list[TargetFix]:
    """The tracker's fixes of ``plan``'s car every FIX_PERIOD with ``sigma`` m noise per axis."""
    rng = random.Random(seed)
    out = []
    for k in range(round(until / FIX_PERIOD)):
        pose = plan.pose(k * FIX_PERIOD)
        e, n = pose.east + rng.gauss(0.0, sigma), pose.north + rng.gauss(0.0, sigma)
        out.append(TargetFix(k * FIX_PERIOD, (e, n, 0.75)))
    return out


def error(estimate: TargetEstimate, pose: DrivePose) -> tuple[float, float]:
    """Position and velocity error of the estimate, m and m/s."""
    ve, vn = pose.speed * math.sin(pose.heading), pose.speed * math.cos(pose.heading)
    position = math.hypot(estimate.position[0] - pose.east, estimate.position[1] - pose.north)
    return position, math.hypot(estimate.velocity[0] - ve, estimate.velocity[1] - vn)


# --- configuration ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"distance": 0.0}, "distance"),
        ({"max_speed": math.nan}, "max_speed"),
        ({"lost_timeout": -1.0}, "lost_timeout"),
        ({"stop_speed": 3.0}, "below moving_speed"),
        ({"max_gated": 0}, "max_gated"),
        ({"distance": 300.0}, "max_range"),
    ],
)
def test_bad_configuration_is_refused(change: dict[str, float], words: str) -> None:
    with pytest.raises(ConfigError, match=words):
        CarFollowingConfig(**change)  # type: ignore[arg-type]


# --- the estimate -------------------------------------------------------------------------------


@pytest.mark.parametrize(("sigma", "position_bound", "velocity_bound"), [(3.0, 2.5, 1.5)])
def test_estimate_converges_on_a_straight_drive(
    sigma: float, position_bound: float, velocity_bound: float
) -> None:
    plan, est = straight_plan(), TargetEstimator()
    errors = []
    for fix in fixes(plan, 40.0, sigma):
        verdict = est.update(fix)
        assert verdict in (FixVerdict.STARTED, FixVerdict.ACCEPTED)
        estimate = est.predict(fix.time + LATENCY)
        assert estimate is not None
        if fix.time > 15.0:  # at cruise speed (10 m/s after 5 s) and settled
            errors.append(error(estimate, plan.pose(fix.time + LATENCY)))
    assert statistics.mean(e[0] for e in errors) < position_bound
    assert statistics.mean(e[1] for e in errors) < velocity_bound
    assert max(e[0] for e in errors) < 3 * position_bound


@pytest.mark.parametrize(
    ("jump", "verdicts"),
    [
        (40.0, [FixVerdict.GATED, FixVerdict.ACCEPTED]),  # one wild fix: dropped
        (2.0, [FixVerdict.ACCEPTED, FixVerdict.ACCEPTED]),  # within the noise: taken
    ],
)
def test_an_outlier_is_gated(jump: float, verdicts: list[FixVerdict]) -> None:
    plan, est = straight_plan(), TargetEstimator()
    series = fixes(plan, 20.0, 1.0)
    for fix in series[:-2]:
        est.update(fix)
    before = est.predict(series[-2].time)
    assert before is not None
    odd = series[-2]
    odd = TargetFix(odd.time, (odd.position[0], odd.position[1] + jump, odd.position[2]))
    assert [est.update(odd), est.update(series[-1])] == verdicts
    after = est.predict(series[-1].time)
    assert after is not None and abs(after.position[1]) < 3.0


def test_outliers_in_a_row_restart_the_estimate_at_the_new_place() -> None:
    config = CarFollowingConfig()
    est = TargetEstimator(config)
    for k in range(20):
        est.update(TargetFix(k * FIX_PERIOD, (0.0, 0.0, 0.0)))
    moved = [
        TargetFix(4.0 + k * FIX_PERIOD, (100.0, 0.0, 0.0)) for k in range(config.max_gated + 1)
    ]
    verdicts = [est.update(fix) for fix in moved]
    assert verdicts == [FixVerdict.GATED] * config.max_gated + [FixVerdict.RESTARTED]
    estimate = est.predict(moved[-1].time)
    assert estimate is not None and estimate.position[:2] == (100.0, 0.0)


@pytest.mark.parametrize(
    ("fix", "verdict"),
    [
        (TargetFix(0.5, (1.0, 1.0, 0.0)), FixVerdict.STALE),
        (TargetFix(2.0, (math.nan, 1.0, 0.0)), FixVerdict.INVALID),
        (TargetFix(math.inf, (1.0, 1.0, 0.0)), FixVerdict.INVALID),
    ],
)
def test_stale_and_invalid_fixes_are_dropped(fix: TargetFix, verdict: FixVerdict) -> None:
    est = TargetEstimator()
    est.update(TargetFix(1.0, (0.0, 0.0, 0.0)))
    assert est.update(fix) is verdict
    assert est.counts[verdict] == 1


def test_speed_is_bounded_and_prediction_stops_after_the_extrapolation_limit() -> None:
    config = CarFollowingConfig(max_target_speed=12.0, max_extrapolation=1.0, gate=100.0)
    est = TargetEstimator(config)
    for k in range(10):  # 50 m/s: faster than any car
        est.update(TargetFix(k * FIX_PERIOD, (50.0 * k * FIX_PERIOD, 0.0, 0.0)))
    estimate = est.predict(est.time)
    assert estimate is not None and estimate.speed <= 12.0 + 1e-9
    late, later = est.predict(est.time + 1.0), est.predict(est.time + 5.0)
    assert late is not None and later is not None
    assert later.position == late.position and later.velocity == (0.0, 0.0)
    assert est.predict(est.time + 5.0) is not None and TargetEstimator().predict(0.0) is None


# --- the following law --------------------------------------------------------------------------


def state_at(position: tuple[float, float, float], heading: float = 0.0) -> EstimatedState:
    return EstimatedState(0.0, position, (0.0, 0.0, 0.0), 0.0, 0.0, heading)


def still(e: float, n: float) -> TargetEstimate:
    return TargetEstimate(0.0, (e, n, 0.0), (0.0, 0.0), 1.0, 0.0)


@pytest.mark.parametrize(
    ("aircraft", "car", "standoff"),
    [
        ((0.0, 0.0, 30.0), (0.0, 50.0), (0.0, 30.0)),  # car north: standoff 20 m south of it
        ((0.0, 0.0, 30.0), (-40.0, 0.0), (-20.0, 0.0)),  # car west
        ((0.0, 0.0, 30.0), (3.0, 4.0), (-9.0, -12.0)),  # too close: back off on the bearing
    ],
)
def test_a_standing_car_is_held_at_the_distance_on_the_current_bearing(
    aircraft: tuple[float, float, float], car: tuple[float, float], standoff: tuple[float, float]
) -> None:
    follower = CarFollower()
    follower.start(state_at(aircraft), still(*car))
    out = follower.update(state_at(aircraft), still(*car), TICK)
    assert out.mode is FollowMode.BEARING
    assert out.reference.position == pytest.approx((*standoff, 30.0), abs=1e-6)
    bearing = math.atan2(car[0] - aircraft[0], car[1] - aircraft[1]) % math.tau
    assert out.reference.heading == pytest.approx(bearing)
    assert out.reference.velocity == (0.0, 0.0, 0.0)


def test_a_driving_car_is_followed_from_behind_with_its_velocity_fed_forward() -> None:
    follower = CarFollower()
    aircraft = state_at((0.0, -20.0, 25.0))
    driving = TargetEstimate(0.0, (0.0, 0.0, 0.0), (0.0, 10.0), 1.0, 0.0)
    follower.start(aircraft, driving)
    outs = [follower.update(aircraft, driving, TICK) for _ in range(400)]
    ref = outs[-1].reference
    assert outs[-1].mode is FollowMode.BEHIND
    assert ref.position == pytest.approx((0.0, -20.0, 25.0), abs=1e-6)
    assert ref.velocity == pytest.approx((0.0, 10.0, 0.0), abs=1e-3)
    accel = [math.hypot(*o.reference.acceleration) for o in outs]
    assert max(accel) <= follower.config.max_accel + 1e-9  # the ramp to 10 m/s is limited


def test_the_standoff_point_swings_round_at_a_bounded_rate() -> None:
    follower = CarFollower()
    aircraft = state_at((0.0, -20.0, 25.0))
    north = TargetEstimate(0.0, (0.0, 0.0, 0.0), (0.0, 10.0), 1.0, 0.0)
    east = TargetEstimate(0.0, (0.0, 0.0, 0.0), (10.0, 0.0), 1.0, 0.0)
    follower.start(aircraft, north)
    follower.update(aircraft, north, TICK)
    looks = [follower.update(aircraft, east, TICK).look for _ in range(1000)]
    rates = [abs(b - a) / TICK for a, b in itertools.pairwise(looks)]
    assert max(rates) <= follower.config.max_swing_rate + 1e-9
    assert looks[-1] == pytest.approx(math.pi / 2, abs=math.radians(2.0))


# --- closed loop on a point mass ----------------------------------------------------------------


def point_mass(
    plan: DrivePlan, start: tuple[float, float], seconds: float, sigma: float
) -> list[tuple[float, float]]:
    """Follow ``plan``'s car from ``start`` with a point mass (outer loop law, |a| <= 4 m/s^2).

    Returns (time, horizontal distance to the true car) of every tick.
    """
    config = CarFollowingConfig()
    g = config.gains
    est, follower = TargetEstimator(config), CarFollower(config)
    series = fixes(plan, seconds, sigma)
    p, v = [start[0], start[1]], [0.0, 0.0]
    out: list[tuple[float, float]] = []
    started = False
    for k in range(round(seconds / TICK)):
        t = k * TICK
        while series and series[0].time + LATENCY <= t:
            est.update(series.pop(0))
        target = est.predict(t)
        if target is None:
            continue
        state = EstimatedState(t, (p[0], p[1], 30.0), (v[0], v[1], 0.0), 0.0, 0.0, 0.0)
        if not started:
            follower.start(state, target)
            started = True
        ref: Reference = follower.update(state, target, TICK).reference
        cx, cy = g.k_pos * (ref.position[0] - p[0]), g.k_pos * (ref.position[1] - p[1])
        norm = max(1.0, math.hypot(cx, cy) / g.max_correction)
        ax = ref.acceleration[0] + g.k_vel * (ref.velocity[0] + cx / norm - v[0])
        ay = ref.acceleration[1] + g.k_vel * (ref.velocity[1] + cy / norm - v[1])
        scale = max(1.0, math.hypot(ax, ay) / 4.0)
        v = [v[0] + ax / scale * TICK, v[1] + ay / scale * TICK]
        p = [p[0] + v[0] * TICK, p[1] + v[1] * TICK]
        car = plan.pose(t)
        out.append((t, math.hypot(car.east - p[0], car.north - p[1])))
    return out


Scenario = Callable[[], tuple[DrivePlan, tuple[float, float]]]


@pytest.mark.parametrize(
    ("scenario", "settle", "low", "high"),
    [
        (lambda: (straight_plan(), (-20.0, 0.0)), 15.0, 17.0, 23.0),
        (lambda: (chase_plan(), (80.0, -100.0)), 10.0, 9.0, 31.0),  # three 90 degree corners
    ],
)
def test_point_mass_keeps_the_distance(
    scenario: Scenario, settle: float, low: float, high: float
) -> None:
    plan, start = scenario()
    distances = [d for t, d in point_mass(plan, start, 90.0, 3.0) if t > settle]
    assert low < min(distances) and max(distances) < high
    assert abs(statistics.mean(distances) - 20.0) < 2.0
