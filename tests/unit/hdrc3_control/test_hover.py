"""Hovering: Hover-Stable-CO tolerances, and hovering through a GPS dropout in the sim."""

from __future__ import annotations

import math
from types import ModuleType

import numpy as np
import pytest

from hdrc3_control.commands import EstimatedState, EstimatorHealth
from hdrc3_control.hover import HoverController, HoverSetpoint, HoverStatus, hover_stable
from sim.sensors.fault import FaultMode

SP = HoverSetpoint((0.0, 0.0, 20.0), 0.0)


def _state(
    pos: tuple[float, float, float], vel: tuple[float, float, float], hdg: float
) -> EstimatedState:
    return EstimatedState(0.0, pos, vel, 0.0, 0.0, hdg)


@pytest.mark.parametrize(
    ("pos", "vel", "hdg", "stable"),
    [
        ((0.0, 0.0, 20.0), (0.0, 0.0, 0.0), 0.0, True),
        ((3.0, 3.9, 21.9), (0.7, 0.7, 0.9), math.radians(4.9), True),
        ((3.0, 4.1, 20.0), (0.0, 0.0, 0.0), 0.0, False),  # 5.08 m off
        ((0.0, 0.0, 22.1), (0.0, 0.0, 0.0), 0.0, False),
        ((0.0, 0.0, 20.0), (0.0, 0.0, 0.0), math.radians(-5.1), False),
        ((0.0, 0.0, 20.0), (0.8, 0.8, 0.0), 0.0, False),
        ((0.0, 0.0, 20.0), (0.0, 0.0, -1.1), 0.0, False),
        ((0.0, 0.0, 20.0), (0.0, 0.0, 0.0), 2 * math.pi - 0.05, True),  # heading wraps
    ],
)
def test_hover_stable_tolerances(
    pos: tuple[float, float, float], vel: tuple[float, float, float], hdg: float, stable: bool
) -> None:
    assert hover_stable(_state(pos, vel, hdg), SP) is stable


def test_lost_navigation_levels_the_aircraft() -> None:
    lost = EstimatedState(
        0.0, (9.0, 9.0, 9.0), (3.0, 0.0, 0.0), 0.1, 0.1, 0.0, health=EstimatorHealth.LOST
    )
    out = HoverController(SP).update(lost, 0.02)
    assert out.status is HoverStatus.NAVIGATION_LOST
    assert (out.command.roll, out.command.pitch, out.command.vertical) == (0.0, 0.0, 0.0)


def test_hover_through_a_gps_dropout_stays_hover_stable(harness: ModuleType) -> None:
    f = harness.SimFlight(seed=4)
    f.start_engine()
    up = harness.takeoff(f, 10.0)
    assert up.ok
    settle = harness.hover(f, up.outputs[-1].hover_point, 25.0, up.integral, until_stable=True)
    assert settle.ok
    setpoint = up.outputs[-1].hover_point
    before = harness.hover(f, setpoint, 5.0, settle.integral)
    truth_ref = np.mean([t.position_enu for t in f.log.truth[before.first_tick :]], axis=0)
    f.suite.sensor("gps").fault.set(FaultMode.DROP)
    dropped = harness.hover(f, setpoint, 4.0, before.integral)
    f.suite.sensor("gps").fault.clear()
    after = harness.hover(f, setpoint, 5.0, dropped.integral)
    health = [s.health for s in f.log.estimate[dropped.first_tick :]]
    assert EstimatorHealth.DEGRADED in health and EstimatorHealth.LOST not in health
    assert f.log.estimate[-1].health is EstimatorHealth.OK
    assert all(o.status is HoverStatus.STABLE for o in dropped.outputs + after.outputs)
    truth = np.array([t.position_enu for t in f.log.truth[dropped.first_tick :]])
    assert np.max(np.hypot(*(truth[:, :2] - truth_ref[:2]).T)) < 5.0
    assert np.max(np.abs(truth[:, 2] - truth_ref[2])) < 2.0
