"""Thermal counts: centi-kelvin, blur keeps the mean, detector noise of the stated NETD."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.render.imaging import CENTI_KELVIN, ColorImaging, ThermalImaging, thermal_counts


def test_counts_are_centi_kelvin() -> None:
    kelvin = np.full((20, 30), 300.0, dtype=np.float32)
    counts = thermal_counts(kelvin, ThermalImaging(blur_px=0.0, netd=0.0), np.random.default_rng(0))
    assert counts.dtype == np.uint16 and np.all(counts == 30000)
    assert counts[0, 0] / CENTI_KELVIN == 300.0


def test_noise_has_the_netd_and_blur_spreads_a_hot_spot() -> None:
    kelvin = np.full((120, 160), 290.0, dtype=np.float32)
    noisy = thermal_counts(kelvin, ThermalImaging(blur_px=0.0, netd=0.1), np.random.default_rng(1))
    assert np.std(noisy / CENTI_KELVIN) == pytest.approx(0.1, rel=0.05)
    kelvin[60, 80] = 310.0
    blurred = thermal_counts(
        kelvin, ThermalImaging(blur_px=0.6, netd=0.0), np.random.default_rng(1)
    )
    assert 290.0 < blurred[60, 80] / CENTI_KELVIN < 310.0
    assert blurred[60, 81] / CENTI_KELVIN > 290.5
    assert blurred.sum() / CENTI_KELVIN == pytest.approx(kelvin.sum(), abs=2.0)


def test_sun_direction_is_a_unit_vector_towards_the_sun() -> None:
    sun = ColorImaging(sun_azimuth=math.radians(180.0), sun_elevation=math.radians(30.0))
    east, north, up = sun.sun_direction()
    assert math.hypot(east, north, up) == pytest.approx(1.0)
    assert north < 0.0 and up == pytest.approx(0.5) and abs(east) < 1e-12
