"""On-ground detection: a skid load switch, debounced by thresholding a noisy load signal."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


@dataclass(frozen=True, slots=True)
class GroundContactParams:
    """The switch reads a normalised skid load (1 on ground, 0 airborne) thresholded at 0.5.

    With the nominal 0.05 load noise a false reading is a 10-sigma event (never); NOISE_UP by 10
    gives a 16 % flip rate, BIAS of +-1 makes it stuck.
    """

    rate_hz: float = 50.0
    noise: float = 0.05
    threshold: float = 0.5


@dataclass(frozen=True, slots=True)
class GroundContactSample:
    """One on-ground flag."""

    time: float
    on_ground: bool


class GroundContactSensor(Sensor[GroundContactSample]):
    """Skid switch (always powered with the airframe); field (load) for BIAS."""

    fields = ("load",)

    def __init__(self, params: GroundContactParams | None = None, seed: int = 0) -> None:
        self.params = params or GroundContactParams()
        super().__init__("ground_contact", self.params.rate_hz, seed)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        load = 1.0 if truth.on_ground else 0.0
        return np.array([load + scale * self.params.noise * float(self.rng.standard_normal())])

    def _pack(
        self, time: float, truth: TruthState, value: NDArray[np.float64]
    ) -> GroundContactSample:
        return GroundContactSample(time, bool(value[0] >= self.params.threshold))
