"""Error processes: Gauss-Markov stationarity and correlation, random-walk spread."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.sensors.noise import GaussMarkov, RandomWalk


def test_gauss_markov_is_stationary_with_its_correlation_time() -> None:
    rng = np.random.default_rng(11)
    process = GaussMarkov(sigma=2.0, tau=10.0, dim=1)
    process.reset(rng)
    dt = 1.0
    series = np.array([process.step(dt, rng)[0] for _ in range(50_000)])
    assert np.std(series) == pytest.approx(2.0, rel=0.1)
    lag = round(10.0 / dt)
    correlation = np.corrcoef(series[:-lag], series[lag:])[0, 1]
    assert correlation == pytest.approx(math.exp(-1.0), abs=0.05)


def test_random_walk_spreads_with_sqrt_time() -> None:
    rng = np.random.default_rng(12)
    walk = RandomWalk(initial=0.0, density=0.5, dim=2000)
    walk.reset(rng)
    for _ in range(100):
        walk.step(1.0, rng)
    assert np.std(walk.value) == pytest.approx(0.5 * math.sqrt(100.0), rel=0.05)


@pytest.mark.parametrize("args", [(-1.0, 1.0), (1.0, 0.0)])
def test_gauss_markov_rejects_bad_parameters(args: tuple[float, float]) -> None:
    with pytest.raises(ValueError):
        GaussMarkov(*args)
