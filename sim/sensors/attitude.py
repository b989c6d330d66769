"""Attitude and heading sensor (the Yamaha Attitude Sensor, YAS, of chapter section 4.2)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.fault import wrap_angle
from sim.sensors.noise import GaussMarkov
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


@dataclass(frozen=True, slots=True)
class AttitudeParams:
    """Error model of an AHRS with magnetometer heading.

    Roll/pitch of a vibration-isolated AHRS are good to a few tenths of a degree; the magnetic
    heading carries an extra slowly varying error (local disturbances, declination model,
    engine/ferrous interference) of about a degree.
    """

    rate_hz: float = 50.0
    roll_pitch_noise: float = math.radians(0.2)
    """rad, 1 sigma, white."""
    heading_noise: float = math.radians(0.5)
    """rad, 1 sigma, white."""
    heading_bias_sigma: float = math.radians(1.0)
    """rad, Gauss-Markov std of the magnetic heading error."""
    heading_bias_time: float = 300.0
    """s."""


@dataclass(frozen=True, slots=True)
class AttitudeSample:
    """One attitude reading (Euler 3-2-1)."""

    time: float
    roll: float
    pitch: float
    heading: float
    """rad clockwise from north, [0, 2*pi)."""


class AttitudeSensor(Sensor[AttitudeSample]):
    """YAS attitude and heading; fields (roll, pitch, heading) in rad for BIAS."""

    fields = ("roll", "pitch", "heading")

    def __init__(
        self, params: AttitudeParams | None = None, seed: int = 0, power: PowerManager | None = None
    ) -> None:
        self.params = params or AttitudeParams()
        p = self.params
        self._heading_bias = GaussMarkov(p.heading_bias_sigma, p.heading_bias_time)
        super().__init__("attitude", p.rate_hz, seed, power, PowerDevice.PFC)

    def _reset_state(self) -> None:
        self._heading_bias.reset(self.rng)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        p = self.params
        bias = float(self._heading_bias.step(dt, self.rng)[0])
        white = self.rng.standard_normal(3)
        return np.array(
            [
                truth.roll + scale * p.roll_pitch_noise * white[0],
                truth.pitch + scale * p.roll_pitch_noise * white[1],
                truth.heading + bias + scale * p.heading_noise * white[2],
            ]
        )

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> AttitudeSample:
        return AttitudeSample(time, float(value[0]), float(value[1]), wrap_angle(float(value[2])))
