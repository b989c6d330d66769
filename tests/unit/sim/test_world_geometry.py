"""World geometry: containment, segment tests and 2.5D ray casting against a small world."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.geodesy import GeodeticOrigin
from sim.terrain import Terrain
from sim.world import Building, Vegetation, World
from sim.world_geometry import HitKind, WorldGeometry
from sim.world_loader import load_world

SLOPE = Terrain(-100.0, -100.0, 200.0, ((0.0, 0.0), (10.0, 10.0)))  # rises 5 m per 100 m north
WORLD = World(
    name="geo",
    origin=GeodeticOrigin(55.7, 13.47, 95.0),
    terrain=SLOPE,
    buildings=(Building("box", ((0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)), 10.0, 5.0),),
    vegetation=(Vegetation("trees", ((30.0, -5.0), (40.0, -5.0), (40.0, 5.0), (30.0, 5.0)), 8.0),),
)
GEO = WorldGeometry(WORLD)


@pytest.mark.parametrize(
    ("point", "expected"),
    [
        ((5.0, 5.0, None), "box"),
        ((5.0, 5.0, 10.0), "box"),
        ((5.0, 5.0, 16.0), None),  # above the roof (top 15)
        ((10.0, 5.0, 8.0), "box"),  # on the wall
        ((15.0, 5.0, None), None),
    ],
)
def test_point_in_building(point: tuple[float, float, float | None], expected: str | None) -> None:
    assert GEO.point_in_building(*point) == expected


@pytest.mark.parametrize(
    ("start", "end", "expected"),
    [
        ((-10.0, 5.0, 8.0), (20.0, 5.0, 8.0), "box"),  # through the walls
        ((-10.0, 5.0, 20.0), (20.0, 5.0, 20.0), None),  # over the roof
        ((-10.0, 5.0, 8.0), (-1.0, 5.0, 8.0), None),  # stops short
        ((5.0, 5.0, 30.0), (5.0, 5.0, 14.0), "box"),  # vertical into the roof
        ((-10.0, -10.0, 10.0), (20.0, 20.0, 10.0), "box"),  # diagonal through a corner region
    ],
)
def test_segment_intersects_building(
    start: tuple[float, float, float], end: tuple[float, float, float], expected: str | None
) -> None:
    assert GEO.segment_intersects_building(start, end) == expected


def test_ray_hits_wall_roof_vegetation_and_terrain() -> None:
    wall = GEO.ray_cast((-20.0, 5.0, 8.0), (1.0, 0.0, 0.0), 100.0)
    assert (
        wall is not None and wall.kind is HitKind.BUILDING and wall.distance == pytest.approx(20.0)
    )
    roof = GEO.ray_cast((5.0, 5.0, 40.0), (0.0, 0.0, -1.0), 100.0)
    assert roof is not None and roof.distance == pytest.approx(25.0)
    trees = GEO.ray_cast((20.0, 0.0, 8.0), (1.0, 0.0, 0.0), 100.0)
    assert trees is not None and trees.kind is HitKind.VEGETATION and trees.name == "trees"
    assert trees.distance == pytest.approx(10.0)
    ground = GEO.ray_cast((-50.0, 0.0, 20.0), (0.0, 0.0, -1.0), 100.0)
    assert ground is not None and ground.kind is HitKind.TERRAIN
    assert ground.point[2] == pytest.approx(SLOPE.height(-50.0, 0.0), abs=1e-6)


def test_slanted_ray_meets_sloped_terrain() -> None:
    direction = (0.0, math.cos(math.radians(-30.0)), math.sin(math.radians(-30.0)))
    hit = GEO.ray_cast((-50.0, -50.0, 20.0), direction, 200.0)
    assert hit is not None and hit.kind is HitKind.TERRAIN
    assert hit.point[2] == pytest.approx(SLOPE.height(hit.point[0], hit.point[1]), abs=1e-4)


def test_ray_misses_within_range() -> None:
    assert GEO.ray_cast((-50.0, 0.0, 50.0), (0.0, -1.0, 0.0), 10.0) is None
    with pytest.raises(ValueError):
        GEO.ray_cast((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 10.0)


def test_revinge_buildings_are_found_by_their_footprint_centre() -> None:
    world = load_world("revinge")
    geometry = WorldGeometry(world)
    for building in world.buildings[:5]:
        e = sum(p[0] for p in building.footprint[:4]) / 4.0
        n = sum(p[1] for p in building.footprint[:4]) / 4.0
        if building.name != geometry.point_in_building(e, n):
            pytest.fail(f"{building.name} not found at ({e}, {n})")


def test_ray_cast_many_equals_ray_cast_per_ray() -> None:
    world = load_world("revinge")
    geometry = WorldGeometry(world)
    rng = np.random.default_rng(8)
    for origin in [(-60.0, 40.0, 8.0), (100.0, 50.0, 30.0), (10.0, -150.0, 3.0)]:
        directions = rng.normal(size=(200, 3))
        many = geometry.ray_cast_many(origin, directions, 80.0)
        for direction, distance in zip(directions, many, strict=True):
            hit = geometry.ray_cast(origin, tuple(direction), 80.0)
            expected = math.inf if hit is None else hit.distance
            assert distance == pytest.approx(expected, abs=1e-6), (origin, direction)
    assert np.isfinite(many).sum() > 50  # the comparison covered real hits


def test_ray_cast_many_rejects_bad_directions() -> None:
    with pytest.raises(ValueError):
        GEO.ray_cast_many((0.0, 0.0, 10.0), np.zeros((3, 3)), 10.0)
