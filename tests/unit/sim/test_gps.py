"""GPS: error statistics over a long deterministic run, outages, WGS84 consistency."""

from __future__ import annotations

import numpy as np
import pytest

from sim.geodesy import GeodeticOrigin, geodetic_to_enu
from sim.sensors.fake_truth import make_truth
from sim.sensors.gps import Gps, GpsParams, GpsSample

ORIGIN = GeodeticOrigin(55.70, 13.47, 95.0)
POSITION = (120.0, -40.0, 30.0)
VELOCITY = (3.0, -1.0, 0.5)


def fixes(gps: Gps, seconds: float) -> list[GpsSample | None]:
    steps = round(seconds * gps.rate_hz)
    return [
        gps.update(make_truth(k / gps.rate_hz, position_enu=POSITION, velocity_enu=VELOCITY))
        for k in range(steps)
    ]


def test_error_statistics_over_ten_minutes() -> None:
    params = GpsParams(outage_rate=0.0)
    samples = [s for s in fixes(Gps(ORIGIN, params, seed=21), 600.0) if s is not None]
    assert len(samples) == 6000
    error = np.array([s.position_enu for s in samples]) - POSITION
    # Correlated errors over ~5 correlation times: loose bounds around the 1.5 / 3 m sigmas.
    horizontal_rms = np.sqrt(np.mean(error[:, :2] ** 2, axis=0))
    assert np.all((horizontal_rms > 0.5) & (horizontal_rms < 3.0))
    assert 1.0 < np.sqrt(np.mean(error[:, 2] ** 2)) < 6.0
    jitter = np.std(np.diff(error, axis=0), axis=0) / np.sqrt(2.0)
    assert np.all(np.abs(jitter - 0.3) < 0.05)  # white part, 0.3 m
    v_error = np.array([s.velocity_enu for s in samples]) - VELOCITY
    assert np.std(v_error, axis=0) == pytest.approx([0.1, 0.1, 0.1], rel=0.1)


def test_geodetic_fix_matches_enu_fix() -> None:
    sample = next(s for s in fixes(Gps(ORIGIN, seed=2), 1.0) if s is not None)
    back = geodetic_to_enu(ORIGIN, sample.latitude, sample.longitude, sample.altitude)
    assert back == pytest.approx(sample.position_enu, abs=1e-6)


def test_outages_remove_about_the_expected_fraction() -> None:
    params = GpsParams(outage_rate=0.1, outage_mean_duration=1.0)
    samples = fixes(Gps(ORIGIN, params, seed=5), 400.0)
    missing = sum(s is None for s in samples) / len(samples)
    # Expected unavailability ~ rate*duration/(1 + rate*duration) = 0.09.
    assert 0.04 < missing < 0.16
    # Outages come in runs (several consecutive missing fixes), not as isolated drops.
    gaps = np.diff(np.flatnonzero([s is None for s in samples]))
    assert np.mean(gaps == 1) > 0.7
