"""Landing: touchdown, refusal, the pad search, and the take-off/hover/path/land sequence."""

from __future__ import annotations

import math
from collections.abc import Callable
from types import ModuleType

import pytest

from hdrc3_control.commands import EstimatedState, EstimatorHealth
from hdrc3_control.event_codec import encode
from hdrc3_control.kernel_functions import FunctionContext, LandingFunction
from hdrc3_control.landing import (
    HeadingSource,
    Landing,
    LandingAid,
    LandingConfig,
    LandingEvent,
    LandingPhase,
    LandingSite,
    LandingTarget,
    landing_heading,
    plan_landing,
    scan_offsets,
    search_height,
)
from hdrc3_control.path_following import PathEvent, PathStatus
from hdrc3_control.ppc_hardware import COLOR
from hdrc3_control.ppc_modes import PadVision
from hdrc3_control.state_estimator import EstimatorConfig
from hdrc3_control.wind_estimate import WindEstimate, WindStatus
from hdrc3_hcsm.control_function import HookResult, Phase
from hdrc3_hcsm.memory import MemoryBank
from hdrc3_perception.pad_fix import fix_sigma
from sim.landing_pattern import PAD_HALF_WIDTH_M

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


SEARCH_H = (6.4 + PAD_HALF_WIDTH_M) / math.tan(COLOR.vfov(0.0) / 2.0)
"""The default search height: 6.4 m of GPS error plus the pattern, in half the vertical FOV."""
OK, DEGRADED, LOST = EstimatorHealth.OK, EstimatorHealth.DEGRADED, EstimatorHealth.LOST
NO_FIX = "no vision fix of pad L1"


@pytest.mark.parametrize(
    ("at", "vision_age", "sites", "health", "aid", "reason", "search"),
    [
        ((110.0, 55.0, 14.0), 0.2, (L1, FAR), OK, LandingAid.VISION, "pad L1", None),
        # near the pad without a fix: a vision landing that searches first
        ((110.0, 55.0, 14.0), 3.0, (L1,), OK, LandingAid.VISION, "pad L1", SEARCH_H),
        ((110.0, 55.0, 14.0), math.inf, (L1,), OK, LandingAid.VISION, "pad L1", SEARCH_H),
        # no search when the navigation is not OK (the failsafe's emergency landing)
        (
            (110.0, 55.0, 14.0),
            math.inf,
            (L1,),
            DEGRADED,
            LandingAid.GPS,
            f"{NO_FIX} (navigation degraded)",
            None,
        ),
        (
            (110.0, 55.0, 14.0),
            math.inf,
            (L1,),
            LOST,
            LandingAid.GPS,
            f"{NO_FIX} (navigation lost)",
            None,
        ),
        # too far to search: as before
        ((120.0, 60.0, 14.0), math.inf, (L1,), OK, LandingAid.GPS, NO_FIX, None),
        (
            (120.0, 60.0, 14.0),
            0.2,
            (L1,),
            OK,
            LandingAid.GPS,
            "pad L1 25.4 m away (over 20 m)",
            None,
        ),
        ((110.0, 55.0, 14.0), 0.2, (), OK, LandingAid.GPS, "no patterned pad in the world", None),
    ],
)
def test_the_landing_point_is_the_pad_on_a_recent_fix_within_20_m(
    at: tuple[float, float, float],
    vision_age: float,
    sites: tuple[LandingSite, ...],
    health: EstimatorHealth,
    aid: LandingAid,
    reason: str,
    search: float | None,
) -> None:
    state = EstimatedState(0.0, at, (0.0, 0.0, 0.0), 0.0, 0.0, 0.3, health=health)
    plan = plan_landing(
        state, 0.3, 1.0, vision_age, sites, LandingConfig(), pad_vision=PadVision.RUNNING
    )
    assert (plan.aid, plan.reason) == (aid, reason)
    assert not plan.engage
    assert plan.search_height == (None if search is None else pytest.approx(search))
    expected = (L1.east, L1.north, L1.ground_height) if aid is LandingAid.VISION else (*at[:2], 1.0)
    target = plan.target
    assert (target.east, target.north, target.ground_height, target.heading) == (*expected, 0.3)


