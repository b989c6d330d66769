"""Hovering control mode: PID loops holding position, altitude and heading (chapter 5.2, 6.1.1)."""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import AttitudeCommand, EstimatedState, EstimatorHealth, Vec3, wrap_pi
from hdrc3_control.outer_loop import OuterLoop, OuterLoopGains, Reference, accel_to_attitude


@dataclass(frozen=True, slots=True)
class HoverTolerances:
    """Hover-Stable-CO bounds (chapter 6.1.1: 5 m, 2 m, 5 deg, 1 m/s)."""

    position: float = 5.0
    altitude: float = 2.0
    heading: float = math.radians(5.0)
    velocity: float = 1.0
    """Horizontal and vertical speed, m/s each."""


@dataclass(frozen=True, slots=True)
class HoverSetpoint:
    """Where to hover (the Hovering-DO slot)."""

    position: Vec3
    heading: float

    def __post_init__(self) -> None:
        """Reject non-finite setpoints."""
        if not all(math.isfinite(v) for v in (*self.position, self.heading)):
            raise ConfigError(f"hover setpoint must be finite, got {self.position}, {self.heading}")

    @staticmethod
    def at(state: EstimatedState) -> HoverSetpoint:
        """Hover where the aircraft is now, with its current heading."""
        return HoverSetpoint(state.position, state.heading)


class HoverStatus(enum.Enum):
    """Status of the hovering function in one tick."""

    STABILISING = "stabilising"
    """Outside the Hover-Stable tolerances."""
    STABLE = "stable"
    """Hover-Stable-CO holds."""
    NAVIGATION_LOST = "navigation_lost"
    """The estimator reports LOST: the command only levels the aircraft and holds height rate 0."""


@dataclass(frozen=True, slots=True)
class HoverOutput:
    """Command and status of one tick."""

    command: AttitudeCommand
    status: HoverStatus
    position_error: float
    altitude_error: float
    heading_error: float


def hover_stable(
    state: EstimatedState, setpoint: HoverSetpoint, tol: HoverTolerances | None = None
) -> bool:
    """Hover-Stable-CO: position, altitude, heading and velocities within the tolerances."""
    t = tol or HoverTolerances()
    dx = state.position[0] - setpoint.position[0]
    dy = state.position[1] - setpoint.position[1]
    return (
        math.hypot(dx, dy) <= t.position
        and abs(state.position[2] - setpoint.position[2]) <= t.altitude
        and abs(wrap_pi(state.heading - setpoint.heading)) <= t.heading
        and state.horizontal_speed <= t.velocity
        and abs(state.velocity[2]) <= t.velocity
    )


class HoverController:
    """Holds a :class:`HoverSetpoint`; call :meth:`update` once per tick."""

    def __init__(
        self,
        setpoint: HoverSetpoint,
        gains: OuterLoopGains | None = None,
        tolerances: HoverTolerances | None = None,
        integral: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        """Hover at ``setpoint``; ``integral`` hands over the wind trim of the previous mode."""
        self.setpoint = setpoint
        self.tolerances = tolerances or HoverTolerances()
        self.loop = OuterLoop(gains)
        self.loop.reset(integral)

    def update(self, state: EstimatedState, dt: float) -> HoverOutput:
        """One tick of the hover loops."""
        sp = self.setpoint
        errs = (
            math.hypot(sp.position[0] - state.position[0], sp.position[1] - state.position[1]),
            sp.position[2] - state.position[2],
            wrap_pi(sp.heading - state.heading),
        )
        if state.health is EstimatorHealth.LOST:
            # No trustworthy velocity: level the aircraft, hold the height rate, keep the trim.
            ix, iy = self.loop.integral
            roll, pitch = accel_to_attitude(ix, iy, state.heading, self.loop.gains.max_tilt)
            cmd = AttitudeCommand(roll=roll, pitch=pitch, yaw_rate=0.0, vertical=0.0)
            return HoverOutput(cmd, HoverStatus.NAVIGATION_LOST, *errs)
        cmd = self.loop.update(state, Reference(position=sp.position, heading=sp.heading), dt)
        stable = hover_stable(state, sp, self.tolerances)
        status = HoverStatus.STABLE if stable else HoverStatus.STABILISING
        return HoverOutput(cmd, status, *errs)
