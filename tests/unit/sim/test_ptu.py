"""Pan-tilt unit: limits, rate limits, command statuses, power."""

from __future__ import annotations

import math

import pytest

from sim.sensors.errors import SensorError
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.ptu import PanTiltUnit, PtuCommandStatus, PtuParams

DEG = math.radians(1.0)


@pytest.mark.parametrize(
    ("pan", "tilt", "status", "target"),
    [
        (0.5, 1.0, PtuCommandStatus.ACCEPTED, (0.5, 1.0)),
        (4.0, 1.0, PtuCommandStatus.CLAMPED, (170 * DEG, 1.0)),
        (-4.0, -1.0, PtuCommandStatus.CLAMPED, (-170 * DEG, -10 * DEG)),
        (0.0, 2.0, PtuCommandStatus.CLAMPED, (0.0, 95 * DEG)),
        (math.nan, 0.0, PtuCommandStatus.REJECTED, (0.0, 0.0)),
        (0.0, math.inf, PtuCommandStatus.REJECTED, (0.0, 0.0)),
    ],
)
def test_command_limits(
    pan: float, tilt: float, status: PtuCommandStatus, target: tuple[float, float]
) -> None:
    result = PanTiltUnit().command(pan, tilt)
    assert result.status is status
    assert (result.pan_target, result.tilt_target) == pytest.approx(target)


def test_rate_limited_motion_reaches_target() -> None:
    ptu = PanTiltUnit()
    ptu.command(math.radians(90.0), math.radians(90.0))
    dt = 0.02
    ptu.step(dt)
    assert ptu.pan == pytest.approx(60 * DEG * dt) and ptu.tilt == pytest.approx(60 * DEG * dt)
    steps = 1
    while not ptu.at_target:
        ptu.step(dt)
        steps += 1
    assert steps * dt == pytest.approx(1.5, abs=dt)  # 90 deg at 60 deg/s
    assert (ptu.pan, ptu.tilt) == (math.radians(90.0), math.radians(90.0))


def test_unpowered_ptu_neither_accepts_nor_moves() -> None:
    manager = PowerManager()
    ptu = PanTiltUnit(power=manager)
    ptu.command(1.0, 1.0)
    manager.switch(PowerDevice.PTU, on=False)
    ptu.step(0.5)
    assert (ptu.pan, ptu.tilt) == (0.0, 0.0)
    assert ptu.command(0.2, 0.2).status is PtuCommandStatus.UNPOWERED


def test_bad_parameters_and_steps() -> None:
    with pytest.raises(SensorError):
        PtuParams(pan_min=1.0, pan_max=0.0)
    with pytest.raises(SensorError):
        PanTiltUnit().step(-0.1)
