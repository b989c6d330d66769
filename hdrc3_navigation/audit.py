"""Independent geometric audit of planned segments and flown tracks against a world file.

Deliberately shares nothing with the planner's checker (no FCL, no constraint checker): each
position is compared with the world's building and vegetation footprints (shapely distances),
their roof heights, the terrain height and the no-fly zones' polygons and height bands. Used by
tests to check every planned segment and every flown track.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

from hdrc3_control.path_segment import PathSegment
from sim.world import World


@dataclass(frozen=True, slots=True)
class Violation:
    """One position that breaks the clearance or enters a no-fly zone."""

    position: tuple[float, float, float]
    what: str
    clearance: float
    """Distance to the offending solid, m (0 inside a no-fly zone)."""


class WorldAudit:
    """Clearance and no-fly checks of positions in one world."""

    def __init__(
        self,
        world: World,
        zones: Iterable[tuple[str, Sequence[tuple[float, float]], float, float]] = (),
    ):
        self.world = world
        solids: list[tuple[str, Polygon, float]] = []
        for b in world.buildings:
            solids.append((f"building {b.name}", Polygon(b.footprint), b.top))
        for v in world.vegetation:
            poly = Polygon(v.polygon)
            xy = np.asarray(poly.exterior.coords)
            ground = float(world.terrain.heights_at(xy[:, 0], xy[:, 1]).max())
            solids.append((f"vegetation {v.name}", poly, ground + v.height))
        self._solids = solids
        self._zones = [(z.name, Polygon(z.polygon), z.floor, z.ceiling) for z in world.no_fly_zones]
        self._zones += [(name, Polygon(p), lo, hi) for name, p, lo, hi in zones]

    def check_points(self, points: NDArray[np.float64], clearance: float) -> list[Violation]:
        """Violations of (n, 3) positions: closer than ``clearance`` or inside a zone."""
        out: list[Violation] = []
        x, y, z = points[:, 0], points[:, 1], points[:, 2]
        ground = self.world.terrain.heights_at(x, y)
        for i in np.flatnonzero(z - ground < clearance):
            out.append(Violation(_p(points[i]), "terrain", float(z[i] - ground[i])))
        pts = shapely.points(x, y)
        for name, poly, top in self._solids:
            horizontal = shapely.distance(poly, pts)
            vertical = np.maximum(0.0, z - top)
            dist = np.hypot(horizontal, vertical)
            for i in np.flatnonzero(dist < clearance):
                out.append(Violation(_p(points[i]), name, float(dist[i])))
        for name, poly, floor, ceiling in self._zones:
            inside = shapely.intersects_xy(poly, x, y) & (z >= floor) & (z <= ceiling)
            for i in np.flatnonzero(inside):
                out.append(Violation(_p(points[i]), f"no-fly zone {name}", 0.0))
        return out

    def check_segments(
        self, segments: Iterable[PathSegment], clearance: float, step: float = 0.5
    ) -> list[Violation]:
        """Violations along cubic segments sampled every ``step`` metres (about)."""
        out: list[Violation] = []
        for seg in segments:
            n = max(2, math.ceil(seg.arc_length() / step))
            pts = np.array([seg.position(float(s)) for s in np.linspace(0.0, 1.0, n + 1)])
            out += self.check_points(pts, clearance)
        return out


def _p(v: NDArray[np.float64]) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))