@pytest.mark.parametrize(
    ("pad_vision", "vision_age", "aid", "reason", "search", "engage"),
    [
        # the PPC cannot see the pad: GPS on the pad's GIS position at once, saying why
        (
            PadVision.NONE,
            math.inf,
            LandingAid.GPS,
            f"{NO_FIX}: no vision pipeline (the PPC has no colour camera or pad pose node)",
            None,
            False,
        ),
        (
            PadVision.BUSY,
            3.0,
            LandingAid.GPS,
            f"{NO_FIX}: the PPC's image processing runs another function",
            None,
            False,
        ),
        # ready but idle: the landing engages the pad's pose and searches
        (
            PadVision.READY,
            math.inf,
            LandingAid.VISION,
            "pad L1, its pose engaged by the landing",
            SEARCH_H,
            True,
        ),
        # engaged (by PPCL or starting up) or running: it searches as before
        (PadVision.ENGAGED, math.inf, LandingAid.VISION, "pad L1", SEARCH_H, False),
        (PadVision.RUNNING, math.inf, LandingAid.VISION, "pad L1", SEARCH_H, False),
        # a recent fix: no search
        (PadVision.RUNNING, 0.2, LandingAid.VISION, "pad L1", None, False),
    ],
)
def test_the_landing_searches_only_when_the_ppc_can_see_the_pad(
    pad_vision: PadVision,
    vision_age: float,
    aid: LandingAid,
    reason: str,
    search: float | None,
    engage: bool,
) -> None:
    state = EstimatedState(0.0, (110.0, 55.0, 14.0), (0.0, 0.0, 0.0), 0.0, 0.0, 0.3)
    config = LandingConfig()
    plan = plan_landing(state, 0.3, 1.0, vision_age, (L1,), config, pad_vision=pad_vision)
    assert (plan.aid, plan.reason, plan.engage) == (aid, reason, engage)
    assert plan.search_height == (None if search is None else pytest.approx(search))
    target = plan.target  # the pad's GIS position either way (it is within 20 m)
    assert (target.east, target.north, target.ground_height) == (L1.east, L1.north, 2.0)


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


@pytest.mark.parametrize(
    ("position_sigma", "height"),
    [
        (0.0, 21.06),  # (6.4 m + 1.1 m) / tan(19.6 deg)
        (2.0, 21.06),  # 3 sigma below the GPS error allowance: the allowance
        (2.3, 22.0),  # 3 sigma = 6.9 m: 22.46 m, capped at the ceiling
        (4.0, 22.0),
    ],
)
def test_the_search_height_puts_the_pattern_inside_the_image(
    position_sigma: float, height: float
) -> None:
    config = LandingConfig()
    h = search_height(config, position_sigma)
    assert h == pytest.approx(height, abs=0.01)
    error = max(config.search_position_error, config.search_sigmas * position_sigma)
    edge = math.atan((error + PAD_HALF_WIDTH_M) / h)  # the pattern's far side, off the axis
    if h < config.search_ceiling:
        assert edge == pytest.approx(COLOR.vfov(0.0) / 2.0)  # on the image's edge
    else:
        assert edge > COLOR.vfov(0.0) / 2.0  # capped: too large an error to search for


@pytest.mark.parametrize(
    ("height", "taken"), [(LandingConfig().search_ceiling, True), (25.0, False)]
)
def test_the_filter_takes_fixes_from_the_search_ceiling_but_not_much_higher(
    height: float, taken: bool
) -> None:
    """Ten fixes with ``fix_sigma`` per axis agree to ``vision_reset_spread`` with a margin."""
    spread = math.sqrt(3.0) * fix_sigma(height)  # expected 3-D RMS about their mean
    assert (spread <= 0.85 * EstimatorConfig().vision_reset_spread) == taken


def _at(e: float, n: float, up: float, health: EstimatorHealth = OK) -> EstimatedState:
    return EstimatedState(0.0, (e, n, up), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0, health=health)


