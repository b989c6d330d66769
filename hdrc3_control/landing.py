"""Landing control mode (Landing automaton, fcl_land): controlled descent onto a landing point.

Phases: SEARCH (only without a recent vision fix near a patterned pad: climb over the pad until
the pattern is seen, :func:`search_height`), APPROACH (hover over the landing point at the current
height with the landing heading), DESCENT (descend with a rate that slows down with the estimated
height above the ground) and TOUCHDOWN (skid switch closed for ``touchdown_ticks`` consecutive
ticks, a timely detection: early detection loads the skids, late detection causes ground
resonance), then LANDED with an engine shutdown request. The height above ground comes from the
navigation filter; a vision pose (the landing pattern) enters through
``StateEstimator.update_vision`` (the hook of chapter 5.4).

Which aid (§5.4, :func:`plan_landing`): with a vision fix accepted within ``vision_recent`` and
a patterned pad within ``engage_radius`` (the chapter's 20 m hemisphere) the landing point is
the pad's centre and the position is held on it down to the skids while fixes keep coming;
near such a pad (within ``engage_radius``) without a recent fix, the pattern must be seen first:
the landing starts with SEARCH over the pad and becomes a vision landing on the first accepted fix,
or a GPS landing on the pad's GIS position after ``search_timeout``. The search needs the PPC
to be able to see the pad (its ``PadVision`` report, ``ppc/pad_vision``): without a camera and
pad pose pipeline, or with image processing busy with another function, no fix can come, and the
landing lands on the pad's GIS position on GPS at once and says why. When the pipeline is ready
but idle, the plan says to engage it (``LandingPlan.engage``; the landing function does, through
the Pad Vision automaton, and releases it when it ends). Otherwise (no pad nearby, or
navigation not OK) the aircraft lands where it is on GPS and the barometer, and below
``final_height`` holds only its velocity (GPS position jitter would become horizontal speed at
touchdown).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from typing import Protocol

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import (
    AttitudeCommand,
    EstimatedState,
    EstimatorHealth,
    Vec3,
    wrap_pi,
)
from hdrc3_control.outer_loop import OuterLoop, OuterLoopGains, Reference
from hdrc3_control.ppc_hardware import COLOR, CameraSpec
from hdrc3_control.ppc_modes import CAN_SEE_PAD, PadVision
from hdrc3_control.wind_estimate import WindEstimate, WindStatus
from sim.landing_pattern import PAD_HALF_WIDTH_M


class LandingPhase(enum.Enum):
    """Phase of the landing function."""

    SEARCH = "search"
    """Near a patterned pad without a recent vision fix: over the pad at the search height until
    a fix is accepted or ``search_timeout`` (§5.4: the pattern is seen before a vision landing)."""
    APPROACH = "approach"
    DESCENT = "descent"
    TOUCHDOWN = "touchdown"
    LANDED = "landed"
    REFUSED_ON_GROUND = "refused_on_ground"


class HeadingSource(enum.Enum):
    """Why the landing heading is what it is (:func:`landing_heading`)."""

    INTO_WIND = "into_wind"
    """Nose into the on-board wind estimate (§5.4: no tailwind landings)."""
    COMMANDED = "commanded"
    """The land command's heading (calm, or the wind within ``headwind_tolerance`` of it)."""
    CURRENT = "current"
    """No heading commanded and no wind to turn into: the heading the aircraft has."""


class LandingEvent(enum.Enum):
    """What happened in one tick (``LandingOutput.events``)."""

    PATTERN_FOUND = "pattern_found"
    """A vision fix ended the search: a vision landing on the pad."""
    SEARCH_TIMED_OUT = "search_timed_out"
    """No fix within ``search_timeout``: the landing goes on, on GPS and the barometer."""


@dataclass(frozen=True, slots=True)
class LandingTarget:
    """Where to land: the point on the ground and the landing heading."""

    east: float
    north: float
    ground_height: float
    """Terrain (pad) height, ENU up, m."""
    heading: float

    def __post_init__(self) -> None:
        """Reject non-finite targets."""
        if not all(math.isfinite(v) for v in (self.east, self.north, self.ground_height)):
            raise ConfigError("landing target must be finite")


