"""The scene of revinge: terrain on the heightfield, roofs at building tops, trees in woods."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from sim.render.materials import Material, ThermalEnvironment
from sim.render.scene import TERRAIN_MARGIN_M, SceneMeshes, build_scene
from sim.world import ObjectKind, World
from sim.world_loader import load_world

ENV = ThermalEnvironment()


@pytest.fixture(scope="module")
def revinge() -> tuple[World, SceneMeshes]:
    world = load_world("revinge")
    return world, build_scene(world, ENV)


def test_terrain_vertices_lie_on_the_heightfield_and_beyond_the_grid(
    revinge: tuple[World, SceneMeshes],
) -> None:
    world, scene = revinge
    v = scene.static
    ground = v[
        np.isin(
            np.round(v[:, 9] - ENV.ambient, 3),
            [Material.GRASS.surface.warmth, Material.FIELD.surface.warmth],
        )
    ]
    heights = world.terrain.heights_at(ground[:, 0].astype(float), ground[:, 1].astype(float))
    assert np.allclose(ground[:, 2], heights, atol=1e-4)
    e0, _, _, n1 = world.bounds
    assert ground[:, 0].min() <= e0 - TERRAIN_MARGIN_M + 1.0
    assert ground[:, 1].max() >= n1 + TERRAIN_MARGIN_M - 1.0


def test_every_building_has_a_hot_roof_at_its_top(revinge: tuple[World, SceneMeshes]) -> None:
    world, scene = revinge
    v = scene.static
    roofs = v[np.isclose(v[:, 9], ENV.ambient + Material.ROOF.surface.warmth)]
    for building in world.buildings:
        inside = Polygon(building.footprint).buffer(0.01)
        mine = [p for p in roofs if inside.contains(Point(p[0], p[1]))]
        assert mine and all(abs(p[2] - building.top) < 1e-3 for p in mine), building.name


def test_trees_grow_inside_the_vegetation_areas_only(revinge: tuple[World, SceneMeshes]) -> None:
    world, scene = revinge
    v = scene.static
    trunks = v[np.isclose(v[:, 9], ENV.ambient + Material.TRUNK.surface.warmth)]
    areas = [Polygon(a.polygon).buffer(1.0) for a in world.vegetation]
    assert len(trunks) > 36 * 50
    assert all(any(a.contains(Point(p[0], p[1])) for a in areas) for p in trunks[::36])


def test_objects_mesh_has_every_person_warm(revinge: tuple[World, SceneMeshes]) -> None:
    world, scene = revinge
    persons = world.objects_of(ObjectKind.PERSON)
    for person in persons:
        assert person.temperature is not None
        assert np.isclose(scene.objects[:, 9], person.temperature, atol=1e-3).any(), person.id
