"""Runtime constraints checked at query time (chapter section 7.1.2).

Minimum/maximum altitude (a plane test on configurations and on the sampled curve), no-fly
zones (shapely: a configuration projected on the ground plane inside the polygon within the
zone's floor..ceiling; a curve piece crossing the polygon while its height range on the
crossing overlaps floor..ceiling) and ascent/descent rate limits (the vertical speed of a piece
flown at the requested speed). No-fly polygons are grown by the safety margin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import LineString, Point
from shapely.prepared import prep

from hdrc3_base.errors import ConfigError
from hdrc3_navigation.gis import Gis, Point2, Point3, Zone


@dataclass(frozen=True, slots=True)
class Constraints:
    """Constraints of one query; ``None`` means no limit."""

    min_altitude: float | None = None
    """Lowest allowed height, m local up."""
    max_altitude: float | None = None
    """Highest allowed height, m local up."""
    max_climb_rate: float | None = None
    """Highest ascent rate at the requested speed, m/s."""
    max_descent_rate: float | None = None
    """Highest descent rate at the requested speed, m/s."""
    no_fly: tuple[tuple[Point2, ...], ...] = field(default=())
    """Extra no-fly polygons for this query (unbounded in height)."""

    def problems(self) -> list[str]:
        """Reasons why the constraints are inconsistent (empty when they are fine)."""
        out = []
        for name in ("min_altitude", "max_altitude", "max_climb_rate", "max_descent_rate"):
            value = getattr(self, name)
            if value is not None and not math.isfinite(value):
                out.append(f"{name} must be finite, got {value}")
        for name in ("max_climb_rate", "max_descent_rate"):
            value = getattr(self, name)
            if value is not None and value <= 0.0:
                out.append(f"{name} must be > 0, got {value}")
        lo, hi = self.min_altitude, self.max_altitude
        if lo is not None and hi is not None and lo > hi:
            out.append(f"min altitude {lo} m is above max altitude {hi} m")
        for i, poly in enumerate(self.no_fly):
            try:
                Zone(f"query-{i}", poly).shape()
            except ConfigError as exc:
                out.append(str(exc))
        return out


class ConstraintChecker:
    """Tests configurations and polylines against runtime constraints and the GIS's zones.

    Built once per query from the GIS state at that moment.
    """

    def __init__(self, gis: Gis, constraints: Constraints, speed: float) -> None:
        self.constraints = constraints
        self.speed = speed
        zones = list(gis.no_fly_zones)
        zones += [Zone(f"query no-fly {i}", p) for i, p in enumerate(constraints.no_fly)]
        self._zones = [
            (z.name, z.shape().buffer(gis.margin), z.floor - gis.margin, z.ceiling + gis.margin)
            for z in zones
        ]
        for _, shape, _, _ in self._zones:
            shapely.prepare(shape)
        self._prepared = [prep(shape) for _, shape, _, _ in self._zones]
        union = shapely.union_all([shape for _, shape, _, _ in self._zones])
        self._union = prep(union) if self._zones else None

    def zone_at(self, p: Point3) -> str | None:
        """Name of the (grown) no-fly zone containing ``p``, or None."""
        if self._union is None:
            return None
        pt = Point(p[0], p[1])
        if not self._union.intersects(pt):
            return None
        for (name, _, floor, ceiling), prepared in zip(self._zones, self._prepared, strict=True):
            if floor <= p[2] <= ceiling and prepared.intersects(pt):
                return name
        return None

    def altitude_problem(self, z: float) -> str | None:
        """Why a height violates the altitude limits, or None."""
        c = self.constraints
        if c.min_altitude is not None and z < c.min_altitude - 1e-6:
            return f"height {z:.1f} m is below the minimum altitude {c.min_altitude} m"
        if c.max_altitude is not None and z > c.max_altitude + 1e-6:
            return f"height {z:.1f} m is above the maximum altitude {c.max_altitude} m"
        return None

    def point_ok(self, p: Point3) -> bool:
        """Configuration test: altitude limits and no-fly zones."""
        return self.altitude_problem(p[2]) is None and self.zone_at(p) is None

    def polyline_ok(self, points: NDArray[np.float64]) -> bool:
        """Curve test on a polyline (a straight edge or a sampled cubic)."""
        z = points[:, 2]
        c = self.constraints
        if c.min_altitude is not None and float(z.min()) < c.min_altitude - 1e-6:
            return False
        if c.max_altitude is not None and float(z.max()) > c.max_altitude + 1e-6:
            return False
        if not self._rates_ok(points):
            return False
        return self._zones_ok(points)

    def points_ok(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Vectorised configuration test of (n, 3) points."""
        z = points[:, 2]
        ok = np.ones(len(points), dtype=bool)
        c = self.constraints
        if c.min_altitude is not None:
            ok &= z >= c.min_altitude - 1e-6
        if c.max_altitude is not None:
            ok &= z <= c.max_altitude + 1e-6
        for _, shape, floor, ceiling in self._zones:
            inside = shapely.intersects_xy(shape, points[:, 0], points[:, 1])
            ok &= ~(inside & (z >= floor) & (z <= ceiling))
        return ok

    def edges_ok(
        self,
        a: NDArray[np.float64],
        b: NDArray[np.float64],
        lines: NDArray[np.object_] | None = None,
        zone_cache: dict[bytes, NDArray[np.intp]] | None = None,
    ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """Vectorised curve test of the straight edges a[i]-b[i] ((m, 3) arrays).

        Returns the answers for flying a->b and b->a (rate limits depend on the direction).
        ``lines`` are the edges' ground projections if already built (the roadmap keeps them);
        ``zone_cache`` keeps, per zone, which of those lines cross its footprint (valid only
        for the same ``lines``).
        """
        ok = np.ones(len(a), dtype=bool)
        z_lo, z_hi = np.minimum(a[:, 2], b[:, 2]), np.maximum(a[:, 2], b[:, 2])
        c = self.constraints
        if c.min_altitude is not None:
            ok &= z_lo >= c.min_altitude - 1e-6
        if c.max_altitude is not None:
            ok &= z_hi <= c.max_altitude + 1e-6
        if self._zones and lines is None:
            lines = shapely.linestrings(np.stack([a[:, :2], b[:, :2]], axis=1))
        for _, shape, floor, ceiling in self._zones:
            key = shapely.to_wkb(shape) + np.array([floor, ceiling]).tobytes()
            crossing = None if zone_cache is None else zone_cache.get(key)
            if crossing is None:
                crossing = np.flatnonzero(shapely.intersects(shape, lines))
                if zone_cache is not None:
                    zone_cache[key] = crossing
            hit = crossing[ok[crossing] & (z_hi[crossing] >= floor) & (z_lo[crossing] <= ceiling)]
            inside = (z_lo[hit] >= floor) & (z_hi[hit] <= ceiling)
            ok[hit[inside]] = False  # crosses the footprint within the zone's height band
            for i in hit[~inside]:
                if _piece_enters(a[i], b[i], shape, floor, ceiling):
                    ok[i] = False
        if c.max_climb_rate is None and c.max_descent_rate is None:
            return ok, ok
        d = b - a
        vz = d[:, 2] / np.maximum(np.linalg.norm(d, axis=1), 1e-9) * self.speed
        up, down = np.ones(len(a), dtype=bool), np.ones(len(a), dtype=bool)
        if c.max_climb_rate is not None:
            up &= vz <= c.max_climb_rate + 1e-9
            down &= -vz <= c.max_climb_rate + 1e-9
        if c.max_descent_rate is not None:
            up &= -vz <= c.max_descent_rate + 1e-9
            down &= vz <= c.max_descent_rate + 1e-9
        return ok & up, ok & down

    def _rates_ok(self, points: NDArray[np.float64]) -> bool:
        c = self.constraints
        if c.max_climb_rate is None and c.max_descent_rate is None:
            return True
        d = np.diff(points, axis=0)
        length = np.linalg.norm(d, axis=1)
        ok = length > 1e-9
        vz = np.where(ok, d[:, 2] / np.where(ok, length, 1.0), 0.0) * self.speed
        if c.max_climb_rate is not None and float(vz.max()) > c.max_climb_rate + 1e-9:
            return False
        return not (c.max_descent_rate is not None and float(-vz.min()) > c.max_descent_rate + 1e-9)

    def _zones_ok(self, points: NDArray[np.float64]) -> bool:
        if self._union is None:
            return True
        line = LineString(points[:, :2]) if len(points) > 1 else Point(points[0, :2])
        if not self._union.intersects(line):
            return True
        for (_, shape, floor, ceiling), prepared in zip(self._zones, self._prepared, strict=True):
            if not prepared.intersects(line):
                continue
            for i in range(len(points) - 1):
                if _piece_enters(points[i], points[i + 1], shape, floor, ceiling):
                    return False
        return True


def _piece_enters(
    a: NDArray[np.float64], b: NDArray[np.float64], shape: object, floor: float, ceiling: float
) -> bool:
    """Whether the straight piece a-b passes through the prism shape x [floor, ceiling]."""
    horiz = float(np.hypot(b[0] - a[0], b[1] - a[1]))
    if horiz < 1e-9:
        return bool(shapely.intersects(shape, Point(a[0], a[1]))) and (
            min(a[2], b[2]) <= ceiling and max(a[2], b[2]) >= floor
        )
    crossing = shapely.intersection(shape, LineString([a[:2], b[:2]]))
    if crossing.is_empty:
        return False
    coords = np.asarray(shapely.get_coordinates(crossing))
    t = np.hypot(coords[:, 0] - a[0], coords[:, 1] - a[1]) / horiz
    z = a[2] + t * (b[2] - a[2])
    return float(z.min()) <= ceiling and float(z.max()) >= floor