class LandingAid(enum.Enum):
    """What the landing point and the final descent rest on."""

    VISION = "vision"
    """The pad's pattern: its fixes in the navigation filter (§5.4)."""
    GPS = "gps"
    """GPS and the barometer: the landing point is where the aircraft is."""


@dataclass(frozen=True, slots=True)
class LandingSite:
    """A pad carrying the vision landing pattern, in the world's ENU frame."""

    name: str
    east: float
    north: float
    ground_height: float
    """Height of the pad's surface, ENU up, m."""


class Pad(Protocol):
    """A pad of the world file (``sim.world.LandingPad``)."""

    @property
    def name(self) -> str:
        """The pad's name."""

    @property
    def east(self) -> float:
        """East of the world's origin, m."""

    @property
    def north(self) -> float:
        """North of the world's origin, m."""

    @property
    def pattern(self) -> bool:
        """Whether it carries the vision landing pattern."""


def landing_sites(
    pads: Iterable[Pad], terrain: Callable[[float, float], float]
) -> tuple[LandingSite, ...]:
    """The pads that carry the vision landing pattern, on the terrain."""
    return tuple(
        LandingSite(p.name, p.east, p.north, terrain(p.east, p.north)) for p in pads if p.pattern
    )


@dataclass(frozen=True, slots=True)
class LandingConfig:
    """Descent schedule and touchdown detection."""

    cg_above_skids: float = 0.45
    approach_radius: float = 1.0
    """Horizontal distance to the landing point before descending, m."""
    approach_speed: float = 0.5
    """Horizontal speed below which the approach counts as settled, m/s."""
    descent_fast: float = 1.0
    """m/s above ``slow_height``."""
    descent_slow: float = 0.5
    slow_height: float = 12.0
    descent_final: float = 0.25
    """m/s below ``final_height`` down to the touchdown (the chapter: 0.18-0.35 m/s)."""
    final_height: float = 6.0
    lost_vertical_damping: float = 1.0
    """Without a usable inertial solution (``EstimatorHealth.LOST``): the climb-rate command
    becomes ``rate + k * (rate - vz)`` on the filter's GPS/barometer vertical velocity, 1 (see
    :meth:`Landing._vertical`)."""
    vision_recent: float = 1.0
    """A vision fix accepted within this makes a vision landing; during one, fixes within this
    keep the position held on the pad below ``final_height``, s."""
    engage_radius: float = 20.0
    """A vision landing engages within this distance of the pad's centre (§5.4 requirement 1), m."""
    search_position_error: float = 6.4
    """Horizontal error of the GPS position the search allows for, m (:func:`search_height`).

    The filter does not know it (its GPS model is white, ``EstimatorConfig``): standalone GPS
    is off by a correlated ~2 m in the open (§11.1.1, the simulator's receiver 1.5 m per axis);
    multipath and masking near buildings make it several times that. 6.4 m is the radial RMS
    of three times the open-field error (4.5 m per axis, the bench's ``--gps-noise 3``)."""
    search_ceiling: float = 22.0
    """Highest search above the pad, m: a fix's 1-sigma grows with the squared range
    (``hdrc3_perception.pad_fix.fix_sigma``: 0.14 m at 22 m); the filter takes the pad only when
    ten fixes agree to ``EstimatorConfig.vision_reset_spread`` (0.3 m RMS in 3-D), which 0.14 m
    per axis does with a margin (0.24 m) and 0.17 m (25 m) no longer does."""
    search_sigmas: float = 3.0
    """The filter's own error counts as this many of its position sigmas (when larger)."""
    search_timeout: float = 25.0
    """Search this long (s of sim time: climb, then hover) for a fix before landing on GPS."""
    search_patience: float = 25.0
    """Search up to this much longer while fixes arrive that the filter has not taken yet (it
    takes the pad once ten agree, ``EstimatorConfig.gate_reset_count``; on degraded GPS that
    took up to 20 s in the bench), s."""
    scan_dwell: float = 2.0
    """The search's camera scan: look at each point of :func:`scan_offsets` this long, s."""
    scan_hold: float = 2.0
    """Hold the scan's point while the filter received a fix within this, s."""
    scan_height_margin: float = 1.5
    """The scan starts once the climb is within this of the search height, m."""
    scan_overlap: float = 0.9
    """Ring spacing of the scan as a fraction of the hexagonal covering's (gapless below 1)."""
    camera: CameraSpec = COLOR
    """The camera the pattern is seen with (at zoom 0, the PTU pointed at the pad)."""
    calm_wind: float = 2.0
    """Below this estimated wind speed the heading is free (as commanded, or as it is), m/s."""
    headwind_tolerance: float = math.radians(30.0)
    """A commanded heading is kept while the estimated wind is within this of its nose, rad."""
    heading_hysteresis: float = math.radians(15.0)
    """Until the descent the heading follows the wind estimate when it moves this much, rad."""
    touchdown_ticks: int = 3
    settle_time: float = 1.0
    """After touchdown: push down on the skids this long, then request engine shutdown, s."""
    gains: OuterLoopGains = field(default_factory=lambda: OuterLoopGains(k_pos=0.8, k_vel=1.2))


