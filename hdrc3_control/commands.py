"""The control kernel's output to the YACS interface and its input from the navigation filter."""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError

Vec3 = tuple[float, float, float]

G = 9.80665
"""Standard gravity, m/s^2."""


class VerticalMode(enum.Enum):
    """How :attr:`AttitudeCommand.vertical` is meant."""

    VERTICAL_RATE = "vertical_rate"
    """m/s, climb positive (the YACS closes the loop on the collective)."""
    COLLECTIVE = "collective"
    """Normalised collective 0 .. 1."""


@dataclass(frozen=True, slots=True)
class AttitudeCommand:
    """One outer-loop command to the attitude control system (roll, pitch, yaw rate, vertical)."""

    roll: float = 0.0
    """rad, right wing down positive."""
    pitch: float = 0.0
    """rad, nose up positive."""
    yaw_rate: float = 0.0
    """rad/s, nose right positive."""
    vertical: float = 0.0
    """Climb rate (m/s) or collective (0 .. 1), see ``vertical_mode``."""
    vertical_mode: VerticalMode = VerticalMode.VERTICAL_RATE
    engine_off: bool = False
    """Ask the YACS to stop the engine (the landing mode, once on the skids)."""

    def __post_init__(self) -> None:
        """Reject non-finite values and collectives outside the servo travel."""
        values = (self.roll, self.pitch, self.yaw_rate, self.vertical)
        if not all(math.isfinite(v) for v in values):
            raise ConfigError(f"attitude command must be finite, got {values}")
        if self.vertical_mode is VerticalMode.COLLECTIVE and not 0.0 <= self.vertical <= 1.0:
            raise ConfigError(f"collective {self.vertical} outside [0, 1]")


class EstimatorHealth(enum.Enum):
    """Health of the navigation solution."""

    OK = "ok"
    """Absolute position aiding (GPS or vision) is current."""
    DEGRADED = "degraded"
    """Dead reckoning on the IMU: aiding lost for less than the allowed time."""
    LOST = "lost"
    """No usable solution: uninitialised, IMU/attitude stale or frozen, dead reckoning too long."""


@dataclass(frozen=True, slots=True)
class EstimatedState:
    """The navigation solution the control functions work on (local ENU frame, SI units)."""

    time: float
    """Sim time of the estimate, s."""
    position: Vec3
    """m, ENU (centre of gravity)."""
    velocity: Vec3
    """m/s, ENU."""
    roll: float
    pitch: float
    heading: float
    """rad clockwise from north, [0, 2*pi)."""
    rates: Vec3 = (0.0, 0.0, 0.0)
    """Body rates p, q, r (FRD), rad/s."""
    on_ground: bool = False
    health: EstimatorHealth = EstimatorHealth.OK
    position_sigma: float = 0.0
    """Horizontal position 1-sigma of the filter, m."""
    rotor_rpm: float = 0.0
    """Last main rotor rpm reading (0 if none)."""

    @property
    def horizontal_speed(self) -> float:
        """Ground speed, m/s."""
        return math.hypot(self.velocity[0], self.velocity[1])


def wrap_pi(angle: float) -> float:
    """Wrap an angle to [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def wrap_2pi(angle: float) -> float:
    """Wrap an angle to [0, 2*pi)."""
    return angle % (2.0 * math.pi)


def to_heading_frame(east: float, north: float, heading: float) -> tuple[float, float]:
    """(forward, right) of a horizontal ENU vector, the nose at ``heading`` (rad from north)."""
    s, c = math.sin(heading), math.cos(heading)
    return east * s + north * c, east * c - north * s


def from_heading_frame(forward: float, right: float, heading: float) -> tuple[float, float]:
    """(east, north) of a horizontal vector given along the nose and to its right."""
    s, c = math.sin(heading), math.cos(heading)
    return forward * s + right * c, forward * c - right * s


def clip(value: float, limit: float) -> float:
    """Clip ``value`` to [-limit, limit]."""
    return -limit if value < -limit else limit if value > limit else value
