"""The runtime part of a path planner's world model, as executors check a path against it (§7).

Figure 18: the fly-to executor streams planned segments while the world may change (a no-fly
zone declared, an obstacle reported). The path planner publishes what changed at runtime
(:meth:`hdrc3_navigation.gis.Gis.runtime_regions`) as one value, :class:`RuntimeWorld`; the
executor asks it whether the part of its path not yet flown enters any of those regions, grown
by the planner's safety margin, and replans if so. The check is shapely on sampled points, not
the planner's FCL geometry: it only has to say "this path is no longer valid", the new plan is
the planner's.

Elevation maps (§11.2) are listed by name only (``elevation_maps``): :meth:`first_conflict`
checks a path against the no-fly zones and obstacles alone, so storing a map does not make an
executor replan a path in flight (it bumps the revision, so the path is checked again against
the zones and obstacles); plans made after the map is stored respect it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.gis import Gis, Zone

SAMPLE_STEP = 1.0
"""Segments are checked at points about this far apart along the curve, m."""


@dataclass(frozen=True, slots=True)
class Conflict:
    """Where a path first enters a runtime region."""

    segment: int
    """Index of the segment in the list checked."""
    position: tuple[float, float, float]
    region: str
    """``no-fly zone NAME`` or ``obstacle NAME``."""


@dataclass(frozen=True, slots=True)
class RuntimeWorld:
    """No-fly zones and obstacles added at runtime, with the planner's margin and revision."""

    revision: int = 0
    margin: float = 0.0
    no_fly_zones: tuple[Zone, ...] = ()
    obstacles: tuple[Zone, ...] = ()
    elevation_maps: tuple[str, ...] = ()
    """Names of the elevation maps stored in the GIS (not checked by :meth:`first_conflict`)."""

    @classmethod
    def of(cls, gis: Gis) -> RuntimeWorld:
        """The runtime regions of a GIS now."""
        zones, obstacles = gis.runtime_regions()
        return cls(gis.revision, gis.margin, zones, obstacles, gis.elevation_map_names)

    def _regions(self) -> list[tuple[str, Polygon, float, float]]:
        m = self.margin
        out = []
        for kind, regions in (("no-fly zone", self.no_fly_zones), ("obstacle", self.obstacles)):
            for z in regions:
                grown = Polygon(z.polygon).buffer(m) if m > 0 else Polygon(z.polygon)
                out.append((f"{kind} {z.name}", grown, z.floor - m, z.ceiling + m))
        return out

    def first_conflict(self, segments: list[PathSegment], from_s: float = 0.0) -> Conflict | None:
        """The first point of ``segments`` inside a grown region (the first from ``from_s``)."""
        regions = self._regions()
        if not regions:
            return None
        for index, segment in enumerate(segments):
            points = _sample(segment, from_s if index == 0 else 0.0)
            x, y, z = points[:, 0], points[:, 1], points[:, 2]
            hits = np.zeros(len(points), dtype=bool)
            names: list[str | None] = [None] * len(points)
            for name, poly, floor, ceiling in regions:
                inside = shapely.intersects_xy(poly, x, y) & (z >= floor) & (z <= ceiling)
                for k in np.flatnonzero(inside & ~hits):
                    names[int(k)] = name
                hits |= inside
            if hits.any():
                first = int(np.argmax(hits))
                p = points[first]
                return Conflict(index, (float(p[0]), float(p[1]), float(p[2])), str(names[first]))
        return None


def _sample(segment: PathSegment, from_s: float) -> NDArray[np.float64]:
    n = max(2, math.ceil(segment.arc_length() * (1.0 - from_s) / SAMPLE_STEP))
    return np.array([segment.position(float(s)) for s in np.linspace(from_s, 1.0, n + 1)])
