"""A minimal velocity-hold outer loop on top of the YACS, for tests and benchmarks of the sim.

Not the control kernel (that is hdrc3_control, a later issue): it only turns a desired ground
velocity and heading into ``YacsCommand``s so that the flight model can be exercised in hover,
wind and forward flight.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from sim.truth_state import TruthState
from sim.yacs import YacsCommand

if TYPE_CHECKING:
    from sim.aircraft import Aircraft

G = 9.80665


class VelocityHold:
    """PI on the horizontal velocity error -> roll/pitch commands; P on heading -> yaw rate."""

    def __init__(
        self, k_vel: float = 0.5, k_int: float = 0.1, max_tilt: float = math.radians(25.0)
    ) -> None:
        """Gains in m/s^2 per m/s (proportional) and per m (integral)."""
        self._k_vel = k_vel
        self._k_int = k_int
        self._max_tilt = max_tilt
        self._int_e = 0.0
        self._int_n = 0.0

    def update(
        self,
        state: TruthState,
        dt: float,
        velocity_en: tuple[float, float],
        climb_rate: float,
        heading: float,
    ) -> YacsCommand:
        """Command for the desired ENU ground velocity, climb rate (m/s) and heading (rad)."""
        ve, vn, _ = state.velocity_enu
        err_e = velocity_en[0] - ve
        err_n = velocity_en[1] - vn
        if not state.on_ground:
            self._int_e += err_e * dt
            self._int_n += err_n * dt
        acc_e = self._k_vel * err_e + self._k_int * self._int_e
        acc_n = self._k_vel * err_n + self._k_int * self._int_n
        c, s = math.cos(state.heading), math.sin(state.heading)
        acc_fwd = acc_n * c + acc_e * s
        acc_right = -acc_n * s + acc_e * c
        limit = self._max_tilt
        pitch = max(-limit, min(limit, -math.atan2(acc_fwd, G)))
        roll = max(-limit, min(limit, math.atan2(acc_right, G)))
        heading_err = (heading - state.heading + math.pi) % (2.0 * math.pi) - math.pi
        return YacsCommand(roll=roll, pitch=pitch, yaw_rate=1.0 * heading_err, vertical=climb_rate)


def fly(
    aircraft: Aircraft,
    hold: VelocityHold,
    seconds: float,
    velocity_en: tuple[float, float] = (0.0, 0.0),
    climb_rate: float = 0.0,
    heading: float = 0.0,
    outer_rate_hz: float = 50.0,
) -> TruthState:
    """Fly ``seconds`` with the outer loop at ``outer_rate_hz`` over the 200 Hz aircraft steps."""
    inner = max(1, round(1.0 / (outer_rate_hz * aircraft.model.dt)))
    outer_dt = inner * aircraft.model.dt
    for _ in range(round(seconds / outer_dt)):
        aircraft.command(hold.update(aircraft.truth(), outer_dt, velocity_en, climb_rate, heading))
        for _ in range(inner):
            aircraft.step()
    return aircraft.truth()
