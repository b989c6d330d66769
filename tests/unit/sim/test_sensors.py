"""Behaviour shared by every sensor: rates, determinism, power gating and the four fault modes.

The fault tests compare a faulted run with an unfaulted run from the same seed: the noise stream
is drawn identically in both, so a BIAS shows up as an exact offset.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

from sim.geodesy import GeodeticOrigin
from sim.sensors.attitude import AttitudeSample, AttitudeSensor
from sim.sensors.barometer import Barometer, BarometerSample
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, Camera, CameraFrame
from sim.sensors.engine import RpmSample, RpmSensor
from sim.sensors.errors import SensorError
from sim.sensors.fake_truth import make_truth
from sim.sensors.fault import FaultMode
from sim.sensors.gps import Gps, GpsParams, GpsSample
from sim.sensors.ground_contact import GroundContactSample, GroundContactSensor
from sim.sensors.imu import Imu, ImuSample
from sim.sensors.laser import LaserRangeFinder, LaserScan
from sim.sensors.power import PowerDevice, PowerManager, PowerSample, PowerSensor
from sim.sensors.ptu import PanTiltUnit, PtuSample, PtuSensor
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState
from sim.world_geometry import WorldGeometry
from sim.world_loader import load_world

ORIGIN = GeodeticOrigin(55.70, 13.47, 95.0)
FDM_HZ = 200.0
GEOMETRY = WorldGeometry(load_world("revinge"))


@dataclass(frozen=True)
class Case:
    build: Callable[[int, PowerManager], Sensor[Any]]
    values: Callable[[Any], NDArray[np.float64]]
    rate_hz: float
    device: PowerDevice | None


def _ptu() -> PanTiltUnit:
    ptu = PanTiltUnit()
    ptu.pan, ptu.tilt = 0.3, 1.2
    return ptu


def _gps(s: GpsSample) -> NDArray[np.float64]:
    return np.array([*s.position_enu, *s.velocity_enu])


def _imu(s: ImuSample) -> NDArray[np.float64]:
    return np.array([*s.specific_force, *s.angular_rate])


def _baro(s: BarometerSample) -> NDArray[np.float64]:
    return np.array([s.altitude])


def _att(s: AttitudeSample) -> NDArray[np.float64]:
    return np.array([s.roll, s.pitch, s.heading])


def _rpm(s: RpmSample) -> NDArray[np.float64]:
    return np.array([s.rpm])


def _ground(s: GroundContactSample) -> NDArray[np.float64]:
    return np.array([float(s.on_ground)])


def _power(s: PowerSample) -> NDArray[np.float64]:
    return np.array([s.voltage, s.current, float(s.status)])


def _ptu_values(s: PtuSample) -> NDArray[np.float64]:
    return np.array([s.pan, s.tilt])


def _camera(s: CameraFrame) -> NDArray[np.float64]:
    return np.array([s.pan, s.tilt, s.zoom])


def _laser(s: LaserScan) -> NDArray[np.float64]:
    return np.array([s.rotation_angle, *s.ranges])


CASES: dict[str, Case] = {
    "gps": Case(
        lambda seed, pm: Gps(ORIGIN, GpsParams(outage_rate=0.0), seed, pm),
        _gps,
        10.0,
        PowerDevice.GPS,
    ),
    "imu": Case(lambda seed, pm: Imu(seed=seed, power=pm), _imu, 200.0, PowerDevice.IMU),
    "barometer": Case(
        lambda seed, pm: Barometer(ORIGIN.altitude, seed=seed, power=pm),
        _baro,
        25.0,
        PowerDevice.PFC,
    ),
    "attitude": Case(
        lambda seed, pm: AttitudeSensor(seed=seed, power=pm), _att, 50.0, PowerDevice.PFC
    ),
    "rpm": Case(lambda seed, pm: RpmSensor(seed=seed), _rpm, 25.0, None),
    "ground_contact": Case(lambda seed, pm: GroundContactSensor(seed=seed), _ground, 50.0, None),
    "power": Case(lambda seed, pm: PowerSensor(pm, seed=seed), _power, 5.0, None),
    "ptu": Case(lambda seed, pm: PtuSensor(_ptu(), seed, pm), _ptu_values, 25.0, PowerDevice.PTU),
    "color_camera": Case(
        lambda seed, pm: Camera(COLOR_CAMERA, _ptu(), seed, pm),
        _camera,
        25.0,
        PowerDevice.COLOR_CAMERA,
    ),
    "thermal_camera": Case(
        lambda seed, pm: Camera(THERMAL_CAMERA, _ptu(), seed, pm),
        _camera,
        25.0,
        PowerDevice.THERMAL_CAMERA,
    ),
    "laser": Case(
        lambda seed, pm: LaserRangeFinder(GEOMETRY, seed=seed, power=pm),
        _laser,
        1 / 0.013,
        PowerDevice.LASER,
    ),
}
# A truth over the revinge town so the laser sees buildings; heading east, slight bank.
TRUTH = {"position_enu": (-60.0, 40.0, 8.0), "heading": math.pi / 2, "roll": 0.05}


def run(sensor: Sensor[Any], duration: float, start: float = 0.0, **changes: Any) -> list[Any]:
    steps = round(duration * FDM_HZ)
    truths = [make_truth(start + k / FDM_HZ, **{**TRUTH, **changes}) for k in range(steps)]
    samples = [sensor.update(t) for t in truths]
    return [s for s in samples if s is not None]


def matrix(case: Case, samples: list[Any]) -> NDArray[np.float64]:
    return np.array([case.values(s) for s in samples])


def duration_for(case: Case) -> float:
    return 20.0 / case.rate_hz  # 20 samples each


@pytest.mark.parametrize("name", sorted(CASES))
def test_rate_and_timestamps(name: str) -> None:
    case = CASES[name]
    duration = 4.0 if case.rate_hz < 50.0 else 1.0
    samples = run(case.build(1, PowerManager()), duration)
    expected = duration * case.rate_hz
    assert abs(len(samples) - expected) <= 1.0 + 0.06 * expected  # FDM steps quantise the rate
    times = np.array([s.time for s in samples])
    assert np.all(np.diff(times) > 0.0) and times[0] == 0.0


@pytest.mark.parametrize("name", sorted(CASES))
def test_same_seed_same_samples(name: str) -> None:
    case = CASES[name]
    d = duration_for(case)
    first = run(case.build(7, PowerManager()), d)
    sensor = case.build(7, PowerManager())
    run(sensor, d / 2)
    sensor.reset(7)  # reset restarts the stream exactly
    assert run(sensor, d) == first == run(case.build(7, PowerManager()), d)


@pytest.mark.parametrize("name", sorted(set(CASES) - {"ground_contact"}))
def test_different_seed_different_noise(name: str) -> None:
    case = CASES[name]
    d = duration_for(case)
    a = matrix(case, run(case.build(1, PowerManager()), d))
    b = matrix(case, run(case.build(2, PowerManager()), d))
    assert not np.array_equal(a, b)


@pytest.mark.parametrize("name", sorted(CASES))
def test_drop_fault(name: str) -> None:
    case = CASES[name]
    sensor = case.build(3, PowerManager())
    sensor.fault.set(FaultMode.DROP)
    assert run(sensor, duration_for(case)) == []
    sensor.fault.clear()
    assert run(sensor, duration_for(case), start=duration_for(case))


@pytest.mark.parametrize("name", sorted(CASES))
def test_freeze_fault_repeats_last_value(name: str) -> None:
    case = CASES[name]
    sensor = case.build(3, PowerManager())
    before = run(sensor, duration_for(case))
    sensor.fault.set(FaultMode.FREEZE)
    steps = round(5 * FDM_HZ / case.rate_hz)  # five more periods
    later = [make_truth(duration_for(case) + k / FDM_HZ, **TRUTH) for k in range(1, steps)]
    frozen = [s for s in (sensor.update(t) for t in later) if s is not None]
    assert len(frozen) >= 2
    assert all(np.array_equal(case.values(s), case.values(before[-1])) for s in frozen)
    assert frozen[-1].time > before[-1].time  # fresh timestamps on a stuck value


@pytest.mark.parametrize("name", sorted(CASES))
def test_bias_fault_is_an_exact_offset(name: str) -> None:
    case = CASES[name]
    d = duration_for(case)
    clean = matrix(case, run(case.build(5, PowerManager()), d))
    sensor = case.build(5, PowerManager())
    sensor.fault.set(FaultMode.BIAS, 0.25)
    biased = matrix(case, run(sensor, d))
    assert np.array_equal(np.isinf(biased), np.isinf(clean))  # no return stays no return
    offset = np.where(np.isfinite(clean), biased, 0.0) - np.where(np.isfinite(clean), clean, 0.0)
    if name == "ground_contact":
        assert np.all(biased == clean)  # a 0.25 load bias does not cross the 0.5 threshold
        return
    if name == "rpm":
        assert np.all(np.abs(offset) <= 1.0)  # whole-rpm rounding swallows a quarter rpm
        return
    biasable = {"power": [0, 1], "color_camera": [0, 1], "thermal_camera": [0, 1]}
    columns = biasable.get(name, list(range(1 if name == "laser" else 0, clean.shape[1])))
    mask = np.zeros(clean.shape[1], dtype=bool)
    mask[columns] = True
    resolution = 0.011 if name == "laser" else 1e-9  # ranges are quantised to 1 cm
    finite = np.isfinite(clean)
    assert np.all(np.abs(offset[:, mask][finite[:, mask]] - 0.25) < resolution)
    assert np.all(offset[:, ~mask] == 0.0)


@pytest.mark.parametrize("name", sorted(set(CASES) - {"power", "rpm"}))
def test_noise_up_fault_spreads_samples(name: str) -> None:
    case = CASES[name]
    d = 2 * duration_for(case)
    clean = matrix(case, run(case.build(4, PowerManager()), d))
    sensor = case.build(4, PowerManager())
    sensor.fault.set(FaultMode.NOISE_UP, 10.0)
    noisy = matrix(case, run(sensor, d))
    finite = np.all(np.isfinite(clean), axis=0) & np.all(np.isfinite(noisy), axis=0)
    spread_clean = np.std(clean[:, finite], axis=0)
    spread_noisy = np.std(noisy[:, finite], axis=0)
    assert np.max(spread_noisy) > 3.0 * np.max(spread_clean)


@pytest.mark.parametrize("name", sorted(n for n, c in CASES.items() if c.device is not None))
def test_unpowered_sensor_is_silent(name: str) -> None:
    case = CASES[name]
    manager = PowerManager()
    sensor = case.build(1, manager)
    device = case.device
    assert device is not None
    manager.switch(device, on=False)
    assert run(sensor, duration_for(case)) == []
    manager.switch(device, on=True)
    assert run(sensor, duration_for(case), start=duration_for(case))


@pytest.mark.parametrize(
    ("mode", "magnitude"), [(FaultMode.NOISE_UP, -1.0), (FaultMode.BIAS, math.inf)]
)
def test_bad_fault_magnitude(mode: FaultMode, magnitude: float) -> None:
    with pytest.raises(SensorError):
        RpmSensor().fault.set(mode, magnitude)


def test_bias_vector_must_match_fields() -> None:
    sensor = Imu()
    sensor.fault.set(FaultMode.BIAS, (0.1, 0.2))
    with pytest.raises(SensorError):
        sensor.update(make_truth())


def test_skipped_periods_do_not_burst() -> None:
    sensor = RpmSensor()
    assert sensor.update(make_truth(0.0)) is not None
    assert sensor.update(make_truth(1.0)) is not None  # 24 periods skipped: one sample
    assert sensor.update(make_truth(1.01)) is None
    assert sensor.update(make_truth(1.04)) is not None


def _first(sensor: Sensor[Any], truth: TruthState) -> Any:
    sample = sensor.update(truth)
    assert sample is not None
    return sample


def test_rpm_is_zero_when_stopped_and_rounded() -> None:
    assert _first(RpmSensor(), make_truth(rotor_rpm=0.0)).rpm == 0.0
    assert _first(RpmSensor(seed=3), make_truth(rotor_rpm=850.0)).rpm % 1.0 == 0.0


def test_ground_contact_follows_truth_and_sticks_under_bias() -> None:
    assert _first(GroundContactSensor(), make_truth(on_ground=True)).on_ground
    sensor = GroundContactSensor()
    sensor.fault.set(FaultMode.BIAS, 1.0)
    assert _first(sensor, make_truth(on_ground=False)).on_ground


def test_attitude_heading_wraps() -> None:
    sensor = AttitudeSensor(seed=1)
    sensor.fault.set(FaultMode.BIAS, (0.0, 0.0, -0.5))
    sample = _first(sensor, make_truth(heading=0.1))
    assert 0.0 <= sample.heading < 2 * math.pi and sample.heading > math.pi


def test_barometer_altitude_and_pressure() -> None:
    samples = run(Barometer(ORIGIN.altitude, seed=2), 20.0, position_enu=(0.0, 0.0, 50.0))
    altitudes = np.array([s.altitude for s in samples])
    assert abs(altitudes.mean() - (ORIGIN.altitude + 50.0)) < 8.0  # drift sigma 2 m
    assert 0.2 < np.std(np.diff(altitudes)) / math.sqrt(2) < 0.4  # white noise 0.3 m
    assert samples[0].pressure == pytest.approx(
        101325.0 * (1 - 2.25577e-5 * altitudes[0]) ** 5.25588
    )
