"""GIS service core (chapter section 7, Figure 17): the world model the path planner checks.

Static geometry of a world file becomes python-fcl collision objects: every building and
vegetation area is a vertical prism, every terrain grid triangle a prism reaching far below the
ground, each split into convex pieces (``fcl.Convex``, constrained Delaunay triangles of the
footprint from shapely) so that a point deep inside a solid still collides. FCL's dynamic
AABB-tree broad phase plus GJK narrow phase plays the role of the chapter's OBBTree checker.

A configuration is free when a sphere of the safety margin's radius around it touches no solid;
a straight motion is free when the capsule (swept sphere) along it touches none. Runtime
obstacles (prisms) live in a second manager; no-fly zones (world-file and runtime) are kept as
shapely polygons for :mod:`hdrc3_navigation.constraints`.

Elevation maps from the laser range finder (§11.2: "the 3D maps acquired are saved in the GIS
Service database and available to the deliberative services") join the runtime manager too,
each as ONE ``fcl.BVHModel`` of its triangulated surface
(:meth:`hdrc3_navigation.elevation_map.ElevationMap.triangles`), rather than a convex prism per
triangle as the world file's terrain: a 150 m x 150 m map at 1 m is ~45k triangles, one
bounding-volume hierarchy built in ~0.1 s instead of 45k convex objects in the broad phase. A
mesh is only a surface, so a sphere or capsule wholly under it would touch nothing: a point below
a map's surface at its (east, north) (the height of the cell holding it; unmapped or outside: no
verdict) is therefore not free, and a straight motion is not free when either end is below a
map's surface. A motion with both ends above the surface that passes through a solid under it
must cross the surface mesh, except where the solid is cut open by the map's edge or a hole of
unmapped cells (no surface there, as in the map).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import fcl
import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

from hdrc3_base.errors import ConfigError, DataError
from hdrc3_navigation.elevation_map import ElevationMap
from sim.world import World

Vec3 = tuple[float, float, float]
Point3 = Sequence[float] | NDArray[np.float64]
"""A position: a sequence or an array of (east, north, up)."""
Point2 = tuple[float, float]
DEFAULT_MARGIN = 6.0
"""Safety margin around every solid, m (issue 13)."""
DEFAULT_CLEARANCE_ABOVE = 40.0
"""Height of the planning volume above the highest solid, m."""
_GROUND_DEPTH = 200.0
"""Terrain prisms reach this far below the lowest terrain point, m."""


@dataclass(frozen=True, slots=True)
class Zone:
    """A no-fly zone: a horizontal polygon between floor and ceiling (local up, m)."""

    name: str
    polygon: tuple[Point2, ...]
    floor: float = -math.inf
    ceiling: float = math.inf

    def shape(self) -> Polygon:
        """The footprint as a validated shapely polygon."""
        return _polygon(self.polygon, f"no-fly zone {self.name!r}")


@dataclass(frozen=True, slots=True)
class _StoredMap:
    """An elevation map in the GIS: the map, its surface as one BVH, its bounding box."""

    map: ElevationMap
    surface: Any
    """``fcl.CollisionObject`` of the ``fcl.BVHModel`` (registered in the runtime manager)."""
    box: tuple[float, float, float, float, float, float]
    """(min e, n, u, max e, n, u): the mapped cells' extent, the lowest and highest height."""
    triangles: int


def _polygon(points: Sequence[Point2], what: str) -> Polygon:
    if len(points) < 3 or not all(math.isfinite(c) for p in points for c in p):
        raise ConfigError(f"{what}: a polygon needs at least 3 finite vertices")
    poly = Polygon(points)
    if not poly.is_valid or poly.area <= 1e-6:
        raise ConfigError(f"{what}: polygon is self-intersecting or has no area")
    return poly


def _convex_prism(triangle: NDArray[np.float64], bottom: float, top: NDArray[np.float64]) -> Any:
    """A convex prism over one triangle: bottom at a height, top at per-vertex heights."""
    xy = np.asarray(triangle, dtype=np.float64)
    verts = np.vstack(
        [np.column_stack([xy, np.full(3, bottom)]), np.column_stack([xy, np.asarray(top)])]
    )
    # faces: count followed by vertex indices, outward orientation is not required by GJK
    faces = np.array(
        [3, 0, 2, 1, 3, 3, 4, 5, 4, 0, 1, 4, 3, 4, 1, 2, 5, 4, 4, 2, 0, 3, 5], dtype=np.int32
    )
    return fcl.Convex(verts, 5, faces)


def _prism_pieces(footprint: Polygon, base: float, top: float) -> list[Any]:
    """Convex pieces of a vertical prism over a (possibly non-convex) footprint."""
    pieces = []
    for tri in shapely.constrained_delaunay_triangles(footprint).geoms:
        xy = np.asarray(tri.exterior.coords[:3], dtype=np.float64)
        pieces.append(_convex_prism(xy, base, np.full(3, top)))
    return pieces