@pytest.mark.parametrize(
    ("start_up", "climb", "phase"),
    [
        (5.45, 2.5, LandingPhase.SEARCH),  # 5 m up: climbs at the loop's limit towards 21 m
        (19.45, 1.65, LandingPhase.SEARCH),  # 19 m up: the last 2 m (k_alt 0.8)
        (23.45, 0.0, LandingPhase.SEARCH),  # above the search height: holds, never lower
    ],
)
def test_the_search_climbs_over_the_pad(start_up: float, climb: float, phase: LandingPhase) -> None:
    """8 m east of the pad, heading north: the search climbs and rolls left, towards the pad."""
    fn = Landing()
    here = _at(8.0, 0.0, start_up)
    assert fn.start(here, PAD, search_height=SEARCH_H) is LandingPhase.SEARCH
    out = fn.update(here, 0.0, 0.02)
    assert (out.phase, out.events) == (phase, ())
    assert out.command.vertical == pytest.approx(climb, abs=0.05)
    assert out.command.roll < -0.1


@pytest.mark.parametrize(
    ("fix_at", "seen_from", "events", "search_time"),
    [
        (4.0, None, (LandingEvent.PATTERN_FOUND,), 4.0),
        (None, None, (LandingEvent.SEARCH_TIMED_OUT,), 25.0),
        # fixes arrive from 7 s on that the filter takes only at 30 s: the search waits
        (30.0, 7.0, (LandingEvent.PATTERN_FOUND,), 30.0),
        # ... but not for ever: 25 s + 25 s of patience
        (None, 7.0, (LandingEvent.SEARCH_TIMED_OUT,), 50.0),
        (None, 40.0, (LandingEvent.SEARCH_TIMED_OUT,), 25.0),  # nothing seen by 25 s
    ],
)
def test_the_search_ends_on_a_fix_or_after_the_timeout(
    fix_at: float | None,
    seen_from: float | None,
    events: tuple[LandingEvent, ...],
    search_time: float,
) -> None:
    fn = Landing()
    here = _at(0.0, 0.0, 21.6)
    fn.start(here, PAD, search_height=SEARCH_H)
    seen: list[tuple[float, LandingEvent]] = []
    for k in range(3000):  # 60 s
        t = 100.0 + k * 0.02
        found = fix_at is not None and t - 100.0 >= fix_at - 1e-9
        arriving = seen_from is not None and t - 100.0 >= seen_from - 1e-9
        out = fn.update(here, t, 0.02, precise=found, seen=arriving)
        seen += [(t - 100.0, e) for e in out.events]
    assert [e for _, e in seen] == list(events)
    assert seen[0][0] == pytest.approx(search_time)
    assert fn.search_time == pytest.approx(search_time)
    assert out.phase is LandingPhase.DESCENT  # over the pad: settles, then descends


HOVER_L1 = _at(108.0, 54.0, 8.0)  # 8.9 m from L1's centre, 5.55 m above it
FOUND = "landed on vision: pad L1 (found after a 6.0 s search from 21.1 m)"
FAILED = f"landed on GPS and barometer: {NO_FIX}: the search from 21.1 m failed (25 s)"


