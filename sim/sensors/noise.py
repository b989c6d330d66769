"""Random error processes used by the sensor models: Gauss-Markov and random walk."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray


class GaussMarkov:
    """First-order Gauss-Markov process: stationary std ``sigma``, correlation time ``tau``.

    Exact discretisation x' = a*x + sigma*sqrt(1-a^2)*w with a = exp(-dt/tau), so the variance
    stays ``sigma**2`` for any step; it starts from its stationary distribution.
    """

    def __init__(self, sigma: float, tau: float, dim: int = 1) -> None:
        if sigma < 0.0 or tau <= 0.0:
            raise ValueError(f"need sigma >= 0 and tau > 0, got {sigma}, {tau}")
        self.sigma = sigma
        self.tau = tau
        self.value: NDArray[np.float64] = np.zeros(dim)

    def reset(self, rng: np.random.Generator) -> None:
        """Draw a fresh state from the stationary distribution."""
        self.value = self.sigma * rng.standard_normal(self.value.size)

    def step(self, dt: float, rng: np.random.Generator) -> NDArray[np.float64]:
        """Advance by ``dt`` seconds and return the new value."""
        a = math.exp(-max(dt, 0.0) / self.tau)
        noise = rng.standard_normal(self.value.size)
        self.value = a * self.value + self.sigma * math.sqrt(1.0 - a * a) * noise
        return self.value


class RandomWalk:
    """Random walk (integrated white noise) with initial std ``initial`` and density ``density``.

    ``density`` is in units/sqrt(s): after t seconds the walk has spread by density*sqrt(t).
    """

    def __init__(self, initial: float, density: float, dim: int = 1) -> None:
        if initial < 0.0 or density < 0.0:
            raise ValueError(f"need initial >= 0 and density >= 0, got {initial}, {density}")
        self.initial = initial
        self.density = density
        self.value: NDArray[np.float64] = np.zeros(dim)

    def reset(self, rng: np.random.Generator) -> None:
        """Draw a fresh initial value (turn-on bias)."""
        self.value = self.initial * rng.standard_normal(self.value.size)

    def step(self, dt: float, rng: np.random.Generator) -> NDArray[np.float64]:
        """Advance by ``dt`` seconds and return the new value."""
        spread = self.density * math.sqrt(max(dt, 0.0))
        self.value = self.value + spread * rng.standard_normal(self.value.size)
        return self.value
