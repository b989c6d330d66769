"""Gamma dose-rate meter and the radiation field it reads (section 9.4's monitor-radiation).

The chapter's Fukushima examples have AVs monitor radiation at a damaged reactor. The field is
the world file's point sources (``[[radiation_source]]``): each gives ``dose_rate`` microsievert
per hour at 1 m, falling with the square of the distance and the air's linear attenuation
``exp(-mu * d)``, over the world's natural background. Buildings do not shield (a simplification
this model states rather than hides). The detector counts photons: a Poisson number with the
mean ``sensitivity * dose rate * integration time``, so a reading's relative noise is
``1 / sqrt(counts)``; it reports the counts and the dose rate they stand for. Hand-written (a few
lines of physics) because no maintained Python package models a dose-rate meter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState
from sim.world import World

Vec3 = tuple[float, float, float]
NEAR_M = 1.0
"""m: closer than this to a source the field is taken as at 1 m (inside the source's casing)."""


@dataclass(frozen=True, slots=True)
class RadiationParams:
    """Rate and response of the detector (a small CsI scintillator)."""

    rate_hz: float = 1.0
    """Samples per second; each integrates over its whole period."""
    sensitivity: float = 50.0
    """Counts per second per microsievert per hour."""


@dataclass(frozen=True, slots=True)
class RadiationSample:
    """One integration of the detector."""

    time: float
    dose_rate: float
    """microsievert per hour, from the counts."""
    counts: int
    integration_time: float
    """s."""


class RadiationField:
    """The dose rate at any point of a world (ground truth: only sensors read it)."""

    def __init__(self, world: World) -> None:
        """Place every source of ``world`` at its height above the terrain."""
        self.background = world.radiation_background
        self._sources = [
            (
                (s.east, s.north, world.terrain.height(s.east, s.north) + s.height),
                s.dose_rate,
                s.attenuation,
            )
            for s in world.radiation_sources
        ]

    def dose_rate(self, point: Vec3) -> float:
        """Microsievert per hour at ``point`` (local ENU m)."""
        total = self.background
        for (e, n, u), at_1m, mu in self._sources:
            d = max(math.dist(point, (e, n, u)), NEAR_M)
            total += at_1m * math.exp(-mu * d) / (d * d)
        return total


class RadiationSensor(Sensor[RadiationSample]):
    """Dose-rate meter on the aircraft; field (counts) of one integration period."""

    fields = ("counts",)

    def __init__(
        self, field: RadiationField, params: RadiationParams | None = None, seed: int = 0
    ) -> None:
        """Read ``field`` with ``params``' rate and sensitivity."""
        self.params = params or RadiationParams()
        self.field = field
        super().__init__("radiation", self.params.rate_hz, seed)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        mean = self.params.sensitivity * self.field.dose_rate(truth.position_enu) * self.period
        counts = float(self.rng.poisson(mean))
        # a noise-up fault widens the counting noise around the mean
        return np.array([max(0.0, mean + scale * (counts - mean))])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> RadiationSample:
        counts = round(float(value[0]))
        dose = counts / (self.params.sensitivity * self.period)
        return RadiationSample(time, dose, counts, self.period)