@dataclass(frozen=True, slots=True)
class LandingOutput:
    """Command and status of one tick."""

    command: AttitudeCommand
    phase: LandingPhase
    height_above_ground: float
    engine_shutdown: bool
    """True once the engine may be shut down."""
    touchdown_time: float | None
    events: tuple[LandingEvent, ...] = ()


@dataclass(frozen=True, slots=True)
class LandingPlan:
    """Where to land and on which aid; ``reason`` says why (for the operator)."""

    target: LandingTarget
    aid: LandingAid
    reason: str
    search_height: float | None = None
    """Search for the pattern from this height above the pad first, m (None: no search)."""
    pad: str = ""
    """Name of the pad a vision landing is on ('' on GPS)."""
    engage: bool = False
    """Engage the PPC's pad state estimation for this landing (ready there, but idle)."""


@dataclass(frozen=True, slots=True)
class HeadingChoice:
    """The landing heading, why, and the wind it was chosen in."""

    heading: float
    """rad clockwise from north, [0, 2 pi)."""
    source: HeadingSource
    wind: WindEstimate | None

    def describe(self) -> str:
        """For the command's final reply: 'heading 270 deg into the estimated wind 9.8 m/s ...'."""
        deg = f"heading {math.degrees(self.heading):.0f} deg"
        wind = self.wind
        if wind is None or wind.status is WindStatus.NONE:
            estimated = "no wind estimate"
        else:
            settling = " (settling)" if wind.status is WindStatus.SETTLING else ""
            estimated = f"estimated wind {wind.describe()}{settling}"
        if self.source is HeadingSource.INTO_WIND:
            return f"{deg} into the {estimated}"
        what = "as commanded" if self.source is HeadingSource.COMMANDED else "as it was"
        return f"{deg} {what}, {estimated}"


def landing_heading(
    requested: float | None,
    current: float,
    wind: WindEstimate | None,
    config: LandingConfig,
) -> HeadingChoice:
    """The landing heading: into the estimated wind unless calm (§5.4: no tailwind landings).

    ``requested``: the land command's heading (None: none given); it is kept when the wind is
    calm (below ``calm_wind``) or within ``headwind_tolerance`` of its nose. An estimate that is
    still settling counts (the land command may follow a short flight); none does not.
    """
    known = wind is not None and wind.status is not WindStatus.NONE
    if wind is not None and known and wind.speed >= config.calm_wind:
        into = wind.from_direction
        if requested is not None and abs(wrap_pi(requested - into)) <= config.headwind_tolerance:
            return HeadingChoice(requested % math.tau, HeadingSource.COMMANDED, wind)
        return HeadingChoice(into, HeadingSource.INTO_WIND, wind)
    if requested is not None:
        return HeadingChoice(requested % math.tau, HeadingSource.COMMANDED, wind)
    return HeadingChoice(current % math.tau, HeadingSource.CURRENT, wind)


