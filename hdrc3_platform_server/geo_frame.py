"""WGS84 <-> local ENU of the world's geodetic origin, and the world's extent (chapter 6.2).

FCL/PPCL speak WGS84 (longitude, latitude in degrees, altitude in metres above the ellipsoid);
the PFC and PPC work in the local East/North/Up frame. The origin and extent come from a
parameter or from the world file (the world file is data; :func:`frame_from_world` reads it with
the simulator's loader, nothing else of the simulator is used).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import pymap3d

from hdrc3_base.errors import ConfigError

GroundFn = Callable[[float, float], float]
"""Terrain height (m, ENU up) at (east, north)."""


class Geodetic(Protocol):
    """A WGS84 position (``HelicopterState`` has these fields)."""

    longitude: float
    latitude: float
    altitude: float


def _flat(east: float, north: float) -> float:
    return 0.0


@dataclass(frozen=True)
class WorldFrame:
    """Geodetic origin, horizontal extent (ENU metres) and terrain of one world."""

    latitude: float
    longitude: float
    altitude: float
    bounds: tuple[float, float, float, float] = (-5000.0, -5000.0, 5000.0, 5000.0)
    """(east_min, north_min, east_max, north_max), m."""
    margin: float = 1000.0
    """How far outside ``bounds`` a position may still be (m) before it counts as far away."""
    ground: GroundFn = _flat

    def __post_init__(self) -> None:
        """Reject origins that are not on the Earth."""
        values = (self.latitude, self.longitude, self.altitude, *self.bounds, self.margin)
        if not all(math.isfinite(v) for v in values):
            raise ConfigError(f"world frame values must be finite, got {values}")
        if not (-90.0 <= self.latitude <= 90.0 and -180.0 <= self.longitude <= 180.0):
            raise ConfigError(f"origin {self.latitude}, {self.longitude} is not on the Earth")
        if not (self.bounds[0] < self.bounds[2] and self.bounds[1] < self.bounds[3]):
            raise ConfigError(f"bounds {self.bounds} must satisfy min < max")

    def to_enu(self, longitude: float, latitude: float, altitude: float) -> tuple[float, ...]:
        """(east, north, up) in metres of a WGS84 position."""
        e, n, u = pymap3d.geodetic2enu(
            latitude, longitude, altitude, self.latitude, self.longitude, self.altitude
        )
        return (float(e), float(n), float(u))

    def state_enu(self, state: Geodetic) -> tuple[float, float, float] | None:
        """(east, north, up) of a WGS84 position, e.g. a Data Interface state (None: not finite)."""
        values = (state.longitude, state.latitude, state.altitude)
        if not all(math.isfinite(v) for v in values):
            return None
        e, n, u = self.to_enu(*values)
        return (e, n, u)

    def to_wgs84(self, east: float, north: float, up: float) -> tuple[float, float, float]:
        """(longitude, latitude, altitude) of an ENU position."""
        lat, lon, alt = pymap3d.enu2geodetic(
            east, north, up, self.latitude, self.longitude, self.altitude
        )
        return (float(lon), float(lat), float(alt))

    def inside(self, east: float, north: float) -> bool:
        """True if (east, north) is within the world's extent plus the margin."""
        e0, n0, e1, n1 = self.bounds
        m = self.margin
        return e0 - m <= east <= e1 + m and n0 - m <= north <= n1 + m

    def ground_up(self, east: float, north: float) -> float:
        """Terrain height (ENU up, m) at a position; outside the grid the edge value."""
        return float(self.ground(east, north))


def frame_from_world(name_or_path: str, margin: float = 1000.0) -> WorldFrame:
    """Read a world file's origin, extent and terrain (raises ConfigError if it cannot)."""
    from sim.world_loader import load_world  # the world file is data; only its reader is used

    try:
        world = load_world(name_or_path)
    except Exception as exc:  # any loader failure is a configuration problem here
        raise ConfigError(f"cannot load world {name_or_path!r}: {exc}") from exc
    o = world.origin
    terrain = world.terrain
    return WorldFrame(
        o.latitude,
        o.longitude,
        o.altitude,
        world.bounds,
        margin,
        lambda e, n: float(terrain.height(e, n)),
    )
