"""Geometry queries against a world: containment, segment clearance and 2.5D ray casting.

Buildings and vegetation are vertical prisms (footprint extruded between base and top); the
terrain is the bilinear height field. Used by the simulator (laser range finder, ground contact
of objects) and later by the GIS / path planner.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely import STRtree
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from sim.world import World

Vec3 = tuple[float, float, float]


class HitKind(enum.Enum):
    """What a ray hit."""

    TERRAIN = "terrain"
    BUILDING = "building"
    VEGETATION = "vegetation"


@dataclass(frozen=True, slots=True)
class RayHit:
    """First intersection of a ray with the world."""

    distance: float
    """Metres along the ray from its origin."""
    point: Vec3
    """Hit point, local ENU."""
    kind: HitKind
    name: str
    """Name of the building or vegetation area; ``"terrain"`` for the ground."""


@dataclass(frozen=True, slots=True)
class _Prism:
    name: str
    kind: HitKind
    polygon: Polygon
    base: float
    top: float


class WorldGeometry:
    """Spatial index over one world's static geometry."""

    def __init__(self, world: World, terrain_step: float = 1.0) -> None:
        """Index ``world``; ``terrain_step`` (m) is the ray-march step against the terrain."""
        self.world = world
        self.terrain_step = terrain_step
        prisms = [
            _Prism(b.name, HitKind.BUILDING, Polygon(b.footprint), b.base, b.top)
            for b in world.buildings
        ]
        for v in world.vegetation:
            base, top = world.vegetation_top(v)
            prisms.append(_Prism(v.name, HitKind.VEGETATION, Polygon(v.polygon), base, top))
        self._prisms = tuple(prisms)
        self._tree = STRtree([p.polygon for p in prisms])

    def ground_height(self, east: float, north: float) -> float:
        """Height of the terrain at a point, m (local up)."""
        return self.world.terrain.height(east, north)

    def point_in_building(self, east: float, north: float, up: float | None = None) -> str | None:
        """Name of the building containing the point (any height if ``up`` is None), else None."""
        point = Point(east, north)
        for index in self._tree.query(point):
            prism = self._prisms[int(index)]
            if prism.kind is not HitKind.BUILDING or not prism.polygon.covers(point):
                continue
            if up is None or prism.base <= up <= prism.top:
                return prism.name
        return None

    def segment_intersects_building(self, start: Vec3, end: Vec3) -> str | None:
        """Name of the first building the straight segment start->end passes through, else None."""
        direction = (end[0] - start[0], end[1] - start[1], end[2] - start[2])
        hit = self._prism_hit(start, direction, 1.0, {HitKind.BUILDING})
        return None if hit is None else hit[1].name

    def ray_cast(self, origin: Vec3, direction: Vec3, max_range: float) -> RayHit | None:
        """First hit of a ray (terrain, building or vegetation) within ``max_range`` metres."""
        norm = math.sqrt(sum(c * c for c in direction))
        if not (norm > 0.0 and math.isfinite(norm) and max_range > 0.0):
            raise ValueError(f"ray direction must be non-zero and range > 0, got {direction}")
        unit = (direction[0] / norm, direction[1] / norm, direction[2] / norm)
        best: RayHit | None = None
        found = self._prism_hit(origin, unit, max_range, {HitKind.BUILDING, HitKind.VEGETATION})
        if found is not None:
            t, prism = found
            best = RayHit(t, _at(origin, unit, t), prism.kind, prism.name)
        limit = best.distance if best is not None else max_range
        t_ground = self._terrain_hit(origin, unit, limit)
        if t_ground is not None:
            best = RayHit(t_ground, _at(origin, unit, t_ground), HitKind.TERRAIN, "terrain")
        return best

    def ray_cast_many(
        self, origin: Vec3, directions: NDArray[np.float64], max_range: float
    ) -> NDArray[np.float64]:
        """Distances to the first hit of many rays from one origin (inf: nothing within range).

        Vectorised over rays (a laser scan line); ``directions`` is (N, 3) and need not be unit.
        Same result as calling :meth:`ray_cast` per ray.
        """
        d = np.asarray(directions, dtype=np.float64)
        norms = np.linalg.norm(d, axis=1)
        if d.ndim != 2 or d.shape[1] != 3 or not np.all(norms > 0.0) or not max_range > 0.0:
            raise ValueError("directions must be (N, 3) non-zero vectors and range > 0")
        d = d / norms[:, None]
        o = np.asarray(origin, dtype=np.float64)
        best = np.full(len(d), np.inf)
        for prism in self._prisms:
            best = np.minimum(best, _prism_distances(prism, o, d))
        best[best > max_range] = np.inf
        limit = np.minimum(best, max_range)
        ground = self._terrain_distances(o, d, limit)
        result: NDArray[np.float64] = np.minimum(best, ground)
        return result

    def _terrain_distances(
        self, o: NDArray[np.float64], d: NDArray[np.float64], limit: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Vectorised :meth:`_terrain_hit`: march each ray to its own limit, then bisect."""
        terrain = self.world.terrain
        steps = max(2, math.ceil(float(np.max(limit)) / self.terrain_step) + 1)
        t = np.linspace(0.0, 1.0, steps)[None, :] * limit[:, None]
        pts = o[None, None, :] + t[:, :, None] * d[:, None, :]
        gap = pts[..., 2] - terrain.heights_at(pts[..., 0], pts[..., 1])
        below = gap <= 0.0
        hit = below.any(axis=1)
        k = np.argmax(below, axis=1)
        rows = np.arange(len(d))
        hi = t[rows, k]
        lo = t[rows, np.maximum(k - 1, 0)]
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            p = o[None, :] + mid[:, None] * d
            under = p[:, 2] - terrain.heights_at(p[:, 0], p[:, 1]) <= 0.0
            hi = np.where(under, mid, hi)
            lo = np.where(under, lo, mid)
        result: NDArray[np.float64] = np.where(hit, np.where(k == 0, 0.0, hi), np.inf)
        return result

    def _prism_hit(
        self, origin: Vec3, direction: Vec3, t_max: float, kinds: set[HitKind]
    ) -> tuple[float, _Prism] | None:
        """Smallest t in [0, t_max] where origin + t*direction is inside a prism."""
        end = _at(origin, direction, t_max)
        d2 = direction[0] ** 2 + direction[1] ** 2
        path: BaseGeometry = (
            LineString([origin[:2], end[:2]]) if d2 * t_max * t_max > 1e-18 else Point(origin[:2])
        )
        best: tuple[float, _Prism] | None = None
        for index in self._tree.query(path):
            prism = self._prisms[int(index)]
            if prism.kind not in kinds:
                continue
            z_lo, z_hi = _slab(origin[2], direction[2], prism.base, prism.top, t_max)
            if z_lo > z_hi:
                continue
            for lo, hi in _inside_intervals(path, prism.polygon, origin, direction, d2, t_max):
                t = max(lo, z_lo)
                if t <= min(hi, z_hi) and (best is None or t < best[0]):
                    best = (t, prism)
        return best

    def _terrain_hit(self, origin: Vec3, unit: Vec3, t_max: float) -> float | None:
        """First t in [0, t_max] where the ray is at or below the terrain (march + bisection)."""
        steps = max(2, math.ceil(t_max / self.terrain_step) + 1)
        t = np.linspace(0.0, t_max, steps)
        east = origin[0] + unit[0] * t
        north = origin[1] + unit[1] * t
        gap = origin[2] + unit[2] * t - self.world.terrain.heights_at(east, north)
        below = np.nonzero(gap <= 0.0)[0]
        if below.size == 0:
            return None
        k = int(below[0])
        if k == 0:
            return 0.0
        lo, hi = float(t[k - 1]), float(t[k])
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            point = _at(origin, unit, mid)
            if point[2] - self.world.terrain.height(point[0], point[1]) <= 0.0:
                hi = mid
            else:
                lo = mid
        return hi


def _at(origin: Vec3, direction: Vec3, t: float) -> Vec3:
    return (
        origin[0] + t * direction[0],
        origin[1] + t * direction[1],
        origin[2] + t * direction[2],
    )


def _slab(z0: float, dz: float, lo: float, hi: float, t_max: float) -> tuple[float, float]:
    """Interval of t in [0, t_max] where z0 + t*dz lies in [lo, hi] (empty: lo > hi)."""
    if abs(dz) < 1e-12:
        return (0.0, t_max) if lo <= z0 <= hi else (1.0, 0.0)
    a, b = (lo - z0) / dz, (hi - z0) / dz
    return max(0.0, min(a, b)), min(t_max, max(a, b))


def _inside_intervals(
    path: BaseGeometry, polygon: Polygon, origin: Vec3, direction: Vec3, d2: float, t_max: float
) -> list[tuple[float, float]]:
    """Intervals of t where the ray's ground projection lies inside ``polygon``."""
    if isinstance(path, Point):
        return [(0.0, t_max)] if polygon.covers(path) else []
    inside = path.intersection(polygon)
    intervals: list[tuple[float, float]] = []
    for part in getattr(inside, "geoms", [inside]):
        if part.is_empty:
            continue
        ts = [
            ((x - origin[0]) * direction[0] + (y - origin[1]) * direction[1]) / d2
            for x, y in part.coords
        ]
        intervals.append((min(ts), max(ts)))
    return intervals


def _prism_distances(
    prism: _Prism, o: NDArray[np.float64], d: NDArray[np.float64]
) -> NDArray[np.float64]:
    """First t >= 0 where each ray (unit directions ``d``) is inside a vertical prism, else inf.

    Candidates: the origin itself, wall crossings within the prism's height, and roof/floor
    crossings inside the footprint.
    """
    if prism.base <= o[2] <= prism.top and shapely.intersects_xy(prism.polygon, o[0], o[1]):
        return np.zeros(len(d))
    ring = np.asarray(prism.polygon.exterior.coords)
    a, b = ring[:-1], ring[1:]
    e = b - a  # (E, 2)
    ao = a - o[:2]  # (E, 2)
    dx, dy = d[:, 0:1], d[:, 1:2]  # (N, 1)
    denom = dx * e[None, :, 1] - dy * e[None, :, 0]  # d x e, (N, E)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (ao[None, :, 0] * e[None, :, 1] - ao[None, :, 1] * e[None, :, 0]) / denom
        s = (ao[None, :, 0] * dy - ao[None, :, 1] * dx) / denom
        z = o[2] + t * d[:, 2:3]
    wall = (
        (np.abs(denom) > 1e-12)
        & (t >= 0.0)
        & (s >= 0.0)
        & (s <= 1.0)
        & (z >= prism.base)
        & (z <= prism.top)
    )
    best = np.min(np.where(wall, t, np.inf), axis=1)
    dz = d[:, 2]
    for level in (prism.top, prism.base):
        with np.errstate(divide="ignore", invalid="ignore"):
            tl = (level - o[2]) / dz
        ok = np.isfinite(tl) & (tl >= 0.0) & (tl < best)
        if np.any(ok):
            x = o[0] + tl[ok] * d[ok, 0]
            y = o[1] + tl[ok] * d[ok, 1]
            covered = shapely.intersects_xy(prism.polygon, x, y)
            idx = np.flatnonzero(ok)[covered]
            best[idx] = tl[idx]
    result: NDArray[np.float64] = best
    return result
