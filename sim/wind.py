"""Wind over the simulated world: a mean air-mass velocity plus seeded turbulence (gusts).

The gusts are first-order Gauss-Markov processes per ENU axis (the low-order core of the Dryden
model): horizontal standard deviation ``gust_intensity``, vertical half of it, correlation time
``length / airspeed scale`` with a turbulence length of 30 m (low-altitude Dryden scale lengths
are of that order at 10-30 m height). One field is shared by every aircraft of a world (the
aircraft fly within a few hundred metres of each other; spatial variation is not modelled).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hdrc3_base.errors import ConfigError

MAX_MEAN_WIND = 40.0
"""m/s: stronger mean wind is rejected (far beyond what the RMAX flies in)."""
MAX_GUST_INTENSITY = 15.0
"""m/s: stronger gust intensity is rejected."""


@dataclass(frozen=True, slots=True)
class WindSettings:
    """What a user sets: mean wind and gust intensity."""

    mean_enu: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Air-mass velocity (where the wind blows to), m/s, ENU."""
    gust_intensity: float = 0.0
    """Standard deviation of each horizontal gust component, m/s (vertical: half of it)."""

    def problem(self) -> str | None:
        """Why these settings are impossible, or None."""
        values = (*self.mean_enu, self.gust_intensity)
        if not all(math.isfinite(v) for v in values):
            return f"wind must be finite, got mean {self.mean_enu} gust {self.gust_intensity}"
        speed = math.sqrt(sum(v * v for v in self.mean_enu))
        if speed > MAX_MEAN_WIND:
            return f"mean wind {speed:.1f} m/s exceeds {MAX_MEAN_WIND} m/s"
        if not 0.0 <= self.gust_intensity <= MAX_GUST_INTENSITY:
            return f"gust intensity {self.gust_intensity} outside [0, {MAX_GUST_INTENSITY}] m/s"
        return None


class Wind:
    """Mean wind plus gusts, advanced with :meth:`step` (deterministic for a seed)."""

    def __init__(
        self, seed: int, settings: WindSettings | None = None, length: float = 30.0
    ) -> None:
        """Start calm (or with ``settings``); ``length`` is the turbulence scale length, m."""
        if not (math.isfinite(length) and length > 0.0):
            raise ConfigError(f"turbulence length must be > 0 m, got {length}")
        self._length = length
        self.settings = WindSettings()
        self.reset(seed)
        if settings is not None:
            self.set(settings)

    def reset(self, seed: int) -> None:
        """Restart the gust stream from ``seed`` with zero gusts."""
        self._rng = np.random.default_rng(seed)
        self._gust = np.zeros(3)

    def set(self, settings: WindSettings) -> None:
        """Change mean and gust intensity from now on (ConfigError if impossible)."""
        problem = settings.problem()
        if problem is not None:
            raise ConfigError(problem)
        self.settings = settings

    @property
    def mean(self) -> tuple[float, float, float]:
        """Mean air-mass velocity, m/s, ENU."""
        return self.settings.mean_enu

    @property
    def gust(self) -> tuple[float, float, float]:
        """Current gust component, m/s, ENU."""
        g = self._gust
        return float(g[0]), float(g[1]), float(g[2])

    def step(self, dt: float) -> tuple[float, float, float]:
        """Advance the gusts by ``dt`` seconds and return the gust component, m/s ENU."""
        sigma = self.settings.gust_intensity
        # The stream is drawn even in calm air so that a later gust setting does not shift it.
        noise = self._rng.standard_normal(3)
        if sigma == 0.0:
            self._gust[:] = 0.0
            return 0.0, 0.0, 0.0
        mean = self.settings.mean_enu
        airspeed = max(2.0, math.hypot(mean[0], mean[1]))
        a = math.exp(-dt * airspeed / self._length)
        scale = sigma * math.sqrt(1.0 - a * a)
        sigmas = np.array([1.0, 1.0, 0.5])
        self._gust = a * self._gust + scale * sigmas * noise
        return self.gust
