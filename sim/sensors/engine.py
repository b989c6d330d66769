"""Engine (main rotor) rpm sensor: a magnetic pickup counter with jitter and 1 rpm resolution."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


@dataclass(frozen=True, slots=True)
class RpmParams:
    """Error model of a pulse-counting rpm sensor (gate-time jitter of a few rpm at ~850 rpm)."""

    rate_hz: float = 25.0
    noise: float = 5.0
    """rpm, 1 sigma."""


@dataclass(frozen=True, slots=True)
class RpmSample:
    """One rotor speed reading."""

    time: float
    rpm: float
    """Revolutions per minute, rounded to whole rpm, never negative."""


class RpmSensor(Sensor[RpmSample]):
    """Main rotor rpm (read through the Yamaha interface, not power-switched); field (rpm)."""

    fields = ("rpm",)

    def __init__(self, params: RpmParams | None = None, seed: int = 0) -> None:
        self.params = params or RpmParams()
        super().__init__("rpm", self.params.rate_hz, seed)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        white = float(self.rng.standard_normal())
        # A stopped rotor gives no pulses: zero without jitter.
        noise = scale * self.params.noise * white if truth.rotor_rpm > 0.0 else 0.0
        return np.array([truth.rotor_rpm + noise])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> RpmSample:
        return RpmSample(time, float(max(0.0, round(float(value[0])))))
