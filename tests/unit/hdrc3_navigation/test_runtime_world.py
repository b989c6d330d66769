"""The runtime world model: what changed, and where a path first enters it."""

from __future__ import annotations

import math

import pytest

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.gis import Gis, Zone
from hdrc3_navigation.runtime_world import RuntimeWorld
from sim.world import World

SQUARE = ((40.0, -10.0), (50.0, -10.0), (50.0, 10.0), (40.0, 10.0))
EASTWARD = PathSegment.straight((0.0, 0.0, 20.0), (100.0, 0.0, 20.0), 8.0, 8.0)
NORTHWARD = PathSegment.straight((100.0, 0.0, 20.0), (100.0, 50.0, 20.0), 8.0, 0.0)


@pytest.mark.parametrize(
    ("zones", "obstacles", "margin", "from_s", "expect"),
    [
        ((), (), 6.0, 0.0, None),  # nothing changed
        ((Zone("z", SQUARE),), (), 0.0, 0.0, (0, 40.0, "no-fly zone z")),
        ((Zone("z", SQUARE),), (), 6.0, 0.0, (0, 34.0, "no-fly zone z")),  # grown by the margin
        ((Zone("z", SQUARE, 30.0, 50.0),), (), 6.0, 0.0, None),  # above the path's 20 m
        ((Zone("z", SQUARE, 24.0, 50.0),), (), 6.0, 0.0, (0, 34.0, "no-fly zone z")),
        ((), (Zone("box", SQUARE, 0.0, 10.0),), 6.0, 0.0, None),  # 10 m below the path
        ((), (Zone("box", SQUARE, 0.0, 15.0),), 6.0, 0.0, (0, 34.0, "obstacle box")),
        ((Zone("z", SQUARE),), (), 0.0, 0.6, None),  # already past it
        (
            (Zone("n", ((90.0, 30.0), (110.0, 30.0), (110.0, 40.0), (90.0, 40.0))),),
            (),
            0.0,
            0.0,
            (1, 100.0, "no-fly zone n"),
        ),  # on the second segment
    ],
)
def test_the_first_conflict_of_a_path(
    zones: tuple[Zone, ...],
    obstacles: tuple[Zone, ...],
    margin: float,
    from_s: float,
    expect: tuple[int, float, str] | None,
) -> None:
    world = RuntimeWorld(1, margin, zones, obstacles)
    conflict = world.first_conflict([EASTWARD, NORTHWARD], from_s)
    if expect is None:
        assert conflict is None
        return
    assert conflict is not None
    index, east, region = expect
    assert (conflict.segment, conflict.region) == (index, region)
    assert math.isclose(conflict.position[0], east, abs_tol=1.0)


def test_runtime_regions_are_what_changed_after_loading(small_world: World) -> None:
    gis = Gis(small_world)
    assert RuntimeWorld.of(gis).no_fly_zones == ()  # the world file's zone is not a change
    gis.add_no_fly_zone(Zone("new", SQUARE))
    gis.add_obstacle("crate", SQUARE, 0.0, 5.0)
    world = RuntimeWorld.of(gis)
    assert [z.name for z in world.no_fly_zones] == ["new"]
    assert world.obstacles == (Zone("crate", SQUARE, 0.0, 5.0),)
    assert (world.revision, world.margin) == (gis.revision, gis.margin)
    gis.remove_obstacle("crate")
    gis.remove_no_fly_zone("new")
    assert RuntimeWorld.of(gis).obstacles == () == RuntimeWorld.of(gis).no_fly_zones