def search_height(config: LandingConfig, position_sigma: float) -> float:
    """Height above the pad from which the pattern is in the image despite the position error.

    The PTU aims at the pad's GIS position from the filter's pose, but the camera is where the
    aircraft really is: with a horizontal filter error ``e`` the line of sight meets the ground
    ``e`` from the pad, wherever the aircraft is. Looking down from ``h`` over that point, the
    pattern (``PAD_HALF_WIDTH_M`` from its centre) is wholly in the image when
    ``e + r <= h tan(a)``, ``a`` half the camera's narrower field of view (the colour camera's
    vertical one at zoom 0: 19.6 deg). Hence ``h = (e + r) / tan(a)``, with ``e`` the larger of
    ``search_position_error`` and ``search_sigmas`` filter sigmas; capped at ``search_ceiling``
    (above it the filter would not take the fixes). Defaults: (6.4 + 1.1) / tan(19.6 deg) =
    21.1 m, just above the 20 m hemisphere the landing is engaged from.
    """
    c = config
    error = max(c.search_position_error, c.search_sigmas * position_sigma)
    half_angle = c.camera.vfov(0.0) / 2.0
    return min(c.search_ceiling, (error + PAD_HALF_WIDTH_M) / math.tan(half_angle))


def scan_offsets(config: LandingConfig, height: float) -> tuple[tuple[float, float], ...]:
    """Where the search's camera looks, east and north of the pad's GIS position, m.

    The PTU is pointed from the filter's pose, so aiming at ``pad + o`` shows the ground around
    ``pad + o - e`` (``e`` the filter's horizontal error): the pattern is in the image while
    ``|o - e| <= R``, ``R = h tan(a) - r`` (:func:`search_height`'s footprint at ``height``).
    The centre first, then six points ``sqrt(3) R`` out (times ``scan_overlap``): the seven
    footprints of radius ``R`` cover filter errors up to about ``2 R`` (12.8 m from 21.1 m),
    where the centre alone covers ``R`` (6.4 m).
    """
    reach = height * math.tan(config.camera.vfov(0.0) / 2.0) - PAD_HALF_WIDTH_M
    if reach <= 0.0:
        return ((0.0, 0.0),)
    ring = math.sqrt(3.0) * reach * config.scan_overlap
    around = tuple(
        (ring * math.sin(math.radians(a)), ring * math.cos(math.radians(a)))
        for a in range(0, 360, 60)
    )
    return ((0.0, 0.0), *around)


def plan_landing(
    state: EstimatedState,
    heading: float,
    ground_height: float,
    vision_age: float,
    sites: tuple[LandingSite, ...],
    config: LandingConfig,
    *,
    pad_vision: PadVision,
) -> LandingPlan:
    """Choose the landing point: the nearest patterned pad on vision, else here on GPS.

    Within ``engage_radius`` of the pad but without a recent fix, the plan is a vision landing on
    the pad that searches first (``search_height``), when the navigation is OK (not for an
    emergency landing) and the PPC can see the pad (``pad_vision`` in :data:`CAN_SEE_PAD`); when
    it cannot, a GPS landing on the pad's GIS position, at once. ``vision_age``: seconds since
    the filter last accepted a vision fix (inf: never); ``ground_height``: the terrain under the
    aircraft (the GPS landing point's height).
    """
    e, n, u = state.position
    here = LandingTarget(e, n, ground_height, heading)
    if not sites:
        return LandingPlan(here, LandingAid.GPS, "no patterned pad in the world")

    def distance(site: LandingSite) -> float:
        return math.dist((e, n, u), (site.east, site.north, site.ground_height))

    site = min(sites, key=distance)
    far = distance(site)
    near = far <= config.engage_radius
    target = LandingTarget(site.east, site.north, site.ground_height, heading)
    if vision_age > config.vision_recent:
        reason = f"no vision fix of pad {site.name}"
        if not near:
            return LandingPlan(here, LandingAid.GPS, reason)
        if state.health is not EstimatorHealth.OK:
            return LandingPlan(here, LandingAid.GPS, f"{reason} (navigation {state.health.value})")
        if pad_vision not in CAN_SEE_PAD:
            return LandingPlan(target, LandingAid.GPS, f"{reason}: {pad_vision.describe()}")
        height = search_height(config, state.position_sigma)
        return _vision(target, site, pad_vision, height)
    if not near:
        away = f"{far:.1f} m away (over {config.engage_radius:g} m)"
        return LandingPlan(here, LandingAid.GPS, f"pad {site.name} {away}")
    return _vision(target, site, pad_vision, None)


