"""Yaw and climb modes (chapter 6.2.2: fcl_yaw, fcl_climb).

Yaw: the hovering function with a heading setpoint that slews at a bounded rate to the commanded
heading. Climb: path following on a predefined vertical straight path to the commanded altitude,
then hovering there (the function reports DONE with the hover point).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import AttitudeCommand, EstimatedState, Vec3, wrap_2pi, wrap_pi
from hdrc3_control.hover import HoverController, HoverSetpoint
from hdrc3_control.path_following import PathFollower, PathFollowingConfig, PathStatus
from hdrc3_control.path_segment import PathSegment


class ModeStatus(enum.Enum):
    """Status of the yaw and climb functions."""

    ACTIVE = "active"
    DONE = "done"
    """Target reached: continue hovering at ``hover_point``."""
    NAVIGATION_LOST = "navigation_lost"


@dataclass(frozen=True, slots=True)
class ModeOutput:
    """Command and status of one tick."""

    command: AttitudeCommand
    status: ModeStatus
    error: float
    """Heading error (rad) or altitude error (m) left."""
    hover_point: HoverSetpoint


class YawMode:
    """Turn on the spot to a heading (hovering with a slewing heading setpoint)."""

    def __init__(
        self,
        rate: float = math.radians(20.0),
        tolerance: float = math.radians(2.0),
    ) -> None:
        """``rate``: heading slew rate, rad/s; ``tolerance``: heading error counted as done."""
        if not (rate > 0.0 and tolerance > 0.0):
            raise ConfigError("yaw rate and tolerance must be > 0")
        self.rate = rate
        self.tolerance = tolerance
        self._hover: HoverController | None = None
        self._target = 0.0

    @property
    def integral(self) -> tuple[float, float]:
        """Wind trim of the outer loop (to hand over to the next mode)."""
        return self._hover.loop.integral if self._hover is not None else (0.0, 0.0)

    def start(
        self, state: EstimatedState, heading: float, integral: tuple[float, float] = (0.0, 0.0)
    ) -> None:
        """Hold the current position and turn to ``heading`` (rad clockwise from north)."""
        if not math.isfinite(heading):
            raise ConfigError(f"heading must be finite, got {heading}")
        self._target = wrap_2pi(heading)
        self._hover = HoverController(HoverSetpoint.at(state), integral=integral)

    def update(self, state: EstimatedState, dt: float) -> ModeOutput:
        """One tick."""
        hv = self._hover
        if hv is None:
            raise ConfigError("yaw mode updated before start()")
        sp = hv.setpoint
        step = max(-self.rate * dt, min(self.rate * dt, wrap_pi(self._target - sp.heading)))
        hv.setpoint = HoverSetpoint(sp.position, wrap_2pi(sp.heading + step))
        out = hv.update(state, dt)
        err = wrap_pi(self._target - state.heading)
        if out.status.name == "NAVIGATION_LOST":
            status = ModeStatus.NAVIGATION_LOST
        elif abs(err) < self.tolerance and abs(state.rates[2]) < 0.05:
            status = ModeStatus.DONE
        else:
            status = ModeStatus.ACTIVE
        return ModeOutput(out.command, status, err, HoverSetpoint(sp.position, self._target))


class ClimbMode:
    """Climb or descend vertically to an altitude by path following on a vertical segment."""

    def __init__(self, speed: float = 1.5, config: PathFollowingConfig | None = None) -> None:
        """``speed``: vertical speed along the path, m/s."""
        if not speed > 0.0:
            raise ConfigError("climb speed must be > 0")
        self.speed = speed
        self.follower = PathFollower(config)
        self._target: HoverSetpoint | None = None
        self._hover: HoverController | None = None
        """Set when the altitude change is too small for a path: hover there directly."""

    @property
    def integral(self) -> tuple[float, float]:
        """Wind trim of the outer loop (to hand over to the next mode)."""
        if self._hover is not None:
            return self._hover.loop.integral
        return self.follower.loop.integral

    def start(
        self, state: EstimatedState, altitude: float, integral: tuple[float, float] = (0.0, 0.0)
    ) -> None:
        """Climb to ``altitude`` (ENU up, m) over the current position."""
        if not math.isfinite(altitude):
            raise ConfigError(f"altitude must be finite, got {altitude}")
        e, n, u = state.position
        end: Vec3 = (e, n, altitude)
        self._target = HoverSetpoint(end, state.heading)
        self._hover = None
        if abs(altitude - u) < 0.5:
            self._hover = HoverController(self._target, integral=integral)
        else:
            segment = PathSegment.straight(state.position, end, self.speed)
            self.follower.start(state, segment, integral)

    def update(self, state: EstimatedState, now: float, dt: float) -> ModeOutput:
        """One tick."""
        tg = self._target
        if tg is None:
            raise ConfigError("climb mode updated before start()")
        err = tg.position[2] - state.position[2]
        if self._hover is not None:
            return ModeOutput(self._hover.update(state, dt).command, ModeStatus.DONE, err, tg)
        out = self.follower.update(state, now)
        status = {
            PathStatus.ARRIVED: ModeStatus.DONE,
            PathStatus.NAVIGATION_LOST: ModeStatus.NAVIGATION_LOST,
        }.get(out.status, ModeStatus.ACTIVE)
        return ModeOutput(out.command, status, err, tg)
