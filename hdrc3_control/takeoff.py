"""Take-off control mode (fcl_takeoff): climb from the skids to a predefined height.

Climbs at a fixed rate while holding the horizontal position and heading of the start. Lack of
lift (an overweight carrier, a drooping rotor) is detected and returned as FAILED_NO_LIFT: the
aircraft is then put back on its skids with a descent command instead of the mode hanging.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import AttitudeCommand, EstimatedState, EstimatorHealth
from hdrc3_control.hover import HoverSetpoint
from hdrc3_control.outer_loop import OuterLoop, OuterLoopGains, Reference


class TakeoffStatus(enum.Enum):
    """Status of the take-off function."""

    SPOOLING = "spooling"
    """On the skids, waiting for the governor to bring the rotor to ``min_rpm``."""
    CLIMBING = "climbing"
    DONE = "done"
    """Reached the take-off height: engage hovering at ``hover_point``."""
    FAILED_NO_LIFT = "failed_no_lift"
    REFUSED_NOT_ON_GROUND = "refused_not_on_ground"
    REFUSED_ENGINE = "refused_engine"
    """Rotor did not reach governed speed within ``spool_timeout``."""
    NAVIGATION_LOST = "navigation_lost"


@dataclass(frozen=True, slots=True)
class TakeoffConfig:
    """Take-off parameters."""

    height: float = 10.0
    """Take-off height above the start position, m."""
    climb_rate: float = 1.2
    """m/s."""
    min_rpm: float = 800.0
    """Rotor rpm needed to start, rpm."""
    spool_timeout: float = 30.0
    """How long to wait on the skids for ``min_rpm`` (engine start, governor ramp), s."""
    lift_timeout: float = 12.0
    """Time allowed to climb ``lift_height`` after the climb command, s."""
    lift_height: float = 1.5
    """Height gain that proves enough lift, m."""
    droop_rpm: float = 790.0
    """Rotor speed below which the rotor is overloaded (counted only once climbing), rpm."""
    droop_time: float = 3.0
    """Sustained droop this long is a failure, s."""
    done_tolerance: float = 0.5
    gains: OuterLoopGains = field(default_factory=OuterLoopGains)

    def __post_init__(self) -> None:
        """Reject nonsense."""
        if not (self.height > self.lift_height > 0.0 and self.climb_rate > 0.0):
            raise ConfigError("take-off height must exceed lift_height > 0, climb rate > 0")


@dataclass(frozen=True, slots=True)
class TakeoffOutput:
    """Command and status of one tick."""

    command: AttitudeCommand
    status: TakeoffStatus
    height: float
    """Height gained since the start, m."""
    hover_point: HoverSetpoint | None
    reason: str = ""


class Takeoff:
    """The take-off control function."""

    def __init__(self, config: TakeoffConfig | None = None) -> None:
        """Create the function; :meth:`start` engages it."""
        self.config = config or TakeoffConfig()
        self.loop = OuterLoop(self.config.gains)
        self._start: HoverSetpoint | None = None
        self._t0 = 0.0
        self._status = TakeoffStatus.CLIMBING
        self._droop_since: float | None = None
        self._reason = ""

    def start(self, state: EstimatedState, now: float) -> TakeoffStatus:
        """Engage from the skids (Ctrl-Init); returns SPOOLING, CLIMBING or REFUSED_*."""
        c = self.config
        self.loop.reset()
        self._start = HoverSetpoint.at(state)
        self._t0 = now
        self._droop_since = None
        self._reason = ""
        if not state.on_ground:
            self._status = TakeoffStatus.REFUSED_NOT_ON_GROUND
        elif state.rotor_rpm < c.min_rpm:
            self._status = TakeoffStatus.SPOOLING
        else:
            self._status = TakeoffStatus.CLIMBING
        return self._status

    def update(self, state: EstimatedState, now: float, dt: float) -> TakeoffOutput:
        """One tick."""
        c = self.config
        sp = self._start
        if sp is None:
            raise ConfigError("take-off updated before start()")
        height = state.position[2] - sp.position[2]
        target = (sp.position[0], sp.position[1], sp.position[2] + c.height)
        if self._status is TakeoffStatus.SPOOLING:
            if state.rotor_rpm >= c.min_rpm:
                self._status = TakeoffStatus.CLIMBING
                self._t0 = now  # the lift check counts from the climb command
            elif now - self._t0 > c.spool_timeout:
                self._status = TakeoffStatus.REFUSED_ENGINE
                self._reason = (
                    f"rotor at {state.rotor_rpm:.0f} rpm after {c.spool_timeout:.0f} s, "
                    f"needs {c.min_rpm:.0f}"
                )
        if self._status is TakeoffStatus.CLIMBING:
            self._check(state, now, height)
        if self._status is TakeoffStatus.CLIMBING and state.health is EstimatorHealth.LOST:
            self._status = TakeoffStatus.NAVIGATION_LOST
        if self._status is TakeoffStatus.CLIMBING:
            climb = c.climb_rate if height < c.height - 2.0 else None
            ref = Reference(position=target, heading=sp.heading)
            cmd = self.loop.update(state, ref, dt)
            if climb is not None:
                cmd = AttitudeCommand(cmd.roll, cmd.pitch, cmd.yaw_rate, climb)
            if abs(height - c.height) <= c.done_tolerance and abs(state.velocity[2]) < 0.5:
                self._status = TakeoffStatus.DONE
        elif self._status is TakeoffStatus.DONE:
            cmd = self.loop.update(state, Reference(position=target, heading=sp.heading), dt)
        else:
            # spooling, failed or refused: back onto (or stay on) the skids, wings level
            cmd = AttitudeCommand(vertical=-0.5 if not state.on_ground else -1.0)
        hover = HoverSetpoint(target, sp.heading) if self._status is TakeoffStatus.DONE else None
        return TakeoffOutput(cmd, self._status, height, hover, self._reason)

    def _check(self, state: EstimatedState, now: float, height: float) -> None:
        c = self.config
        elapsed = now - self._t0
        if height < c.lift_height and elapsed > c.lift_timeout:
            self._status = TakeoffStatus.FAILED_NO_LIFT
            self._reason = f"gained {height:.2f} m in {elapsed:.1f} s (need {c.lift_height} m)"
            return
        if 0.0 < state.rotor_rpm < c.droop_rpm:
            if self._droop_since is None:
                self._droop_since = now
            elif now - self._droop_since > c.droop_time and height < c.height - 2.0:
                self._status = TakeoffStatus.FAILED_NO_LIFT
                self._reason = f"rotor droops to {state.rotor_rpm:.0f} rpm (overload)"
        else:
            self._droop_since = None
