"""Sensor suite: one step drives every sensor, determinism, faults and power by name."""

from __future__ import annotations

import math

import pytest

from sim.sensors.errors import SensorError
from sim.sensors.fake_truth import make_truth
from sim.sensors.fault import FaultMode
from sim.sensors.power import PowerDevice
from sim.sensors.suite import SensorReadings, SensorSuite
from sim.world_geometry import WorldGeometry
from sim.world_loader import load_world

WORLD = load_world("revinge")
GEOMETRY = WorldGeometry(WORLD)
DT = 0.005


def fly(suite: SensorSuite, seconds: float) -> list[SensorReadings]:
    return [
        suite.step(make_truth(k * DT, position_enu=(-60.0, 40.0, 8.0)), DT)
        for k in range(round(seconds / DT))
    ]


def test_first_step_reads_every_sensor() -> None:
    readings = SensorSuite(WORLD, seed=1, geometry=GEOMETRY).step(make_truth(0.0), DT)
    missing = [name for name in SensorReadings.__slots__ if getattr(readings, name) is None]
    assert missing == []


def test_same_seed_same_readings_and_independent_streams() -> None:
    a = fly(SensorSuite(WORLD, seed=3, geometry=GEOMETRY), 0.2)
    b = fly(SensorSuite(WORLD, seed=3, geometry=GEOMETRY), 0.2)
    c = fly(SensorSuite(WORLD, seed=4, geometry=GEOMETRY), 0.2)
    assert a == b and a != c


def test_fault_and_power_by_name() -> None:
    suite = SensorSuite(WORLD, seed=1, geometry=GEOMETRY)
    assert len(suite.sensors()) == 12
    suite.sensor("gps").fault.set(FaultMode.DROP)
    suite.power.switch(PowerDevice.LASER, on=False)
    readings = fly(suite, 0.5)
    assert all(r.gps is None and r.laser is None for r in readings)
    assert any(r.imu is not None for r in readings)
    assert readings[-1].power is None or readings[-1].power.status & PowerDevice.LASER == 0
    with pytest.raises(SensorError):
        suite.sensor("sonar")


def test_step_moves_the_ptu_and_frames_follow() -> None:
    suite = SensorSuite(WORLD, seed=1, geometry=GEOMETRY)
    suite.ptu.command(0.0, math.pi / 2)
    readings = fly(suite, 2.0)
    frames = [r.color_camera for r in readings if r.color_camera is not None]
    assert frames[0].tilt == pytest.approx(0.0, abs=0.01)
    assert frames[-1].tilt == pytest.approx(math.pi / 2, abs=0.01)
