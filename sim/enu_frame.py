"""Fast ECEF -> local ENU conversion about a fixed geodetic origin (called every FDM step)."""

from __future__ import annotations

import math

import pymap3d


class EnuFrame:
    """A local East-North-Up frame tangent to the WGS84 ellipsoid at a geodetic origin.

    Uses the exact rotation (same result as ``pymap3d.ecef2enu``) with precomputed sines, so one
    conversion costs a few multiplications instead of a library call.
    """

    def __init__(self, latitude_deg: float, longitude_deg: float, altitude_m: float) -> None:
        """Fix the origin (degrees, metres above the ellipsoid)."""
        self.latitude_deg = latitude_deg
        self.longitude_deg = longitude_deg
        self.altitude_m = altitude_m
        x0, y0, z0 = pymap3d.geodetic2ecef(latitude_deg, longitude_deg, altitude_m)
        self._origin = (float(x0), float(y0), float(z0))
        lat = math.radians(latitude_deg)
        lon = math.radians(longitude_deg)
        self._sl, self._cl = math.sin(lat), math.cos(lat)
        self._so, self._co = math.sin(lon), math.cos(lon)

    def from_ecef(self, x: float, y: float, z: float) -> tuple[float, float, float]:
        """ECEF metres -> (east, north, up) metres."""
        dx = x - self._origin[0]
        dy = y - self._origin[1]
        dz = z - self._origin[2]
        so, co, sl, cl = self._so, self._co, self._sl, self._cl
        east = -so * dx + co * dy
        t = co * dx + so * dy
        north = -sl * t + cl * dz
        up = cl * t + sl * dz
        return east, north, up

    def to_geodetic(self, east: float, north: float, up: float) -> tuple[float, float, float]:
        """(east, north, up) metres -> (latitude deg, longitude deg, altitude m)."""
        lat, lon, alt = pymap3d.enu2geodetic(
            east, north, up, self.latitude_deg, self.longitude_deg, self.altitude_m
        )
        return float(lat), float(lon), float(alt)
