"""Ground-truth samples for sensor tests and demos (a fake of the flight model's output)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from sim.truth_state import TruthState

GRAVITY = 9.80665

HOVER = TruthState(
    time=0.0,
    position_enu=(0.0, 0.0, 20.0),
    velocity_enu=(0.0, 0.0, 0.0),
    roll=0.0,
    pitch=0.0,
    heading=0.0,
    body_rates=(0.0, 0.0, 0.0),
    specific_force_body=(0.0, 0.0, -GRAVITY),
    rotor_rpm=850.0,
    engine_running=True,
    on_ground=False,
    height_above_ground=20.0,
    mass=80.0,
)
"""Level hover 20 m above the origin, heading north, rotor at nominal speed."""


def make_truth(time: float = 0.0, **changes: Any) -> TruthState:
    """Make a hover truth state at ``time`` with some fields changed."""
    return replace(HOVER, time=time, **changes)


def truth_series(rate_hz: float, duration: float, **changes: Any) -> list[TruthState]:
    """Make constant truth states at ``rate_hz`` for ``duration`` s (like FDM steps)."""
    steps = round(duration * rate_hz)
    return [make_truth(k / rate_hz, **changes) for k in range(steps)]