@pytest.mark.parametrize(
    ("at", "age_at_land", "ages", "phases", "aid", "note"),
    [
        # a recent fix: no search, the vision landing of before
        (
            HOVER_L1,
            0.2,
            lambda t: 0.2,
            [LandingPhase.APPROACH],
            LandingAid.VISION,
            "landed on vision: pad L1",
        ),
        # no fix: searches; the first fix (6 s on) makes it a vision landing on the pad
        (
            HOVER_L1,
            math.inf,
            lambda t: 0.1 if t >= 6.0 else math.inf,
            [LandingPhase.SEARCH, LandingPhase.APPROACH],
            LandingAid.VISION,
            FOUND,
        ),
        # no fix in 25 s: lands on GPS (on the pad's GIS position) and says the search failed
        (
            HOVER_L1,
            math.inf,
            lambda t: math.inf,
            [LandingPhase.SEARCH, LandingPhase.APPROACH],
            LandingAid.GPS,
            FAILED,
        ),
        # far from the pad: no search, on GPS where it is, as before
        (
            _at(140.0, 50.0, 8.0),
            math.inf,
            lambda t: math.inf,
            [LandingPhase.APPROACH, LandingPhase.DESCENT],
            LandingAid.GPS,
            f"landed on GPS and barometer: {NO_FIX}",
        ),
    ],
)
def test_the_landing_function_searches_for_the_pattern_before_falling_back_to_gps(
    at: EstimatedState,
    age_at_land: float,
    ages: Callable[[float], float],
    phases: list[LandingPhase],
    aid: LandingAid,
    note: str,
) -> None:
    """Driven as the kernel does (20 ms steps, 30 s), the aircraft held still: the phases it
    goes through, the aid it ends on and what the command's Cmd-Finished-EV would say."""
    ctx = FunctionContext(terrain=lambda e, n: 1.0, landing_sites=(L1,))
    ctx.state, ctx.vision_age, ctx.pad_vision = at, age_at_land, PadVision.RUNNING
    fn = LandingFunction(ctx, LandingConfig())
    memory = MemoryBank({"Land-DO": 64})
    memory.write("Land-DO", encode(7, (0.0,)))  # command 7: land, heading north
    assert fn.step(Phase.INITIALIZING, memory, 0.0) is HookResult.DONE
    seen = [fn.phase]
    for k in range(1, 1501):
        ctx.vision_age = ages(k * 0.02)
        assert fn.step(Phase.RUNNING, memory, k * 0.02) is HookResult.BUSY
        if fn.phase is not seen[-1]:
            seen.append(fn.phase)
    assert seen == phases
    assert fn.plan is not None and fn.plan.aid is aid
    assert ctx.notes[7] == f"{note}; heading 0 deg as commanded, no wind estimate"


@pytest.mark.parametrize(
    ("pad_vision", "first_phase", "posted", "note"),
    [
        (
            PadVision.NONE,
            LandingPhase.APPROACH,
            [],
            f"landed on GPS and barometer: {NO_FIX}: no vision pipeline (the PPC has no colour "
            "camera or pad pose node)",
        ),
        (
            PadVision.READY,
            LandingPhase.SEARCH,
            ["Fn-Pad-Engage-EV", "Fn-Pad-Release-EV"],
            "landed on vision: pad L1, its pose engaged by the landing",
        ),
        (PadVision.RUNNING, LandingPhase.SEARCH, [], "landed on vision: pad L1"),
    ],
)
def test_the_landing_engages_the_pads_pose_only_when_the_ppc_has_it_idle(
    pad_vision: PadVision, first_phase: LandingPhase, posted: list[str], note: str
) -> None:
    """Near L1 without a fix: the PPC's report decides between GPS at once and a search, and a
    landing that engaged the pad's pose releases it when it stops (landed, cancelled)."""
    ctx = FunctionContext(terrain=lambda e, n: 1.0, landing_sites=(L1,))
    ctx.state, ctx.pad_vision = _at(110.0, 55.0, 14.0), pad_vision
    fn = LandingFunction(ctx, LandingConfig())
    memory = MemoryBank({"Land-DO": 64})
    memory.write("Land-DO", encode(7, (0.0,)))
    assert fn.step(Phase.INITIALIZING, memory, 0.0) is HookResult.DONE
    assert fn.phase is first_phase
    assert [name for name, _ in ctx.events] == posted[:1]
    plans_on = note.replace("landed on", "landing on")  # said as it starts (Cmd-Accepted-EV)
    if first_phase is LandingPhase.SEARCH:
        plans_on += f"; searching for the pattern from {SEARCH_H:.1f} m first"
    assert ctx.accept_notes[7] == plans_on
    fn.step(Phase.RUNNING, memory, 0.02)
    assert fn.step(Phase.STOPPING, memory, 0.04) is HookResult.DONE
    assert fn.step(Phase.STOPPING, memory, 0.06) is HookResult.DONE  # released once
    assert [name for name, _ in ctx.events] == posted
    assert ctx.notes[7] == f"{note}; heading 0 deg as commanded, no wind estimate"


