"""What the sensors add to the rendered scene: sun and exposure, sensor noise, thermal optics.

Colour: Lambert shading under a directional sun plus sky ambient, times the exposure, plus
zero-mean sensor noise (drawn per pixel in the shader from a per-frame seed), quantised to 8 bit.
Thermal: the scene's surface temperature, blurred by the optics (Gaussian point spread) and
with the detector's temporal noise (NETD), published as 16-bit centi-kelvin (value / 100 = K).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter

CENTI_KELVIN = 100.0
"""Thermal pixel value per kelvin: mono16 value = round(100 * T / K)."""


@dataclass(frozen=True, slots=True)
class ColorImaging:
    """Illumination and colour sensor settings."""

    sun_azimuth: float = math.radians(160.0)
    """Direction the sun stands in, clockwise from north, rad."""
    sun_elevation: float = math.radians(45.0)
    sun: float = 0.75
    """Direct sunlight on a surface facing the sun (relative units)."""
    ambient: float = 0.45
    """Sky light on every surface."""
    exposure: float = 1.0
    """Gain from scene radiance to pixel value (1 = albedo under full light maps to 1)."""
    noise: float = 0.012
    """Standard deviation of the sensor noise, fraction of full scale."""
    sky: tuple[float, float, float] = (0.62, 0.74, 0.90)

    def sun_direction(self) -> tuple[float, float, float]:
        """Unit ENU vector towards the sun."""
        c = math.cos(self.sun_elevation)
        return (
            c * math.sin(self.sun_azimuth),
            c * math.cos(self.sun_azimuth),
            math.sin(self.sun_elevation),
        )


@dataclass(frozen=True, slots=True)
class ThermalImaging:
    """Microbolometer settings."""

    blur_px: float = 0.6
    """Standard deviation of the optics' point spread, pixels."""
    netd: float = 0.08
    """Noise-equivalent temperature difference (detector noise std), K."""


def thermal_counts(
    kelvin: NDArray[np.float32], settings: ThermalImaging, rng: np.random.Generator
) -> NDArray[np.uint16]:
    """Blur, add detector noise and quantise a temperature image to centi-kelvin."""
    blurred = gaussian_filter(kelvin, settings.blur_px) if settings.blur_px > 0 else kelvin
    noisy = blurred + settings.netd * rng.standard_normal(kelvin.shape, dtype=np.float32)
    counts: NDArray[np.uint16] = np.clip(np.rint(noisy * CENTI_KELVIN), 0, 65535).astype(np.uint16)
    return counts
