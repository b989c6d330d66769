"""IMU: white noise level, turn-on bias spread across seeds, bias random walk."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.sensors.fake_truth import make_truth
from sim.sensors.imu import Imu, ImuParams, ImuSample

RATES = (0.1, -0.2, 0.05)


def readings(imu: Imu, seconds: float) -> list[ImuSample]:
    steps = round(seconds * imu.rate_hz)
    out = [imu.update(make_truth(k / imu.rate_hz, body_rates=RATES)) for k in range(steps)]
    return [s for s in out if s is not None]


def test_white_noise_levels() -> None:
    samples = readings(Imu(seed=1), 20.0)
    accel = np.array([s.specific_force for s in samples])
    gyro = np.array([s.angular_rate for s in samples])
    # Differencing removes the slowly walking bias; what remains is sqrt(2) x white noise.
    assert np.std(np.diff(accel, axis=0), axis=0) / math.sqrt(2) == pytest.approx(
        [0.05] * 3, rel=0.1
    )
    expected = math.radians(0.2)
    assert np.std(np.diff(gyro, axis=0), axis=0) / math.sqrt(2) == pytest.approx(
        [expected] * 3, rel=0.1
    )
    assert np.mean(accel[:, 2]) == pytest.approx(-9.80665, abs=0.3)


def test_turn_on_bias_spread_across_seeds() -> None:
    biases = []
    for seed in range(300):
        imu = Imu(seed=seed)
        biases.append(imu.biases[1])
    assert np.std(np.array(biases)) == pytest.approx(math.radians(0.2), rel=0.15)


def test_bias_walks_with_its_density() -> None:
    params = ImuParams(accel_bias_initial=0.0, gyro_bias_initial=0.0, accel_bias_walk=0.01)
    finals = []
    for seed in range(50):
        imu = Imu(params, seed=seed)
        readings(imu, 1.0)
        finals.append(imu.biases[0])
    # After 1 s (199 steps of 5 ms) the bias spread is 0.01 * sqrt(0.995) m/s^2 per axis.
    assert np.std(np.array(finals)) == pytest.approx(0.01 * math.sqrt(0.995), rel=0.15)