class Gis:
    """Collision geometry and no-fly zones of one world, with runtime updates.

    Args:
        world: The loaded world (terrain, buildings, vegetation, no-fly zones).
        margin: Safety margin around solids and no-fly zones, m.
        ceiling: Top of the planning volume (local up); default: highest solid + 40 m.

    """

    def __init__(self, world: World, margin: float = DEFAULT_MARGIN, ceiling: float | None = None):
        if not math.isfinite(margin) or margin <= 0.0:
            raise ConfigError(f"safety margin must be a positive number of metres, got {margin}")
        self.world = world
        self.margin = margin
        self._sphere = fcl.Sphere(margin)
        self._static = fcl.DynamicAABBTreeCollisionManager()
        self._static_objects: list[Any] = []
        terrain = world.terrain
        grid = terrain.array()
        self.ground_min = float(grid.min())
        solids_top = float(grid.max())
        for building in world.buildings:
            self._add_static(_prism_pieces(Polygon(building.footprint), -1e3, building.top))
            solids_top = max(solids_top, building.top)
        for veg in world.vegetation:
            poly = Polygon(veg.polygon)
            ground = float(terrain.heights_at(*np.asarray(poly.exterior.coords).T).max())
            self._add_static(_prism_pieces(poly, -1e3, ground + veg.height))
            solids_top = max(solids_top, ground + veg.height)
        self._add_static(self._terrain_pieces())
        self._static.setup()
        e0, n0, e1, n1 = world.bounds
        top = solids_top + DEFAULT_CLEARANCE_ABOVE if ceiling is None else ceiling
        if not math.isfinite(top) or top <= self.ground_min + margin:
            raise ConfigError(f"planning ceiling {top} is not above the ground plus margin")
        self.bounds: tuple[Vec3, Vec3] = ((e0, n0, self.ground_min), (e1, n1, top))
        """Planning volume (lower corner, upper corner)."""
        self._footprint = shapely.box(e0, n0, e1, n1)
        self._runtime = fcl.DynamicAABBTreeCollisionManager()
        self._runtime_objects: dict[str, list[Any]] = {}
        self._runtime_boxes: dict[str, tuple[float, ...]] = {}
        self._zones: dict[str, Zone] = {}
        self._obstacles: dict[str, Zone] = {}
        """Runtime obstacles as prisms (floor = base, ceiling = top)."""
        self._maps: dict[str, _StoredMap] = {}
        """Elevation maps by name (their surfaces are in the runtime manager)."""
        self.revision = 0
        """Incremented on every update (the world file's zones included)."""
        for zone in world.no_fly_zones:
            self.add_no_fly_zone(Zone(zone.name, zone.polygon, zone.floor, zone.ceiling))

    def _add_static(self, geoms: Iterable[Any]) -> None:
        for geom in geoms:
            obj = fcl.CollisionObject(geom, fcl.Transform())
            self._static_objects.append(obj)
            self._static.registerObject(obj)

    def _terrain_pieces(self) -> list[Any]:
        t = self.world.terrain
        bottom = self.ground_min - _GROUND_DEPTH
        pieces = []
        for r in range(t.rows - 1):
            for c in range(t.cols - 1):
                x0, y0 = t.east0 + c * t.spacing, t.north0 + r * t.spacing
                x1, y1 = x0 + t.spacing, y0 + t.spacing
                h = t.heights
                corners = {
                    (x0, y0): h[r][c],
                    (x1, y0): h[r][c + 1],
                    (x0, y1): h[r + 1][c],
                    (x1, y1): h[r + 1][c + 1],
                }
                for tri in (((x0, y0), (x1, y0), (x1, y1)), ((x0, y0), (x1, y1), (x0, y1))):
                    tops = np.array([corners[p] for p in tri])
                    pieces.append(_convex_prism(np.array(tri, dtype=np.float64), bottom, tops))
        return pieces

    # --- queries -------------------------------------------------------------------------

    def inside_bounds(self, p: Point3) -> bool:
        """Whether a point lies inside the planning volume."""
        lo, hi = self.bounds
        return all(lo[i] <= p[i] <= hi[i] for i in range(3))

    def _hits(self, obj: Any, static: bool = True) -> bool:
        managers = (self._static, self._runtime) if static else (self._runtime,)
        for manager in managers:
            if manager is self._runtime and not (self._runtime_objects or self._maps):
                continue
            data = fcl.CollisionData()
            manager.collide(obj, data, fcl.defaultCollisionCallback)
            if data.result.is_collision:
                return True
        return False

    def point_free(self, p: Point3, static: bool = True) -> bool:
        """True if a sphere of the margin's radius at ``p`` touches no solid.

        With ``static`` False only the runtime obstacles and elevation maps are tested (roadmap
        nodes are known to be clear of the static world). A point below an elevation map's
        surface is not free.
        """
        pa = np.asarray(p, dtype=np.float64)
        if self._maps and self._below_maps(pa.reshape(1, 3)):
            return False
        obj = fcl.CollisionObject(self._sphere, fcl.Transform(pa))
        return not self._hits(obj, static)

    def segment_free(self, a: Point3, b: Point3, static: bool = True) -> bool:
        """True if the straight motion a->b, swept by the margin sphere, touches no solid.

        With ``static`` False only the runtime obstacles and elevation maps are tested. A motion
        with an end below an elevation map's surface is not free.
        """
        if not static and not self._runtime_objects and not self._maps:
            return True
        return self._capsule_free(a, b, self.margin, static)

    def _capsule_free(self, a: Point3, b: Point3, radius: float, static: bool = True) -> bool:
        pa, pb = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        if self._maps and self._below_maps(np.vstack([pa, pb])):
            return False
        d = pb - pa
        length = float(np.linalg.norm(d))
        if length < 1e-6:
            geom = self._sphere if radius == self.margin else fcl.Sphere(radius)
            return not self._hits(fcl.CollisionObject(geom, fcl.Transform(pa)), static)
        obj = fcl.CollisionObject(
            fcl.Capsule(radius, length), fcl.Transform(_z_to(d / length), (pa + pb) / 2.0)
        )
        return not self._hits(obj, static)

    def polyline_free(self, points: NDArray[np.float64], piece: float = 12.0) -> bool:
        """True if a densely sampled curve, swept by the margin sphere, touches no solid.

        The samples are grouped into chords of up to ``piece`` metres; each chord's capsule is
        grown by the largest distance of its samples from it, so the test stays conservative.
        """
        i = 0
        n = len(points)
        while i < n - 1:
            j = i + 1
            while j + 1 < n and float(np.linalg.norm(points[j + 1] - points[i])) <= piece:
                j += 1
            grow = _deviation(points[i : j + 1])
            if not self._capsule_free(points[i], points[j], self.margin + grow):
                return False
            i = j
        return True

    # --- runtime updates -----------------------------------------------------------------

    @property
    def no_fly_zones(self) -> tuple[Zone, ...]:
        """The no-fly zones in force (world file and runtime), by insertion order."""
        return tuple(self._zones.values())

    def add_no_fly_zone(self, zone: Zone) -> None:
        """Add (or replace) a no-fly zone by name."""
        zone.shape()  # validates
        if not zone.floor < zone.ceiling:
            raise ConfigError(f"no-fly zone {zone.name!r}: floor must be below ceiling")
        self._zones[zone.name] = zone
        self.revision += 1

    def remove_no_fly_zone(self, name: str) -> None:
        """Remove a no-fly zone (ConfigError if unknown)."""
        if self._zones.pop(name, None) is None:
            raise ConfigError(f"no no-fly zone named {name!r}")
        self.revision += 1

    @property
    def obstacle_names(self) -> tuple[str, ...]:
        """Names of the runtime obstacles."""
        return tuple(self._runtime_objects)

    def add_obstacle(self, name: str, footprint: Sequence[Point2], base: float, top: float) -> None:
        """Add (or replace) a runtime obstacle: a vertical prism over a footprint."""
        poly = _polygon(footprint, f"obstacle {name!r}")
        if not (math.isfinite(base) and math.isfinite(top) and base < top):
            raise ConfigError(f"obstacle {name!r}: base must be below top")
        if name in self._runtime_objects:
            self.remove_obstacle(name)
        objs = [fcl.CollisionObject(g, fcl.Transform()) for g in _prism_pieces(poly, base, top)]
        for obj in objs:
            self._runtime.registerObject(obj)
        self._runtime.setup()
        self._runtime_objects[name] = objs
        e0, n0, e1, n1 = poly.bounds
        self._runtime_boxes[name] = (e0, n0, base, e1, n1, top)
        self._obstacles[name] = Zone(name, tuple(footprint), base, top)
        self.revision += 1

    def runtime_boxes(self) -> NDArray[np.float64]:
        """(k, 6) boxes (min e, n, u, max e, n, u) of the runtime obstacles and elevation maps."""
        boxes = [*self._runtime_boxes.values(), *(m.box for m in self._maps.values())]
        return np.array(boxes, dtype=np.float64).reshape(-1, 6)

    def remove_obstacle(self, name: str) -> None:
        """Remove a runtime obstacle (ConfigError if unknown)."""
        objs = self._runtime_objects.pop(name, None)
        if objs is None:
            raise ConfigError(f"no obstacle named {name!r}")
        del self._runtime_boxes[name]
        del self._obstacles[name]
        for obj in objs:
            self._runtime.unregisterObject(obj)
        self._runtime.setup()
        self.revision += 1

    @property
    def elevation_map_names(self) -> tuple[str, ...]:
        """Names of the elevation maps stored, by insertion order."""
        return tuple(self._maps)

    def add_elevation_map(self, elevation_map: ElevationMap) -> int:
        """Store (or replace, by name) an elevation map; the number of triangles of its surface.

        Raises:
            ConfigError: Not an :class:`ElevationMap`.
            DataError: The map has no triangle (no mapped cell).

        """
        if not isinstance(elevation_map, ElevationMap):
            raise ConfigError(f"not an elevation map: {type(elevation_map).__name__}")
        name = elevation_map.name
        vertices, faces = elevation_map.triangles()
        if len(faces) == 0:
            raise DataError(f"elevation map {name!r} has no triangles (no mapped cell)")
        model = fcl.BVHModel()
        model.beginModel(len(vertices), len(faces))
        model.addSubModel(vertices, faces)
        model.endModel()
        surface = fcl.CollisionObject(model, fcl.Transform())
        rows, cols = np.nonzero(elevation_map.mapped)
        r = elevation_map.resolution
        box = (
            elevation_map.east0 + float(cols.min()) * r,
            elevation_map.north0 + float(rows.min()) * r,
            float(np.nanmin(elevation_map.heights)),
            elevation_map.east0 + float(cols.max() + 1) * r,
            elevation_map.north0 + float(rows.max() + 1) * r,
            float(np.nanmax(elevation_map.heights)),
        )
        old = self._maps.get(name)
        if old is not None:
            self._runtime.unregisterObject(old.surface)
        self._runtime.registerObject(surface)
        self._runtime.setup()
        self._maps[name] = _StoredMap(elevation_map, surface, box, len(faces))
        self.revision += 1
        return len(faces)

    def remove_elevation_map(self, name: str) -> None:
        """Remove an elevation map (ConfigError if unknown)."""
        stored = self._maps.pop(name, None)
        if stored is None:
            raise ConfigError(f"no elevation map named {name!r}")
        self._runtime.unregisterObject(stored.surface)
        self._runtime.setup()
        self.revision += 1

    def _below_maps(self, points: NDArray[np.float64]) -> bool:
        """Whether any of the (k, 3) points is below an elevation map's surface."""
        for stored in self._maps.values():
            e0, n0, _, e1, n1, top = stored.box
            near = (
                (points[:, 0] >= e0)
                & (points[:, 0] <= e1)
                & (points[:, 1] >= n0)
                & (points[:, 1] <= n1)
                & (points[:, 2] < top)
            )
            if not near.any():
                continue
            ground = stored.map.heights_at(points[near, 0], points[near, 1])
            if bool(np.any(points[near, 2] < ground)):  # NaN (unmapped): no verdict
                return True
        return False

    def runtime_regions(self) -> tuple[tuple[Zone, ...], tuple[Zone, ...]]:
        """What changed at runtime: (no-fly zones not as in the world file, obstacles)."""
        from_file = {
            z.name: Zone(z.name, tuple(z.polygon), z.floor, z.ceiling)
            for z in self.world.no_fly_zones
        }
        zones = tuple(z for z in self._zones.values() if from_file.get(z.name) != z)
        return zones, tuple(self._obstacles.values())

    def static_key(self) -> str:
        """Hash of what a roadmap depends on: the world's static geometry and the margin."""
        h = hashlib.sha256()
        source = self.world.source
        if source is not None and source.is_file():
            h.update(source.read_bytes())
        else:
            h.update(
                repr((self.world.terrain, self.world.buildings, self.world.vegetation)).encode()
            )
        h.update(repr((self.margin, self.bounds)).encode())
        return h.hexdigest()[:20]


def _deviation(points: NDArray[np.float64]) -> float:
    """Largest distance of the points from the chord between the first and the last."""
    a, b = points[0], points[-1]
    d = b - a
    dd = float(d @ d)
    if len(points) < 3:
        return 0.0
    t = np.clip(((points - a) @ d) / dd, 0.0, 1.0) if dd > 1e-12 else np.zeros(len(points))
    return float(np.linalg.norm(points - (a + t[:, None] * d), axis=1).max())


def _z_to(direction: NDArray[np.float64]) -> NDArray[np.float64]:
    """Quaternion (w, x, y, z) rotating the z axis onto a unit direction."""
    dx, dy, dz = float(direction[0]), float(direction[1]), float(direction[2])
    if dz < -1.0 + 1e-12:
        return np.array([0.0, 1.0, 0.0, 0.0])
    # q = (1 + z.d, z x d) normalised; z x d = (-dy, dx, 0)
    w = 1.0 + dz
    n = math.sqrt(w * w + dx * dx + dy * dy)
    return np.array([w / n, -dy / n, dx / n, 0.0])
