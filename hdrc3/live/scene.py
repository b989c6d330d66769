"""The world file as Foxglove scene entities: terrain, buildings, no-fly zones, roads.

Buildings and zones are prisms: walls as two triangles per footprint edge, roofs from shapely's
constrained Delaunay triangulation of the footprint (footprints may be concave). Zones are
translucent red with their outline as lines, so what lies inside stays visible.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import shapely
from foxglove.messages import (
    Color,
    LinePrimitive,
    LinePrimitiveLineType,
    Point3,
    SceneEntity,
    SceneUpdate,
    TextPrimitive,
    TriangleListPrimitive,
)

from hdrc3.live.geometry import WORLD_FRAME, color, height_color, point, pose, timestamp
from sim.world import World

Point2 = tuple[float, float]

BUILDING = color(0.62, 0.62, 0.66)
ZONE = color(0.9, 0.15, 0.1, 0.25)
ZONE_EDGE = color(0.9, 0.15, 0.1, 0.9)
ROAD = color(0.3, 0.3, 0.3)
ROAD_LIFT_M = 0.3
"""Roads float this far above the terrain so that they are not hidden in it."""


def _triangulate(polygon: Sequence[Point2]) -> list[tuple[Point2, Point2, Point2]]:
    """Triangles covering a simple polygon (concave ones too)."""
    shape = shapely.Polygon(polygon)
    if not shape.is_valid or shape.area <= 0.0:
        return []
    out = []
    for tri in shapely.get_parts(shapely.constrained_delaunay_triangles(shape)):
        (a, b, c, _) = tri.exterior.coords
        out.append(((a[0], a[1]), (b[0], b[1]), (c[0], c[1])))
    return out


def prism(polygon: Sequence[Point2], floor: float, ceiling: float) -> list[Point3]:
    """Triangle list (three points per triangle) of a vertical prism over ``polygon``."""
    points: list[Point3] = []
    ring = [*polygon, polygon[0]]
    for (x0, y0), (x1, y1) in itertools.pairwise(ring):
        low0, low1 = point(x0, y0, floor), point(x1, y1, floor)
        high0, high1 = point(x0, y0, ceiling), point(x1, y1, ceiling)
        points += [low0, low1, high1, low0, high1, high0]
    for tri in _triangulate(polygon):
        points += [point(x, y, ceiling) for x, y in tri]
    return points


def outline(polygon: Sequence[Point2], height: float) -> list[Point3]:
    """Closed ring of ``polygon`` at ``height`` (for a line loop)."""
    return [point(x, y, height) for x, y in polygon]


def terrain_entity(world: World, stamp_ns: int) -> SceneEntity:
    """The terrain heightfield as an indexed triangle list coloured by height."""
    terrain = world.terrain
    low = min(min(row) for row in terrain.heights)
    high = max(max(row) for row in terrain.heights)
    points: list[Point3] = []
    colors: list[Color] = []
    for r, row in enumerate(terrain.heights):
        for c, h in enumerate(row):
            east = terrain.east0 + c * terrain.spacing
            north = terrain.north0 + r * terrain.spacing
            points.append(point(east, north, h))
            colors.append(height_color(h, low, high))
    indices: list[int] = []
    cols = terrain.cols
    for r in range(terrain.rows - 1):
        for c in range(cols - 1):
            a, b = r * cols + c, r * cols + c + 1
            d, e = a + cols, b + cols
            indices += [a, b, e, a, e, d]
    mesh = TriangleListPrimitive(pose=pose(), points=points, colors=colors, indices=indices)
    return SceneEntity(
        timestamp=timestamp(stamp_ns), frame_id=WORLD_FRAME, id="terrain", triangles=[mesh]
    )


def _label(text: str, east: float, north: float, up: float) -> TextPrimitive:
    return TextPrimitive(
        pose=pose(east, north, up),
        billboard=True,
        font_size=12.0,
        scale_invariant=True,
        color=color(1, 1, 1),
        text=text,
    )


def world_scene(world: World, stamp_ns: int) -> SceneUpdate:
    """Every static thing of ``world`` as one scene update (entity ids: ``kind/name``)."""
    entities = [terrain_entity(world, stamp_ns)]
    stamp = timestamp(stamp_ns)
    for b in world.buildings:
        shape = TriangleListPrimitive(
            pose=pose(), points=prism(b.footprint, b.base, b.top), color=BUILDING
        )
        entities.append(
            SceneEntity(
                timestamp=stamp, frame_id=WORLD_FRAME, id=f"building/{b.name}", triangles=[shape]
            )
        )
    for z in world.no_fly_zones:
        volume = TriangleListPrimitive(
            pose=pose(), points=prism(z.polygon, z.floor, z.ceiling), color=ZONE
        )
        edges = [
            LinePrimitive(
                type=LinePrimitiveLineType.LineLoop,
                pose=pose(),
                thickness=2.0,
                scale_invariant=True,
                points=outline(z.polygon, height),
                color=ZONE_EDGE,
            )
            for height in (z.floor, z.ceiling)
        ]
        east, north = shapely.Polygon(z.polygon).centroid.coords[0]
        entities.append(
            SceneEntity(
                timestamp=stamp,
                frame_id=WORLD_FRAME,
                id=f"no_fly_zone/{z.name}",
                triangles=[volume],
                lines=edges,
                texts=[_label(z.name, east, north, z.ceiling)],
            )
        )
    for road in world.roads:
        line = LinePrimitive(
            type=LinePrimitiveLineType.LineStrip,
            pose=pose(),
            thickness=road.width,
            points=[point(e, n, world.terrain.height(e, n) + ROAD_LIFT_M) for e, n in road.points],
            color=ROAD,
        )
        entities.append(
            SceneEntity(timestamp=stamp, frame_id=WORLD_FRAME, id=f"road/{road.name}", lines=[line])
        )
    return SceneUpdate(entities=entities)