WEST_8 = WindEstimate(8.0, 0.0, WindStatus.OK)
"""8 m/s blowing east: from the west (into-wind heading 270 deg)."""


@pytest.mark.parametrize(
    ("requested", "wind", "heading", "source"),
    [
        (None, WEST_8, 270.0, HeadingSource.INTO_WIND),  # no heading given: into the wind
        (90.0, WEST_8, 270.0, HeadingSource.INTO_WIND),  # a tailwind landing refused
        (180.0, WEST_8, 270.0, HeadingSource.INTO_WIND),  # crosswind: 90 deg off, too far
        (250.0, WEST_8, 250.0, HeadingSource.COMMANDED),  # 20 deg off the wind: kept
        (299.0, WEST_8, 299.0, HeadingSource.COMMANDED),  # 29 deg: within the 30 deg
        (90.0, WindEstimate(1.0, 1.0, WindStatus.OK), 90.0, HeadingSource.COMMANDED),  # calm
        (None, WindEstimate(1.0, 1.0, WindStatus.OK), 30.0, HeadingSource.CURRENT),
        (None, WindEstimate(0.0, -5.0, WindStatus.SETTLING), 0.0, HeadingSource.INTO_WIND),
        (None, WindEstimate(0.0, 0.0, WindStatus.NONE), 30.0, HeadingSource.CURRENT),
        (90.0, None, 90.0, HeadingSource.COMMANDED),  # no estimate at all
    ],
)
def test_the_landing_heading_is_into_the_estimated_wind_unless_calm(
    requested: float | None,
    wind: WindEstimate | None,
    heading: float,
    source: HeadingSource,
) -> None:
    wanted = None if requested is None else math.radians(requested)
    choice = landing_heading(wanted, math.radians(30.0), wind, LandingConfig())
    assert math.degrees(choice.heading) == pytest.approx(heading)
    assert choice.source is source


@pytest.mark.parametrize(
    ("wind", "text"),
    [
        (WEST_8, "heading 270 deg into the estimated wind 8.0 m/s from 270 deg"),
        (None, "heading 30 deg as it was, no wind estimate"),
        (
            WindEstimate(1.0, 0.0, WindStatus.SETTLING),
            "heading 30 deg as it was, estimated wind 1.0 m/s from 270 deg (settling)",
        ),
    ],
)
def test_the_heading_choice_says_which_heading_and_which_wind(
    wind: WindEstimate | None, text: str
) -> None:
    choice = landing_heading(None, math.radians(30.0), wind, LandingConfig())
    assert choice.describe() == text


def _facing(heading_deg: float) -> EstimatedState:
    """Hovering still 40 m from L1 (a GPS landing where it is, no search), nose at ``heading``."""
    return EstimatedState(0.0, (140.0, 50.0, 8.0), (0.0, 0.0, 0.0), 0.0, 0.0,
                          math.radians(heading_deg))  # fmt: skip


def _heading_deg(fn: LandingFunction) -> float:
    target = fn.core.target
    assert target is not None
    return math.degrees(target.heading)


def _phase(fn: LandingFunction) -> LandingPhase:
    return fn.phase


