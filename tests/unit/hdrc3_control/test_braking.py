"""Emergency braking: the braking path, and braking mid-path in the sim."""

from __future__ import annotations

import math
from types import ModuleType

import numpy as np
import pytest

from hdrc3_control.braking import braking_segment
from hdrc3_control.commands import EstimatedState
from hdrc3_control.hover import HoverSetpoint
from hdrc3_control.path_following import PathStatus


@pytest.mark.parametrize(
    ("vel", "heading", "direction", "min_length"),
    [
        ((8.0, 0.0, 0.0), 0.0, (1.0, 0.0), 8.0**2 / 2.4),
        ((0.0, -3.0, 0.0), 0.0, (0.0, -1.0), 3.0**2 / 2.4),
        ((0.1, 0.0, 0.0), math.pi / 2, (1.0, 0.0), 0.0),  # slow: along the heading
    ],
)
def test_braking_segment(
    vel: tuple[float, float, float],
    heading: float,
    direction: tuple[float, float],
    min_length: float,
) -> None:
    state = EstimatedState(0.0, (5.0, 6.0, 20.0), vel, 0.0, 0.0, heading)
    seg = braking_segment(state, 1.2)
    assert seg.target_velocity == 0.0 and seg.end_velocity == 0.0
    np.testing.assert_allclose(seg.tangent(0.5)[:2], direction, atol=1e-9)
    assert seg.arc_length() >= min_length + 5.0 - 1e-9
    assert seg.end[2] == 20.0


def test_emergency_brake_mid_path_then_hover(harness: ModuleType) -> None:
    f = harness.SimFlight(seed=6, placement=harness.FIGURE7_START)
    f.start_engine()
    up = harness.takeoff(f, 12.0)
    path = harness.figure7_path(f.state().position)
    run = harness.fly_path(f, path, up.integral, stop_after=lambda o: o.speed_ref >= 7.9)
    assert run.outputs[-1].status is PathStatus.FOLLOWING
    assert f.truth().velocity_enu[0] > 6.0
    x0 = f.truth().position_enu[0]
    stop = harness.brake(f, run.integral)
    assert stop.ok
    travelled = f.truth().position_enu[0] - x0
    assert 0.0 < travelled < 40.0
    hp = stop.outputs[-1].hover_point
    hold = harness.hover(f, HoverSetpoint(hp, f.state().heading), 10.0, stop.integral)
    assert hold.outputs[-1].status.name == "STABLE"