def _vision(
    target: LandingTarget, site: LandingSite, pad_vision: PadVision, height: float | None
) -> LandingPlan:
    """A vision landing on ``site``; it engages the pad's pose when the PPC has it idle."""
    engage = pad_vision is PadVision.READY
    reason = f"pad {site.name}" + (", its pose engaged by the landing" if engage else "")
    return LandingPlan(target, LandingAid.VISION, reason, height, site.name, engage)


class Landing:
    """The landing control function."""

    def __init__(self, config: LandingConfig | None = None) -> None:
        """Create the function; :meth:`start` engages it."""
        self.config = config or LandingConfig()
        self.loop = OuterLoop(self.config.gains)
        self._target: LandingTarget | None = None
        self._phase = LandingPhase.APPROACH
        self._contacts = 0
        self._touchdown: float | None = None
        self._search_up = 0.0
        """ENU height of the search (the centre of gravity), m."""
        self._search_since: float | None = None
        self.search_time: float | None = None
        """How long the search lasted, once it is over (found or timed out), s."""
        self._scan: tuple[tuple[float, float], ...] = ((0.0, 0.0),)
        self._scan_index = 0
        self._scan_since: float | None = None
        self._seen_at = -math.inf

    def start(
        self,
        state: EstimatedState,
        target: LandingTarget,
        integral: tuple[float, float] = (0.0, 0.0),
        search_height: float | None = None,
    ) -> LandingPhase:
        """Engage from hover (Ctrl-Init); refused when already on the ground.

        ``search_height``: first search for the pattern over ``target`` from this height above
        it (never lower than the aircraft already is); the search ends when :meth:`update` is
        ``precise`` or after ``search_timeout``.
        """
        self.loop.reset(integral)
        self._target = target
        self._contacts = 0
        self._touchdown = None
        self._search_since, self.search_time = None, None
        self._scan, self._scan_index, self._scan_since = ((0.0, 0.0),), 0, None
        self._seen_at = -math.inf
        if state.on_ground:
            self._phase = LandingPhase.REFUSED_ON_GROUND
        elif search_height is not None:
            self._phase = LandingPhase.SEARCH
            floor = target.ground_height + self.config.cg_above_skids
            self._search_up = max(state.position[2], floor + search_height)
            self._scan = scan_offsets(self.config, self._search_up - floor)
        else:
            self._phase = LandingPhase.APPROACH
        return self._phase

    def camera_aim(self, state: EstimatedState, now: float, seen: bool) -> Vec3 | None:
        """Where the camera should look while searching (ENU, on the ground), else None.

        Climbing: the pad's GIS position. At the search height: the points of
        :func:`scan_offsets` in turn, ``scan_dwell`` each, held while fixes arrive that the
        filter has not taken yet (``seen``). None outside the search (the pad itself).
        """
        c, tg = self.config, self._target
        if tg is None or self._phase is not LandingPhase.SEARCH:
            return None
        if seen:
            self._seen_at = now
        if state.position[2] < self._search_up - c.scan_height_margin:
            self._scan_since = None
        elif self._scan_since is None or now - self._seen_at <= c.scan_hold:
            self._scan_since = now
        elif now - self._scan_since >= c.scan_dwell:
            self._scan_index = (self._scan_index + 1) % len(self._scan)
            self._scan_since = now
        de, dn = self._scan[self._scan_index]
        return (tg.east + de, tg.north + dn, tg.ground_height)

    @property
    def target(self) -> LandingTarget | None:
        """Where and with which heading it lands (None before :meth:`start`)."""
        return self._target

    def turn(self, heading: float) -> bool:
        """Land with ``heading`` instead; only before the descent (True if taken)."""
        if self._target is None or self._phase not in (LandingPhase.SEARCH, LandingPhase.APPROACH):
            return False
        self._target = replace(self._target, heading=heading % math.tau)
        return True

    def update(
        self,
        state: EstimatedState,
        now: float,
        dt: float,
        *,
        precise: bool = False,
        seen: bool = False,
    ) -> LandingOutput:
        """One tick; ``precise``: the position is good to centimetres (fresh vision fixes).

        ``seen``: the filter receives vision fixes, taken or not (the search waits longer).
        """
        c = self.config
        tg = self._target
        if tg is None:
            raise ConfigError("landing updated before start()")
        agl = state.position[2] - c.cg_above_skids - tg.ground_height
        dist = math.hypot(state.position[0] - tg.east, state.position[1] - tg.north)
        heading_ok = abs(wrap_pi(tg.heading - state.heading)) < math.radians(10.0)
        events: tuple[LandingEvent, ...] = ()
        if self._phase is LandingPhase.SEARCH:
            events = self._search(now, precise, seen)
        if self._phase is LandingPhase.APPROACH:
            settled = dist < c.approach_radius and state.horizontal_speed < c.approach_speed
            if settled and heading_ok:
                self._phase = LandingPhase.DESCENT
        if self._phase is LandingPhase.DESCENT:
            self._contacts = self._contacts + 1 if state.on_ground else 0
            if self._contacts >= c.touchdown_ticks:
                self._phase = LandingPhase.TOUCHDOWN
                self._touchdown = now
        touched = self._touchdown is not None and now - self._touchdown >= c.settle_time
        if self._phase is LandingPhase.TOUCHDOWN and touched:
            self._phase = LandingPhase.LANDED
        cmd = self._command(state, tg, agl, dt, precise)
        return LandingOutput(
            cmd, self._phase, agl, self._phase is LandingPhase.LANDED, self._touchdown, events
        )

    def _search(self, now: float, precise: bool, seen: bool) -> tuple[LandingEvent, ...]:
        """End the search on a fix (vision) or after the timeout (GPS).

        The timeout is ``search_timeout``, or up to ``search_patience`` more while fixes
        arrive that the filter has not taken yet.
        """
        c = self.config
        if self._search_since is None:
            self._search_since = now
        searched = now - self._search_since
        timeout = c.search_timeout + (c.search_patience if seen else 0.0)
        if precise:
            event = LandingEvent.PATTERN_FOUND
        elif searched >= timeout:
            event = LandingEvent.SEARCH_TIMED_OUT
        else:
            return ()
        self._phase, self.search_time = LandingPhase.APPROACH, searched
        return (event,)

    def _command(
        self, state: EstimatedState, tg: LandingTarget, agl: float, dt: float, precise: bool
    ) -> AttitudeCommand:
        c = self.config
        if self._phase in (LandingPhase.TOUCHDOWN, LandingPhase.LANDED):
            # weight on the skids: collective down, attitude level, no yaw
            return AttitudeCommand(vertical=-1.0)
        if self._phase is LandingPhase.REFUSED_ON_GROUND:
            return AttitudeCommand(vertical=-1.0)
        here: Vec3 = (tg.east, tg.north, state.position[2])
        if self._phase is LandingPhase.SEARCH:
            here = (tg.east, tg.north, self._search_up)
        if self._phase is LandingPhase.DESCENT and agl <= c.final_height and not precise:
            # final descent on GPS: velocity hold only; GPS position jitter would otherwise
            # become horizontal speed at touchdown
            here = state.position
        cmd = self.loop.update(state, Reference(position=here, heading=tg.heading), dt)
        if self._phase in (LandingPhase.SEARCH, LandingPhase.APPROACH):
            rate = cmd.vertical
        elif state.health is EstimatorHealth.LOST:
            rate = -c.descent_final
        elif agl > c.slow_height:
            rate = -c.descent_fast
        elif agl > c.final_height:
            rate = -c.descent_slow
        else:
            rate = -c.descent_final
        return AttitudeCommand(cmd.roll, cmd.pitch, cmd.yaw_rate, self._vertical(state, rate))

    def _vertical(self, state: EstimatedState, rate: float) -> float:
        """The climb-rate command for ``rate`` (m/s, up).

        With the inertial solution lost (IMU frozen or stale) the YACS's own climb-rate hold flies
        on the barometer alone (its baro-inertial filter has no accelerometer left, ``sim/yas.py``):
        that estimate lags the true rate by seconds and the hold swings into a growing vertical
        oscillation (measured: 3 m/s up, then a fall touching down at 2-6 m/s). The filter's
        vertical velocity still has GPS and barometer; feeding its error back through the
        command (``rate + k (rate - vz)``) puts an unlagged rate measurement into the YACS's
        loop, which damps it. In steady state the YACS's integrator still brings the rate to
        ``rate``.
        """
        if state.health is not EstimatorHealth.LOST:
            return rate
        return rate + self.config.lost_vertical_damping * (rate - state.velocity[2])
