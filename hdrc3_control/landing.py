"""Landing control mode (Landing automaton, fcl_land): controlled descent onto a landing point.

Phases: APPROACH (hover over the landing point at the current height with the landing heading),
DESCENT (descend with a rate that slows down with the estimated height above the ground) and
TOUCHDOWN (skid switch closed for ``touchdown_ticks`` consecutive ticks, a timely detection:
early detection loads the skids, late detection causes ground resonance), then LANDED with an
engine shutdown request. The height above ground comes from the navigation filter; a vision pose
(the landing pattern) enters through ``StateEstimator.update_vision`` (the hook of chapter 5.4).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

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

    def update(self, state: EstimatedState, now: float, dt: float) -> LandingOutput:
        """One tick."""
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
        cmd = self._command(state, tg, agl, dt)
        return LandingOutput(
            cmd, self._phase, agl, self._phase is LandingPhase.LANDED, self._touchdown
        )

    def _command(
        self, state: EstimatedState, tg: LandingTarget, agl: float, dt: float
    ) -> AttitudeCommand:
        c = self.config
        if self._phase in (LandingPhase.TOUCHDOWN, LandingPhase.LANDED):
            # weight on the skids: collective down, attitude level, no yaw
            return AttitudeCommand(vertical=-1.0)
        if self._phase is LandingPhase.REFUSED_ON_GROUND:
            return AttitudeCommand(vertical=-1.0)
        here: Vec3 = (tg.east, tg.north, state.position[2])
        if self._phase is LandingPhase.DESCENT and agl <= c.final_height:
            # final descent: velocity hold only; GPS position jitter would otherwise become
            # horizontal speed at touchdown
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
