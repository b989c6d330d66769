"""Conversions between a world's local ENU frame and WGS84 (via pymap3d).

Inside the simulator and planner everything is local East/North/Up metres relative to the world's
geodetic origin; only the edges (GPS samples, FCL/PPCL) speak latitude/longitude in degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pymap3d


@dataclass(frozen=True, slots=True)
class GeodeticOrigin:
    """Geodetic origin of a local ENU frame."""

    latitude: float
    """Degrees north, WGS84."""
    longitude: float
    """Degrees east, WGS84."""
    altitude: float
    """Metres above the WGS84 ellipsoid."""

    def __post_init__(self) -> None:
        """Reject origins that are not a point on (or near) the Earth."""
        values = (self.latitude, self.longitude, self.altitude)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"geodetic origin must be finite, got {values}")
        if not -90.0 <= self.latitude <= 90.0:
            raise ValueError(f"latitude {self.latitude} outside [-90, 90]")
        if not -180.0 <= self.longitude <= 180.0:
            raise ValueError(f"longitude {self.longitude} outside [-180, 180]")
        if not -500.0 <= self.altitude <= 9000.0:
            raise ValueError(f"altitude {self.altitude} outside [-500, 9000] m")


@dataclass(frozen=True, slots=True)
class GeodeticPoint:
    """A WGS84 point: degrees and metres above the ellipsoid."""

    latitude: float
    longitude: float
    altitude: float


def enu_to_geodetic(origin: GeodeticOrigin, east: float, north: float, up: float) -> GeodeticPoint:
    """Convert local ENU metres to WGS84."""
    lat, lon, alt = pymap3d.enu2geodetic(
        east, north, up, origin.latitude, origin.longitude, origin.altitude
    )
    return GeodeticPoint(float(lat), float(lon), float(alt))


def geodetic_to_enu(
    origin: GeodeticOrigin, latitude: float, longitude: float, altitude: float
) -> tuple[float, float, float]:
    """Convert WGS84 to local ENU metres (east, north, up)."""
    e, n, u = pymap3d.geodetic2enu(
        latitude, longitude, altitude, origin.latitude, origin.longitude, origin.altitude
    )
    return float(e), float(n), float(u)


_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_WGS84_E2 = _WGS84_F * (2.0 - _WGS84_F)


class LocalFrame:
    """Fast ENU <-> WGS84/ECEF for one origin, called per GPS fix and per flight-model step.

    pymap3d costs ~0.3 ms a call. ENU <-> ECEF is a fixed rotation with precomputed sines
    (exact, the same result as pymap3d); ECEF -> geodetic iterates the latitude, which converges
    to well below a millimetre in three steps near the Earth's surface.
    """

    def __init__(self, origin: GeodeticOrigin) -> None:
        """Precompute the origin's ECEF position and rotation."""
        self.origin = origin
        lat, lon = math.radians(origin.latitude), math.radians(origin.longitude)
        self._sl, self._cl = math.sin(lat), math.cos(lat)
        self._so, self._co = math.sin(lon), math.cos(lon)
        n = _WGS84_A / math.sqrt(1.0 - _WGS84_E2 * self._sl**2)
        h = origin.altitude
        self._x0 = (n + h) * self._cl * self._co
        self._y0 = (n + h) * self._cl * self._so
        self._z0 = (n * (1.0 - _WGS84_E2) + h) * self._sl

    def from_ecef(self, x: float, y: float, z: float) -> tuple[float, float, float]:
        """ECEF metres -> (east, north, up) metres."""
        dx = x - self._x0
        dy = y - self._y0
        dz = z - self._z0
        so, co, sl, cl = self._so, self._co, self._sl, self._cl
        east = -so * dx + co * dy
        t = co * dx + so * dy
        north = -sl * t + cl * dz
        up = cl * t + sl * dz
        return east, north, up

    def to_geodetic(self, east: float, north: float, up: float) -> GeodeticPoint:
        """Convert local ENU metres to WGS84."""
        so, co, sl, cl = self._so, self._co, self._sl, self._cl
        t = -sl * north + cl * up
        x = self._x0 - so * east + co * t
        y = self._y0 + co * east + so * t
        z = self._z0 + cl * north + sl * up
        p = math.hypot(x, y)
        lat = math.atan2(z, p * (1.0 - _WGS84_E2))
        for _ in range(4):
            s = math.sin(lat)
            n = _WGS84_A / math.sqrt(1.0 - _WGS84_E2 * s * s)
            alt = p / math.cos(lat) - n
            lat = math.atan2(z, p * (1.0 - _WGS84_E2 * n / (n + alt)))
        s = math.sin(lat)
        n = _WGS84_A / math.sqrt(1.0 - _WGS84_E2 * s * s)
        alt = p / math.cos(lat) - n
        return GeodeticPoint(math.degrees(lat), math.degrees(math.atan2(y, x)), alt)
