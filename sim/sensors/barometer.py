"""Barometric altimeter: altitude with white noise and slow weather/temperature drift."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.noise import GaussMarkov
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState

SEA_LEVEL_PRESSURE = 101325.0
"""Pa, ISA."""


def isa_pressure(altitude: float) -> float:
    """ISA troposphere pressure at ``altitude`` metres, Pa."""
    return float(SEA_LEVEL_PRESSURE * (1.0 - 2.25577e-5 * altitude) ** 5.25588)


@dataclass(frozen=True, slots=True)
class BarometerParams:
    """Error model of a MEMS static-pressure altimeter (e.g. MS5611 class, 0.012 mbar rms ~ 0.1 m).

    White noise is raised to 0.3 m for rotor downwash and airspeed effects on the static port;
    the drift stands for weather pressure change (~1 hPa/h ~ 8 m/h) over a flight.
    """

    rate_hz: float = 25.0
    noise: float = 0.3
    """m, 1 sigma, white."""
    drift_sigma: float = 2.0
    """m, Gauss-Markov std of the slow drift."""
    drift_time: float = 900.0
    """s, drift correlation time."""


@dataclass(frozen=True, slots=True)
class BarometerSample:
    """One barometric reading."""

    time: float
    altitude: float
    """m, same datum as GPS altitude (WGS84 ellipsoid) plus the barometric error."""
    pressure: float
    """Pa, ISA pressure at ``altitude``."""


class Barometer(Sensor[BarometerSample]):
    """Barometric altimeter on the PFC; field (altitude) for BIAS."""

    fields = ("altitude",)

    def __init__(
        self,
        origin_altitude: float,
        params: BarometerParams | None = None,
        seed: int = 0,
        power: PowerManager | None = None,
    ) -> None:
        self.origin_altitude = origin_altitude
        self.params = params or BarometerParams()
        self._drift = GaussMarkov(self.params.drift_sigma, self.params.drift_time)
        super().__init__("barometer", self.params.rate_hz, seed, power, PowerDevice.PFC)

    def _reset_state(self) -> None:
        self._drift.reset(self.rng)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        drift = float(self._drift.step(dt, self.rng)[0])
        white = float(self.rng.standard_normal())
        altitude = (
            self.origin_altitude + truth.position_enu[2] + drift + scale * self.params.noise * white
        )
        return np.array([altitude])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> BarometerSample:
        altitude = float(value[0])
        return BarometerSample(time, altitude, isa_pressure(altitude))
