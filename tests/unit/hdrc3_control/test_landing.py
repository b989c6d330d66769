"""Landing: touchdown detection, refusal, and the take-off/hover/path/land sequence in the sim."""

from __future__ import annotations

import math
from types import ModuleType

import pytest

from hdrc3_control.commands import EstimatedState, EstimatorHealth
from hdrc3_control.landing import (
    Landing,
    LandingAid,
    LandingConfig,
    LandingPhase,
    LandingSite,
    LandingTarget,
    plan_landing,
)
from hdrc3_control.path_following import PathEvent, PathStatus

PAD = LandingTarget(0.0, 0.0, 0.0, 0.0)


def _state(
    z: float,
    on_ground: bool = False,
    vz: float = 0.0,
    health: EstimatorHealth = EstimatorHealth.OK,
) -> EstimatedState:
    return EstimatedState(
        0.0, (0.0, 0.0, z), (0.0, 0.0, vz), 0.0, 0.0, 0.0, on_ground=on_ground, health=health
    )


@pytest.mark.parametrize(("height", "rate"), [(20.0, 1.0), (8.0, 0.5), (4.0, 0.25), (0.6, 0.25)])
def test_descent_rate_slows_down_near_the_ground(height: float, rate: float) -> None:
    fn = Landing()
    fn.start(_state(height + 0.45), PAD)
    out = fn.update(_state(height + 0.45), 0.0, 0.02)
    assert out.phase is LandingPhase.DESCENT
    assert out.command.vertical == pytest.approx(-rate)


@pytest.mark.parametrize(
    ("health", "vz", "vertical"),
    [
        (EstimatorHealth.OK, -2.0, -0.25),  # the YACS's climb-rate hold works: the rate as is
        (EstimatorHealth.DEGRADED, 1.0, -0.25),
        (EstimatorHealth.LOST, -0.25, -0.25),  # on the rate: no correction
        (EstimatorHealth.LOST, -2.0, 1.5),  # falling: -0.25 + (-0.25 + 2)
        (EstimatorHealth.LOST, 1.0, -1.5),  # climbing: -0.25 + (-0.25 - 1)
    ],
)
def test_descent_without_inertial_navigation_feeds_back_the_filters_vertical_rate(
    health: EstimatorHealth, vz: float, vertical: float
) -> None:
    fn = Landing()
    fn.start(_state(4.45, health=health), PAD)
    out = fn.update(_state(4.45, vz=vz, health=health), 0.0, 0.02)
    assert out.phase is LandingPhase.DESCENT
    assert out.command.vertical == pytest.approx(vertical)


def test_touchdown_needs_consecutive_contacts_then_engine_shutdown() -> None:
    fn = Landing()
    fn.start(_state(1.0), PAD)
    phases = []
    contacts = [True, False, True, True, True] + [True] * 60
    for k, contact in enumerate(contacts):
        out = fn.update(_state(0.45, contact), k * 0.02, 0.02)
        phases.append(out.phase)
    assert phases[:4] == [LandingPhase.DESCENT] * 4
    assert phases[4] is LandingPhase.TOUCHDOWN
    assert out.phase is LandingPhase.LANDED and out.engine_shutdown
    assert out.touchdown_time == pytest.approx(0.08)


def test_refused_on_the_ground() -> None:
    assert Landing().start(_state(0.45, True), PAD) is LandingPhase.REFUSED_ON_GROUND


def test_takeoff_hover_path_land_sequence(harness: ModuleType) -> None:
    f = harness.SimFlight(seed=9, placement=harness.FIGURE7_START)
    f.start_engine()
    up = harness.takeoff(f, 12.0)
    assert up.ok
    settle = harness.hover(f, up.outputs[-1].hover_point, 20.0, up.integral, until_stable=True)
    assert settle.ok
    path = harness.figure7_path(f.state().position)
    run = harness.fly_path(f, path, settle.integral)
    assert run.ok and run.outputs[-1].status is PathStatus.ARRIVED
    events = [e for o in run.outputs for e in o.events]
    assert events == [
        PathEvent.REQUEST_SEGMENT,
        PathEvent.SEGMENT_SWITCHED,
        PathEvent.REQUEST_SEGMENT,
        PathEvent.SEGMENT_SWITCHED,
        PathEvent.ARRIVED,
    ]
    assert max(o.speed_ref - o.speed_limit for o in run.outputs) <= 1e-9
    hp = run.outputs[-1].hover_point
    hold = harness.hover(
        f, harness.HoverSetpoint(hp, f.state().heading), 30.0, run.integral, until_stable=True
    )
    assert hold.ok
    e, n, _ = hp
    down = harness.land(f, LandingTarget(e, n, 0.0, f.state().heading), hold.integral)
    assert down.ok and down.outputs[-1].engine_shutdown
    vz, vh = harness.touchdown_velocity(f, down.first_tick)
    assert vz <= 0.35 and vh <= 0.15
    assert math.hypot(f.truth().position_enu[0] - e, f.truth().position_enu[1] - n) < 5.0


L1 = LandingSite("L1", 100.0, 50.0, 2.0)
FAR = LandingSite("F", 400.0, 50.0, 0.0)


@pytest.mark.parametrize(
    ("at", "vision_age", "sites", "aid", "reason"),
    [
        ((110.0, 55.0, 14.0), 0.2, (L1, FAR), LandingAid.VISION, "pad L1"),
        ((110.0, 55.0, 14.0), 3.0, (L1,), LandingAid.GPS, "no vision fix of pad L1"),
        ((110.0, 55.0, 14.0), math.inf, (L1,), LandingAid.GPS, "no vision fix of pad L1"),
        ((120.0, 60.0, 14.0), 0.2, (L1,), LandingAid.GPS, "pad L1 25.4 m away (over 20 m)"),
        ((110.0, 55.0, 14.0), 0.2, (), LandingAid.GPS, "no patterned pad in the world"),
    ],
)
def test_the_landing_point_is_the_pad_on_a_recent_fix_within_20_m(
    at: tuple[float, float, float],
    vision_age: float,
    sites: tuple[LandingSite, ...],
    aid: LandingAid,
    reason: str,
) -> None:
    state = EstimatedState(0.0, at, (0.0, 0.0, 0.0), 0.0, 0.0, 0.3)
    plan = plan_landing(state, 0.3, 1.0, vision_age, sites, LandingConfig())
    assert (plan.aid, plan.reason) == (aid, reason)
    expected = (L1.east, L1.north, L1.ground_height) if aid is LandingAid.VISION else (*at[:2], 1.0)
    target = plan.target
    assert (target.east, target.north, target.ground_height, target.heading) == (*expected, 0.3)


@pytest.mark.parametrize(("precise", "roll_towards_pad"), [(True, True), (False, False)])
def test_the_final_descent_holds_the_pad_only_on_precise_positions(
    precise: bool, roll_towards_pad: bool
) -> None:
    """0.5 m east of the pad at 3 m: on vision fixes the loop closes the gap, on GPS it holds
    its velocity (a GPS position jump must not become horizontal speed at touchdown)."""
    fn = Landing()
    state = EstimatedState(0.0, (0.5, 0.0, 3.45), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0)
    fn.start(_state(3.45), PAD)
    fn.update(_state(3.45), 0.0, 0.02)  # settled over the pad: descending
    out = fn.update(state, 0.02, 0.02, precise=precise)
    assert out.phase is LandingPhase.DESCENT
    roll = out.command.roll  # heading north: the pad to the west is a left (negative) roll
    assert (roll < -1e-3, abs(roll) < 1e-3) == (roll_towards_pad, not roll_towards_pad), roll
