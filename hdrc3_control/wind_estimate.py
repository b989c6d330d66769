"""On-board wind estimate from the attitude the aircraft needs to hold its velocity.

In the air the rotor's thrust, tilted by roll and pitch, and the air's drag on the fuselage make
the horizontal acceleration: ``a = T_h + D``. The attitude sensor gives ``T_h`` (the tilt away
from the calm-air hover trim, ``g tan`` of it in the body frame), the filter's velocity gives
``a``; so ``D = a - T_h``. The fuselage drag per unit mass is quadratic in the air's velocity
relative to the aircraft, per body axis: ``D_x = k_x u |u|``, ``D_y = k_y v |v|`` (the RMAX's
side area is about three times its frontal area). Inverting it gives the relative air velocity
in the body frame; rotated to ENU and added to the ground velocity it is the wind. Only sensor
data (attitude, the filter's velocity and heading) and no ground truth enter the estimate.

``D`` is low-passed in ENU (the rotor's oscillation, noise of the attitude sensor and of the
velocity's derivative) before the inversion, the wind after it; both only while airborne with
a good solution. The coefficients were measured on the simulated RMAX hovering at four
headings in 0, 5 and 10 m/s of wind (calm-air trim: roll -2.0 deg, pitch +0.27 deg; nose into
10 m/s: 2.4 deg nose down, side-on: 6.8 deg of roll).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import (
    EstimatedState,
    EstimatorHealth,
    G,
    from_heading_frame,
    to_heading_frame,
    wrap_2pi,
)


class WindStatus(enum.Enum):
    """How far the estimate can be trusted."""

    NONE = "none"
    """Not airborne with a good solution yet: no estimate."""
    SETTLING = "settling"
    """Airborne for less than ``WindConfig.settle_time``: the filters are still converging."""
    OK = "ok"


@dataclass(frozen=True, slots=True)
class WindConfig:
    """Airframe coefficients and filter time constants."""

    trim_roll: float = math.radians(-2.0)
    """Roll of a calm-air hover (the tail rotor's side thrust), rad."""
    trim_pitch: float = math.radians(0.27)
    """Pitch of a calm-air hover, rad."""
    drag_forward: float = 0.0044
    """Fuselage drag per unit mass along the body's x axis, (m/s^2) / (m/s)^2."""
    drag_side: float = 0.0118
    """Fuselage drag per unit mass along the body's y axis, (m/s^2) / (m/s)^2."""
    force_time: float = 1.0
    """Low-pass time constant of the air force (and the velocity it is paired with), s."""
    wind_time: float = 5.0
    """Low-pass time constant of the wind, s."""
    settle_time: float = 8.0
    """Airborne this long before the estimate is OK, s."""

    def __post_init__(self) -> None:
        """Reject non-physical coefficients."""
        positive = (self.drag_forward, self.drag_side, self.force_time, self.wind_time)
        if not all(math.isfinite(v) and v > 0.0 for v in positive):
            raise ConfigError(f"wind estimate coefficients must be > 0, got {positive}")
        if not (math.isfinite(self.settle_time) and self.settle_time >= 0.0):
            raise ConfigError(f"settle time must be >= 0 s, got {self.settle_time}")


@dataclass(frozen=True, slots=True)
class WindEstimate:
    """The estimated mean wind."""

    east: float
    """Air-mass velocity (where the wind blows to), m/s ENU."""
    north: float
    status: WindStatus

    @property
    def speed(self) -> float:
        """Wind speed, m/s."""
        return math.hypot(self.east, self.north)

    @property
    def from_direction(self) -> float:
        """Where the wind comes from, rad clockwise from north (the into-wind heading)."""
        return wrap_2pi(math.atan2(-self.east, -self.north))

    def describe(self) -> str:
        """For the operator: '6.2 m/s from 271 deg'."""
        return f"{self.speed:.1f} m/s from {math.degrees(self.from_direction):.0f} deg"


def signed_sqrt(value: float) -> float:
    """``sign(value) * sqrt(|value|)``."""
    return math.copysign(math.sqrt(abs(value)), value)


def relative_air(
    drag_east: float, drag_north: float, heading: float, config: WindConfig
) -> tuple[float, float]:
    """The air's velocity relative to the aircraft (ENU, m/s) that makes this drag per mass."""
    forward, right = to_heading_frame(drag_east, drag_north, heading)
    u = signed_sqrt(forward / config.drag_forward)
    v = signed_sqrt(right / config.drag_side)
    return from_heading_frame(u, v, heading)


def thrust_accel(
    roll: float, pitch: float, heading: float, config: WindConfig
) -> tuple[float, float]:
    """Horizontal acceleration (east, north) of the thrust tilted away from the calm-air trim."""
    forward = -G * math.tan(pitch - config.trim_pitch)
    right = G * math.tan(roll - config.trim_roll)
    return from_heading_frame(forward, right, heading)


class WindEstimator:
    """Runs every control tick on the navigation solution; :meth:`estimate` reads it."""

    def __init__(self, config: WindConfig | None = None) -> None:
        """Start without an estimate."""
        self.config = config or WindConfig()
        self.reset()

    def reset(self) -> None:
        """Forget everything (on the ground, or the solution was lost)."""
        self._last: EstimatedState | None = None
        self._drag = (0.0, 0.0)
        self._velocity = (0.0, 0.0)
        self._wind = (0.0, 0.0)
        self._airborne = 0.0

    def update(self, state: EstimatedState) -> WindEstimate:
        """Take one navigation solution (the filter's attitude and velocity)."""
        c, last = self.config, self._last
        if state.on_ground or state.health is not EstimatorHealth.OK:
            self.reset()
            return self.estimate()
        self._last = state
        dt = 0.0 if last is None else state.time - last.time
        if last is None or not 0.0 < dt <= 0.5:
            self._airborne = 0.0
            return self.estimate()
        ve, vn = state.velocity[0], state.velocity[1]
        accel = ((ve - last.velocity[0]) / dt, (vn - last.velocity[1]) / dt)
        te, tn = thrust_accel(state.roll, state.pitch, state.heading, c)
        drag = (accel[0] - te, accel[1] - tn)
        first = self._airborne == 0.0
        self._airborne += dt
        if first:
            self._drag, self._velocity = drag, (ve, vn)
        else:
            self._drag = _low_pass(self._drag, drag, dt, c.force_time)
            self._velocity = _low_pass(self._velocity, (ve, vn), dt, c.force_time)
        air = relative_air(*self._drag, state.heading, c)
        wind = (self._velocity[0] + air[0], self._velocity[1] + air[1])
        self._wind = wind if first else _low_pass(self._wind, wind, dt, c.wind_time)
        return self.estimate()

    def estimate(self) -> WindEstimate:
        """The current estimate (status NONE: none yet)."""
        if self._airborne == 0.0:
            return WindEstimate(0.0, 0.0, WindStatus.NONE)
        status = WindStatus.OK if self._airborne >= self.config.settle_time else WindStatus.SETTLING
        return WindEstimate(self._wind[0], self._wind[1], status)


def _low_pass(
    old: tuple[float, float], new: tuple[float, float], dt: float, tau: float
) -> tuple[float, float]:
    a = dt / (tau + dt)
    return old[0] + a * (new[0] - old[0]), old[1] + a * (new[1] - old[1])