def test_the_landing_function_turns_into_the_wind_before_the_descent_and_not_after() -> None:
    """No heading in the command: it turns into the estimated wind, follows the estimate while
    it approaches (beyond the hysteresis), descends once the nose is into it, and holds that
    heading from then on; the final reply says the heading and the wind."""
    ctx = FunctionContext(terrain=lambda e, n: 1.0, landing_sites=(L1,))
    ctx.state, ctx.wind = _facing(0.0), WEST_8
    fn = LandingFunction(ctx, LandingConfig())
    memory = MemoryBank({"Land-DO": 64})
    memory.write("Land-DO", encode(7, ()))  # command 7: land, no heading
    assert fn.step(Phase.INITIALIZING, memory, 0.0) is HookResult.DONE
    assert _heading_deg(fn) == pytest.approx(270.0)
    fn.step(Phase.RUNNING, memory, 0.02)
    assert _phase(fn) is LandingPhase.APPROACH  # the nose is still north
    ctx.wind = WindEstimate(8.0, 1.0, WindStatus.OK)  # 7 deg off: within the hysteresis
    fn.step(Phase.RUNNING, memory, 0.04)
    assert _heading_deg(fn) == pytest.approx(270.0)
    ctx.wind = WindEstimate(6.0, 6.0, WindStatus.OK)  # from 225 deg: turns
    fn.step(Phase.RUNNING, memory, 0.06)
    assert _heading_deg(fn) == pytest.approx(225.0)
    ctx.state = _facing(228.0)
    fn.step(Phase.RUNNING, memory, 0.08)
    assert _phase(fn) is LandingPhase.DESCENT
    ctx.wind = WindEstimate(0.0, 8.0, WindStatus.OK)  # from the south now: too late to turn
    fn.step(Phase.RUNNING, memory, 0.10)
    assert _heading_deg(fn) == pytest.approx(225.0)
    assert ctx.notes[7] == (
        f"landed on GPS and barometer: {NO_FIX}; "
        "heading 225 deg into the estimated wind 8.5 m/s from 225 deg"
    )


@pytest.mark.parametrize(("height", "points"), [(SEARCH_H, 7), (10.0, 7), (2.0, 1)])
def test_the_scan_covers_about_twice_the_footprint_of_the_centre(
    height: float, points: int
) -> None:
    """Seven footprints of radius R (the pattern wholly in the image) leave no gap up to about
    2 R of filter error; too low for a footprint, the scan is the centre alone."""
    config = LandingConfig()
    offsets = scan_offsets(config, height)
    assert len(offsets) == points and offsets[0] == (0.0, 0.0)
    reach = height * math.tan(COLOR.vfov(0.0) / 2.0) - PAD_HALF_WIDTH_M
    if points == 1:
        return
    for k in range(360):  # filter errors up to 1.9 R in every direction: some point sees it
        for r in (0.5 * reach, reach * 1.2, reach * 1.9):
            e = (r * math.sin(math.radians(k)), r * math.cos(math.radians(k)))
            assert min(math.dist(o, e) for o in offsets) <= reach


def _aims(fn: Landing, ups: list[float], seen: Callable[[float], bool]) -> list[int]:
    """Which scan point the camera is aimed at, per second (``ups``: the height each second)."""
    out = []
    offsets = scan_offsets(fn.config, SEARCH_H)
    for second, up in enumerate(ups):
        for k in range(50):
            now = second + k * 0.02
            aim = fn.camera_aim(_state(up), now, seen(now))
        assert aim is not None
        out.append(min(range(len(offsets)), key=lambda i: math.dist(offsets[i], aim[:2])))
    return out


@pytest.mark.parametrize(
    ("ups", "seen", "points"),
    [
        # climbing: the pad; at the search height: a new point every 2 s, round the ring
        ([5.45, 12.0, 20.0, *[SEARCH_H + 0.45] * 6], lambda t: False, [0, 0, 0, 0, 0, 1, 1, 2, 2]),
        # fixes the filter has not taken from 2.5 to 4.5 s: the point (1) is held 2 s after the
        # last one, then looked at 2 s more
        ([SEARCH_H + 0.45] * 9, lambda t: 2.5 <= t < 4.5, [0, 0, 1, 1, 1, 1, 1, 1, 2]),
    ],
)
def test_the_search_scans_the_camera_round_the_pad_once_at_its_height(
    ups: list[float], seen: Callable[[float], bool], points: list[int]
) -> None:
    fn = Landing()
    fn.start(_state(ups[0]), PAD, search_height=SEARCH_H)
    assert _aims(fn, ups, seen) == points


def test_no_scan_outside_the_search() -> None:
    fn = Landing()
    fn.start(_state(10.0), PAD)  # no search height: an approach
    assert fn.camera_aim(_state(10.0), 0.0, seen=False) is None
