"""Yaw and climb modes (fcl_yaw, fcl_climb) flown in the sim, plus their bad input."""

from __future__ import annotations

import math
from types import ModuleType

import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import AttitudeCommand, EstimatedState, wrap_pi
from hdrc3_control.heading_climb import ClimbMode, ModeOutput, ModeStatus, YawMode

HOVERING = EstimatedState(0.0, (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("call", "value"),
    [("yaw", math.nan), ("climb", math.inf)],
)
def test_non_finite_targets_are_refused(call: str, value: float) -> None:
    with pytest.raises(ConfigError):
        if call == "yaw":
            YawMode().start(HOVERING, value)
        else:
            ClimbMode().start(HOVERING, value)


def test_small_altitude_change_is_done_at_once() -> None:
    mode = ClimbMode()
    mode.start(HOVERING, 10.3)
    out = mode.update(HOVERING, 0.0, 0.02)
    assert out.status is ModeStatus.DONE and out.hover_point.position == (0.0, 0.0, 10.3)


def test_yaw_then_climb_in_the_sim(harness: ModuleType) -> None:
    f = harness.SimFlight(seed=11)
    f.start_engine()
    up = harness.takeoff(f, 10.0)
    assert up.ok
    yaw = YawMode()
    target = f.state().heading + math.radians(90.0)
    yaw.start(f.state(), target, up.integral)
    outs: list[ModeOutput] = []

    def turn(s: EstimatedState, now: float) -> AttitudeCommand:
        outs.append(yaw.update(s, f.dt))
        return outs[-1].command

    assert f.fly(turn, 20.0, until=lambda: outs[-1].status is ModeStatus.DONE)
    assert abs(wrap_pi(f.truth().heading - target)) < math.radians(5.0)
    assert 90.0 / 20.0 - 1.0 < f.now - f.log.time[-len(outs)] < 15.0  # slewed, not jumped
    climb = ClimbMode()
    climb.start(f.state(), 20.0, yaw.integral)
    couts: list[ModeOutput] = []

    def up_ctl(s: EstimatedState, now: float) -> AttitudeCommand:
        couts.append(climb.update(s, now, f.dt))
        return couts[-1].command

    assert f.fly(up_ctl, 30.0, until=lambda: couts[-1].status is ModeStatus.DONE)
    assert abs(f.state().position[2] - 20.0) <= 3.0
    moved = math.dist(f.log.truth[-len(couts)].position_enu[:2], f.truth().position_enu[:2])
    assert moved < 2.0  # a vertical path: no horizontal excursion
