"""Semantic checks of a loaded world: geometry validity, overlaps, containment, unique names.

Returns issues as ``(table, entry, key, reason)`` so the loader can attach the file line; entry
is the index within that table's entries in file order.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from itertools import combinations

from shapely.geometry import LineString, Point, Polygon
from shapely.validation import explain_validity

from sim.world import DynamicObject, ObjectKind, Point2, World

Issue = tuple[str, int, str | None, str]
"""(table, entry index, key or None, reason)."""


def validate_world(world: World) -> list[Issue]:
    """All semantic problems of ``world`` (empty if it is valid)."""
    issues: list[Issue] = []
    issues.extend(_unique_names(world))
    issues.extend(_polygons(world))
    issues.extend(_inside_terrain(world))
    if issues:
        return issues  # overlap checks need valid polygons
    issues.extend(_pads_and_depots(world))
    issues.extend(_objects(world))
    issues.extend(_loaded_carriers(world))
    return issues


def _unique_names(world: World) -> Iterator[Issue]:
    seen: dict[str, str] = {}
    named: list[tuple[str, str, Sequence[object]]] = [
        ("building", "name", world.buildings),
        ("road", "name", world.roads),
        ("vegetation", "name", world.vegetation),
        ("no_fly_zone", "name", world.no_fly_zones),
        ("place", "name", world.places),
        ("radiation_source", "name", world.radiation_sources),
        ("pad", "name", world.pads),
        ("depot", "name", world.depots),
        ("object", "id", world.objects),
    ]
    for table, key, items in named:
        for entry, item in enumerate(items):
            name = str(getattr(item, key))
            if name in seen:
                yield table, entry, key, f"duplicate name '{name}' (already used by a {seen[name]})"
            else:
                seen[name] = table


def _polygon_issue(points: Sequence[Point2]) -> str | None:
    polygon = Polygon(points)
    if not polygon.is_valid:
        return f"invalid polygon: {explain_validity(polygon)}"
    if polygon.area <= 0.0:
        return "polygon has zero area"
    return None


def _polygons(world: World) -> Iterator[Issue]:
    groups: list[tuple[str, str, list[tuple[str, Sequence[Point2]]]]] = [
        ("building", "footprint", [(b.name, b.footprint) for b in world.buildings]),
        ("vegetation", "polygon", [(v.name, v.polygon) for v in world.vegetation]),
        ("no_fly_zone", "polygon", [(z.name, z.polygon) for z in world.no_fly_zones]),
    ]
    for table, key, items in groups:
        for entry, (name, points) in enumerate(items):
            problem = _polygon_issue(points)
            if problem is not None:
                yield table, entry, key, f"{table} '{name}': {problem}"
    for entry, road in enumerate(world.roads):
        if LineString(road.points).length <= 0.0:
            yield "road", entry, "points", f"road '{road.name}' has zero length"


def _inside_terrain(world: World) -> Iterator[Issue]:
    e0, n0, e1, n1 = world.bounds

    def outside(points: Sequence[Point2]) -> bool:
        return any(not (e0 <= e <= e1 and n0 <= n <= n1) for e, n in points)

    where = f"outside the terrain grid [{e0}, {e1}] x [{n0}, {n1}]"
    shapes: list[tuple[str, str, Sequence[tuple[str, Sequence[Point2]]]]] = [
        ("building", "footprint", [(b.name, b.footprint) for b in world.buildings]),
        ("road", "points", [(r.name, r.points) for r in world.roads]),
        ("vegetation", "polygon", [(v.name, v.polygon) for v in world.vegetation]),
        ("place", "position", [(p.name, [(p.east, p.north)]) for p in world.places]),
        (
            "radiation_source",
            "position",
            [(r.name, [(r.east, r.north)]) for r in world.radiation_sources],
        ),
        ("pad", "position", [(p.name, [(p.east, p.north)]) for p in world.pads]),
        ("depot", "position", [(d.name, [(d.east, d.north)]) for d in world.depots]),
        (  # a driving car's position is its route's start
            "object",
            "position",
            [(o.id, [(o.east, o.north)] if o.drive is None else []) for o in world.objects],
        ),
        ("object", "route", [(o.id, o.drive.route if o.drive else ()) for o in world.objects]),
    ]
    for table, key, items in shapes:
        for entry, (name, points) in enumerate(items):
            if outside(points):
                yield table, entry, key, f"{table} '{name}' lies {where}"


def _pads_and_depots(world: World) -> Iterator[Issue]:
    buildings = [(b.name, Polygon(b.footprint)) for b in world.buildings]
    trees = [(v.name, Polygon(v.polygon)) for v in world.vegetation]
    for (_, a), (j, b) in combinations(enumerate(world.pads), 2):
        gap = Point(a.east, a.north).distance(Point(b.east, b.north)) - a.radius - b.radius
        if gap < 0.0:
            yield "pad", j, "position", f"pad '{b.name}' overlaps pad '{a.name}' by {-gap:.1f} m"
    areas = [("pad", p.name, Point(p.east, p.north).buffer(p.radius)) for p in world.pads]
    areas += [("depot", d.name, Point(d.east, d.north).buffer(d.radius)) for d in world.depots]
    counters = {"pad": 0, "depot": 0}
    for table, name, disc in areas:
        entry = counters[table]
        counters[table] += 1
        for what, obstacles in (("building", buildings), ("vegetation", trees)):
            for other, polygon in obstacles:
                if disc.intersects(polygon):
                    yield table, entry, "position", f"{table} '{name}' overlaps {what} '{other}'"


def _objects(world: World) -> Iterator[Issue]:
    buildings = [(b.name, Polygon(b.footprint)) for b in world.buildings]
    for entry, obj in enumerate(world.objects):
        if obj.drive is not None:  # a driving car's start lies on its route
            route = obj.drive.route
            line = LineString([*route, route[0]] if obj.drive.loop else route)
            for name, polygon in buildings:
                if line.intersects(polygon):
                    yield (
                        "object",
                        entry,
                        "route",
                        f"car '{obj.id}': route crosses building '{name}'",
                    )
            continue
        point = Point(obj.east, obj.north)
        for name, polygon in buildings:
            if polygon.covers(point):
                yield (
                    "object",
                    entry,
                    "position",
                    f"{obj.kind.value} '{obj.id}' is inside building '{name}'",
                )


def _footprint(obj: DynamicObject) -> Polygon:
    """An object's ground footprint: its length along its heading, its width across."""
    length, width, _ = obj.size
    s, c = math.sin(obj.heading), math.cos(obj.heading)
    corners = [(a * length / 2.0, b * width / 2.0) for a, b in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
    return Polygon([(obj.east + a * s + b * c, obj.north + a * c - b * s) for a, b in corners])


def _loaded_carriers(world: World) -> Iterator[Issue]:
    """A box ``on`` a carrier names a carrier, lies within it, and fits its capacity."""
    carriers = {o.id: o for o in world.objects if o.kind is ObjectKind.CARRIER}
    aboard: dict[str, int] = {}
    for entry, obj in enumerate(world.objects):
        if obj.on is None:
            continue
        carrier = carriers.get(obj.on)
        if carrier is None:
            yield ("object", entry, "on", f"box '{obj.id}': '{obj.on}' is not a carrier")
            continue
        if not _footprint(carrier).contains(_footprint(obj)):
            yield (
                "object",
                entry,
                "position",
                f"box '{obj.id}' does not lie within carrier '{carrier.id}'",
            )
        aboard[carrier.id] = aboard.get(carrier.id, 0) + 1
        if aboard[carrier.id] > (carrier.capacity or 0):
            yield (
                "object",
                entry,
                "on",
                f"carrier '{carrier.id}' holds {carrier.capacity} boxes; '{obj.id}' is one more",
            )
