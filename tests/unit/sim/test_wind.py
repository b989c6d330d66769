import math

import numpy as np
import pytest

from hdrc3_base.errors import ConfigError
from sim.wind import Wind, WindSettings


def _series(seed: int, settings: WindSettings, steps: int = 3000) -> np.ndarray:
    wind = Wind(seed, settings)
    return np.array([wind.step(0.02) for _ in range(steps)])


def test_calm_air_has_no_gusts() -> None:
    assert not _series(1, WindSettings((3.0, 0.0, 0.0), 0.0)).any()


def test_same_seed_same_gusts_other_seed_other_gusts() -> None:
    settings = WindSettings((5.0, 0.0, 0.0), 2.0)
    a, b, c = _series(7, settings), _series(7, settings), _series(8, settings)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_gust_statistics_match_the_intensity() -> None:
    gusts = _series(3, WindSettings((8.0, 0.0, 0.0), 2.0), steps=20000)
    std = gusts.std(axis=0)
    assert std[0] == pytest.approx(2.0, rel=0.25)
    assert std[1] == pytest.approx(2.0, rel=0.25)
    assert std[2] == pytest.approx(1.0, rel=0.25)
    # correlated: neighbouring samples (20 ms apart, tau = 30 m / 8 m/s) are nearly equal
    lag1 = np.corrcoef(gusts[:-1, 0], gusts[1:, 0])[0, 1]
    assert lag1 > 0.98


def test_mean_is_reported_and_changeable_at_run_time() -> None:
    wind = Wind(0)
    assert wind.mean == (0.0, 0.0, 0.0)
    wind.set(WindSettings((1.0, 2.0, 0.0), 0.5))
    assert wind.mean == (1.0, 2.0, 0.0)
    wind.step(0.02)
    assert wind.gust != (0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        (WindSettings((math.nan, 0.0, 0.0), 0.0), "finite"),
        (WindSettings((0.0, 0.0, 0.0), math.inf), "finite"),
        (WindSettings((50.0, 0.0, 0.0), 0.0), "exceeds"),
        (WindSettings((0.0, 0.0, 0.0), -1.0), "gust intensity"),
    ],
)
def test_impossible_settings_are_rejected(settings: WindSettings, message: str) -> None:
    assert message in (settings.problem() or "")
    with pytest.raises(ConfigError, match=message):
        Wind(0).set(settings)
