"""Landing control mode (Landing automaton, fcl_land): controlled descent onto a landing point.

Phases: APPROACH (hover over the landing point at the current height with the landing heading),
DESCENT (descend with a rate that slows down with the estimated height above the ground) and
TOUCHDOWN (skid switch closed for ``touchdown_ticks`` consecutive ticks, a timely detection:
early detection loads the skids, late detection causes ground resonance), then LANDED with an
engine shutdown request. The height above ground comes from the navigation filter; a vision pose
(the landing pattern) enters through ``StateEstimator.update_vision`` (the hook of chapter 5.4).

Which aid (§5.4, :func:`plan_landing`): with a vision fix accepted within ``vision_recent`` and
a patterned pad within ``engage_radius`` (the chapter's 20 m hemisphere) the landing point is
the pad's centre and the position is held on it down to the skids while fixes keep coming;
otherwise the aircraft lands where it is on GPS and the barometer, and below ``final_height``
holds only its velocity (GPS position jitter would become horizontal speed at touchdown).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
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


class LandingPhase(enum.Enum):
    """Phase of the landing function."""

    APPROACH = "approach"
    DESCENT = "descent"
    TOUCHDOWN = "touchdown"
    LANDED = "landed"
    REFUSED_ON_GROUND = "refused_on_ground"


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


@dataclass(frozen=True, slots=True)
class LandingPlan:
    """Where to land and on which aid; ``reason`` says why (for the operator)."""

    target: LandingTarget
    aid: LandingAid
    reason: str


def plan_landing(
    state: EstimatedState,
    heading: float,
    ground_height: float,
    vision_age: float,
    sites: tuple[LandingSite, ...],
    config: LandingConfig,
) -> LandingPlan:
    """Choose the landing point: the nearest patterned pad on vision, else here on GPS.

    ``vision_age``: seconds since the filter last accepted a vision fix (inf: never);
    ``ground_height``: the terrain under the aircraft (the GPS landing point's height).
    """
    e, n, u = state.position
    here = LandingTarget(e, n, ground_height, heading)
    if not sites:
        return LandingPlan(here, LandingAid.GPS, "no patterned pad in the world")

    def distance(site: LandingSite) -> float:
        return math.dist((e, n, u), (site.east, site.north, site.ground_height))

    site = min(sites, key=distance)
    far = distance(site)
    if vision_age > config.vision_recent:
        return LandingPlan(here, LandingAid.GPS, f"no vision fix of pad {site.name}")
    if far > config.engage_radius:
        away = f"{far:.1f} m away (over {config.engage_radius:g} m)"
        return LandingPlan(here, LandingAid.GPS, f"pad {site.name} {away}")
    target = LandingTarget(site.east, site.north, site.ground_height, heading)
    return LandingPlan(target, LandingAid.VISION, f"pad {site.name}")


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

    def start(
        self,
        state: EstimatedState,
        target: LandingTarget,
        integral: tuple[float, float] = (0.0, 0.0),
    ) -> LandingPhase:
        """Engage from hover (Ctrl-Init); refused when already on the ground."""
        self.loop.reset(integral)
        self._target = target
        self._contacts = 0
        self._touchdown = None
        self._phase = LandingPhase.REFUSED_ON_GROUND if state.on_ground else LandingPhase.APPROACH
        return self._phase

    def update(
        self, state: EstimatedState, now: float, dt: float, *, precise: bool = False
    ) -> LandingOutput:
        """One tick; ``precise``: the position is good to centimetres (fresh vision fixes)."""
        c = self.config
        tg = self._target
        if tg is None:
            raise ConfigError("landing updated before start()")
        agl = state.position[2] - c.cg_above_skids - tg.ground_height
        dist = math.hypot(state.position[0] - tg.east, state.position[1] - tg.north)
        heading_ok = abs(wrap_pi(tg.heading - state.heading)) < math.radians(10.0)
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
            cmd, self._phase, agl, self._phase is LandingPhase.LANDED, self._touchdown
        )

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
        if self._phase is LandingPhase.DESCENT and agl <= c.final_height and not precise:
            # final descent on GPS: velocity hold only; GPS position jitter would otherwise
            # become horizontal speed at touchdown
            here = state.position
        cmd = self.loop.update(state, Reference(position=here, heading=tg.heading), dt)
        if self._phase is LandingPhase.APPROACH:
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
