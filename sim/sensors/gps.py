"""GPS receiver: WGS84 position and ENU velocity at 10 Hz with correlated error and outages."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.geodesy import GeodeticOrigin, LocalFrame
from sim.sensors.noise import GaussMarkov
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


@dataclass(frozen=True, slots=True)
class GpsParams:
    """Error model of a single-frequency receiver without differential correction.

    Standalone GPS is good to a few metres, dominated by slowly varying errors (ionosphere,
    ephemeris, multipath) rather than white noise; the chapter (section 11.1.1) measured a bias of
    about two metres east and north without differential correction.
    """

    rate_hz: float = 10.0
    horizontal_sigma: float = 1.5
    """Gauss-Markov std per horizontal axis, m (~2.1 m radial rms)."""
    vertical_sigma: float = 3.0
    """Gauss-Markov std of the vertical error, m (vertical is ~2x worse than horizontal)."""
    correlation_time: float = 120.0
    """s: the correlated error wanders over minutes."""
    white_position_sigma: float = 0.3
    """m, per axis, sample-to-sample jitter."""
    velocity_sigma: float = 0.1
    """m/s per axis (Doppler velocity)."""
    outage_rate: float = 1.0 / 600.0
    """Outages start at this rate, 1/s (one every ten minutes on average)."""
    outage_mean_duration: float = 2.0
    """s, exponential."""


@dataclass(frozen=True, slots=True)
class GpsSample:
    """One GPS fix."""

    time: float
    latitude: float
    """Degrees, WGS84."""
    longitude: float
    """Degrees, WGS84."""
    altitude: float
    """Metres above the WGS84 ellipsoid."""
    position_enu: tuple[float, float, float]
    """The same fix in the world's local ENU frame, m."""
    velocity_enu: tuple[float, float, float]
    """m/s."""


class Gps(Sensor[GpsSample]):
    """GPS receiver; fields (e, n, u, ve, vn, vu) in metres and m/s for BIAS."""

    fields = ("east", "north", "up", "v_east", "v_north", "v_up")

    def __init__(
        self,
        origin: GeodeticOrigin,
        params: GpsParams | None = None,
        seed: int = 0,
        power: PowerManager | None = None,
    ) -> None:
        self.origin = origin
        self._frame = LocalFrame(origin)
        self.params = params or GpsParams()
        p = self.params
        self._horizontal = GaussMarkov(p.horizontal_sigma, p.correlation_time, 2)
        self._vertical = GaussMarkov(p.vertical_sigma, p.correlation_time, 1)
        super().__init__("gps", p.rate_hz, seed, power, PowerDevice.GPS)

    def _reset_state(self) -> None:
        self._horizontal.reset(self.rng)
        self._vertical.reset(self.rng)
        self._outage_until = -math.inf

    def shift_time(self, seconds: float) -> None:
        """Move the schedule and a running outage by ``seconds``."""
        super().shift_time(seconds)
        self._outage_until += seconds

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        p = self.params
        error = np.concatenate(
            [self._horizontal.step(dt, self.rng), self._vertical.step(dt, self.rng)]
        )
        white = self.rng.standard_normal(6)
        starts = self.rng.random() < 1.0 - math.exp(-p.outage_rate * dt)
        duration = self.rng.exponential(p.outage_mean_duration)
        if truth.time < self._outage_until:
            return None
        if starts:
            self._outage_until = truth.time + duration
            return None
        position = np.asarray(truth.position_enu) + scale * (
            error + p.white_position_sigma * white[:3]
        )
        velocity = np.asarray(truth.velocity_enu) + scale * p.velocity_sigma * white[3:]
        return np.concatenate([position, velocity])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> GpsSample:
        e, n, u = (float(v) for v in value[:3])
        fix = self._frame.to_geodetic(e, n, u)
        velocity = (float(value[3]), float(value[4]), float(value[5]))
        return GpsSample(time, fix.latitude, fix.longitude, fix.altitude, (e, n, u), velocity)
