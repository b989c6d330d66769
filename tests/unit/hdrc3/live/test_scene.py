from __future__ import annotations

import pytest
import shapely

from hdrc3.live.scene import _triangulate, prism, world_scene
from hdrc3.live.wire import WireSchema, decode
from sim.world_loader import load_world

SQUARE = ((0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0))
ELL = ((0.0, 0.0), (20.0, 0.0), (20.0, 5.0), (5.0, 5.0), (5.0, 20.0), (0.0, 20.0))


@pytest.mark.parametrize(("polygon", "triangles"), [(SQUARE, 2), (ELL, 4)])
def test_roofs_cover_the_footprint_exactly(polygon, triangles):
    tris = _triangulate(polygon)
    assert len(tris) == triangles
    area = sum(shapely.Polygon(t).area for t in tris)
    assert area == pytest.approx(shapely.Polygon(polygon).area)


def test_prism_has_two_triangles_per_wall_and_a_roof():
    points = prism(SQUARE, 2.0, 7.0)
    assert len(points) == 4 * 6 + 2 * 3


def test_world_scene_holds_every_static_thing_of_the_world_file():
    world = load_world("revinge")
    from foxglove.messages import SceneUpdate

    scene = decode(WireSchema.well_known(SceneUpdate), world_scene(world, 7).encode())
    ids = [e.id for e in scene.entities]
    expected = (
        ["terrain"]
        + [f"building/{b.name}" for b in world.buildings]
        + [f"no_fly_zone/{z.name}" for z in world.no_fly_zones]
        + [f"road/{r.name}" for r in world.roads]
    )
    assert ids == expected
    assert {e.frame_id for e in scene.entities} == {"world"}
    terrain = scene.entities[0].triangles[0]
    cells = (world.terrain.rows - 1) * (world.terrain.cols - 1)
    assert len(terrain.indices) == 6 * cells
    assert len(terrain.points) == world.terrain.rows * world.terrain.cols
    building = world.buildings[0]
    tops = [p.z for p in scene.entities[1].triangles[0].points]
    assert max(tops) == pytest.approx(building.top)
