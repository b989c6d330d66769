"""Surface materials: colour albedo and thermal behaviour of every surface the renderer draws.

The thermal camera sees surface temperature. Each material carries a temperature offset from the
ambient air (sun-heated roofs and asphalt are warmer, vegetation cooler), or an absolute one for
bodies whose temperature the world file gives (persons, dummies, animals, cars).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

ZERO_CELSIUS = 273.15


@dataclass(frozen=True, slots=True)
class ThermalEnvironment:
    """Temperatures of the scene's surroundings, K."""

    ambient: float = ZERO_CELSIUS + 15.0
    """Air temperature; background materials are offsets from it."""
    sky: float = ZERO_CELSIUS - 20.0
    """Apparent temperature of the clear sky (what the camera sees above the horizon)."""


@dataclass(frozen=True, slots=True)
class Surface:
    """Albedo (linear RGB in [0, 1]) and ambient-relative temperature offset, K."""

    albedo: tuple[float, float, float]
    warmth: float


class Material(enum.Enum):
    """Background materials of the static scene."""

    GRASS = Surface((0.26, 0.42, 0.16), -1.5)
    FIELD = Surface((0.50, 0.44, 0.26), 1.0)
    ASPHALT = Surface((0.22, 0.22, 0.23), 8.0)
    """Roads: dark, sun-heated."""
    WALL = Surface((0.62, 0.56, 0.50), 2.0)
    ROOF = Surface((0.52, 0.20, 0.16), 16.0)
    """Sun-heated roofs: a thermal distractor the size of a building."""
    TRUNK = Surface((0.30, 0.22, 0.14), -1.0)
    CROWN = Surface((0.14, 0.30, 0.10), -3.0)
    PAD = Surface((0.70, 0.70, 0.68), 4.0)
    PATTERN_WHITE = Surface((0.85, 0.85, 0.84), 2.0)
    """The landing pattern's plate (sim.landing_pattern)."""
    PATTERN_BLACK = Surface((0.03, 0.03, 0.03), 9.0)

    @property
    def surface(self) -> Surface:
        """The material's albedo and thermal offset."""
        value: Surface = self.value
        return value
