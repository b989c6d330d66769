"""Inertial measurement unit: specific force and body rates at 200 Hz with drifting biases."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.noise import RandomWalk
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


@dataclass(frozen=True, slots=True)
class ImuParams:
    """Error model of an industrial MEMS IMU on a vibrating helicopter.

    Figures of the class of ADIS16xxx-type MEMS units (gyro bias instability of a few deg/h,
    turn-on bias up to ~0.3 deg/s); the white noise is raised well above datasheet density
    because rotor vibration (the RMAX main rotor turns at ~14 Hz) dominates on a helicopter.
    """

    rate_hz: float = 200.0
    accel_noise: float = 0.05
    """m/s^2 per sample, 1 sigma (vibration-dominated)."""
    accel_bias_initial: float = 0.05
    """m/s^2, turn-on bias 1 sigma."""
    accel_bias_walk: float = 0.001
    """m/s^2/sqrt(s), bias random walk."""
    gyro_noise: float = math.radians(0.2)
    """rad/s per sample, 1 sigma."""
    gyro_bias_initial: float = math.radians(0.2)
    """rad/s, turn-on bias 1 sigma."""
    gyro_bias_walk: float = math.radians(0.005)
    """rad/s/sqrt(s), bias random walk."""


@dataclass(frozen=True, slots=True)
class ImuSample:
    """One IMU reading in the body frame (FRD)."""

    time: float
    specific_force: tuple[float, float, float]
    """m/s^2 (hover: about (0, 0, -9.81))."""
    angular_rate: tuple[float, float, float]
    """p, q, r in rad/s."""


class Imu(Sensor[ImuSample]):
    """IMU; fields (fx, fy, fz, p, q, r) for BIAS."""

    fields = ("fx", "fy", "fz", "p", "q", "r")

    def __init__(
        self, params: ImuParams | None = None, seed: int = 0, power: PowerManager | None = None
    ) -> None:
        self.params = params or ImuParams()
        p = self.params
        self._accel_bias = RandomWalk(p.accel_bias_initial, p.accel_bias_walk, 3)
        self._gyro_bias = RandomWalk(p.gyro_bias_initial, p.gyro_bias_walk, 3)
        super().__init__("imu", p.rate_hz, seed, power, PowerDevice.IMU)

    def _reset_state(self) -> None:
        self._accel_bias.reset(self.rng)
        self._gyro_bias.reset(self.rng)

    @property
    def biases(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Current true (accelerometer, gyro) biases, for test evaluation."""
        return self._accel_bias.value.copy(), self._gyro_bias.value.copy()

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        p = self.params
        accel_bias = self._accel_bias.step(dt, self.rng)
        gyro_bias = self._gyro_bias.step(dt, self.rng)
        white = self.rng.standard_normal(6)
        accel = (
            np.asarray(truth.specific_force_body) + accel_bias + scale * p.accel_noise * white[:3]
        )
        gyro = np.asarray(truth.body_rates) + gyro_bias + scale * p.gyro_noise * white[3:]
        return np.concatenate([accel, gyro])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> ImuSample:
        f = tuple(float(v) for v in value[:3])
        w = tuple(float(v) for v in value[3:])
        return ImuSample(time, (f[0], f[1], f[2]), (w[0], w[1], w[2]))
