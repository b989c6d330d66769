"""The outer (translational) loop shared by the flight modes: position/velocity -> attitude.

Cascade at 50 Hz on top of the YACS (chapter 5.3: inner attitude loop, outer position/velocity
loop)::

    v_ref = v_ff + k_pos * (p_ref - p)                   (correction limited to max_correction)
    a_cmd = a_ff + k_vel * (v_ref - v) + k_int * integral(v_ref - v)
    roll  = atan(a_right / g),  pitch = -atan(a_forward / g)   (limited to max_tilt)
    climb = vz_ff + k_alt * (z_ref - z),  yaw_rate = r_ff + k_heading * (psi_ref - psi)

The velocity-error integral trims out wind and gives zero steady-state position error; it only
runs in the air.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import (
    AttitudeCommand,
    EstimatedState,
    G,
    Vec3,
    clip,
    to_heading_frame,
    wrap_pi,
)


@dataclass(frozen=True, slots=True)
class OuterLoopGains:
    """Gains and limits (tuned on the simulated RMAX, see bench/control_kernel.py)."""

    k_pos: float = 0.7
    """Position error -> velocity correction, 1/s."""
    max_correction: float = 3.0
    """Limit of the position-error velocity correction, m/s."""
    k_vel: float = 1.0
    """Velocity error -> acceleration, 1/s."""
    k_int: float = 0.3
    """Velocity error integral -> acceleration, 1/s^2."""
    max_int_accel: float = 3.0
    """Integrator authority, m/s^2 (about 17 deg of tilt)."""
    max_tilt: float = math.radians(22.0)
    k_alt: float = 0.8
    """Height error -> climb rate, 1/s."""
    max_climb: float = 2.5
    max_descent: float = 2.0
    k_heading: float = 1.2
    """Heading error -> yaw rate, 1/s."""
    max_yaw_rate: float = math.radians(40.0)

    def __post_init__(self) -> None:
        """Reject non-finite or negative gains."""
        values = (
            self.k_pos,
            self.max_correction,
            self.k_vel,
            self.k_int,
            self.max_int_accel,
            self.max_tilt,
            self.k_alt,
            self.max_climb,
            self.max_descent,
            self.k_heading,
            self.max_yaw_rate,
        )
        if not all(math.isfinite(v) and v >= 0.0 for v in values):
            raise ConfigError(f"outer loop gains must be finite and >= 0, got {values}")


@dataclass(frozen=True, slots=True)
class Reference:
    """What the outer loop tracks in one tick."""

    position: Vec3
    """m, ENU (the along-path component is zero error on a path)."""
    heading: float
    """rad clockwise from north."""
    velocity: Vec3 = (0.0, 0.0, 0.0)
    """Feed-forward velocity, m/s ENU."""
    acceleration: tuple[float, float] = (0.0, 0.0)
    """Feed-forward horizontal acceleration (east, north), m/s^2 (curvature, speed changes)."""
    yaw_rate: float = 0.0
    """Feed-forward yaw rate, rad/s."""


class OuterLoop:
    """The translational loop; one instance per control function (it holds the integrator)."""

    def __init__(self, gains: OuterLoopGains | None = None) -> None:
        """Start with a zero integrator."""
        self.gains = gains or OuterLoopGains()
        self.reset()

    def reset(self, integral: tuple[float, float] = (0.0, 0.0)) -> None:
        """Set the integrator (e.g. hand the wind trim over from the previous mode)."""
        self.integral = integral

    def update(self, state: EstimatedState, ref: Reference, dt: float) -> AttitudeCommand:
        """One tick: the attitude command that makes ``state`` follow ``ref``."""
        g = self.gains
        px, py, pz = state.position
        vx, vy, _ = state.velocity
        ex, ey = ref.position[0] - px, ref.position[1] - py
        cx, cy = g.k_pos * ex, g.k_pos * ey
        norm = math.hypot(cx, cy)
        if norm > g.max_correction:
            cx, cy = cx * g.max_correction / norm, cy * g.max_correction / norm
        evx = ref.velocity[0] + cx - vx
        evy = ref.velocity[1] + cy - vy
        ix, iy = self.integral
        if not state.on_ground:
            lim = g.max_int_accel
            ix = clip(ix + g.k_int * evx * dt, lim)
            iy = clip(iy + g.k_int * evy * dt, lim)
            self.integral = (ix, iy)
        ax = ref.acceleration[0] + g.k_vel * evx + ix
        ay = ref.acceleration[1] + g.k_vel * evy + iy
        climb = ref.velocity[2] + g.k_alt * (ref.position[2] - pz)
        climb = max(-g.max_descent, min(g.max_climb, climb))
        yaw_rate = ref.yaw_rate + g.k_heading * wrap_pi(ref.heading - state.heading)
        roll, pitch = accel_to_attitude(ax, ay, state.heading, g.max_tilt)
        return AttitudeCommand(
            roll=roll, pitch=pitch, yaw_rate=clip(yaw_rate, g.max_yaw_rate), vertical=climb
        )


def accel_to_attitude(
    accel_east: float, accel_north: float, heading: float, max_tilt: float
) -> tuple[float, float]:
    """Roll and pitch that tilt the thrust to give a horizontal acceleration (east, north)."""
    forward, right = to_heading_frame(accel_east, accel_north, heading)
    roll = clip(math.atan2(right, G), max_tilt)
    pitch = clip(-math.atan2(forward, G), max_tilt)
    return roll, pitch
