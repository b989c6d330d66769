from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_navigation.gis import Gis, Zone
from sim.world import World


@pytest.fixture
def gis(small_world: World) -> Gis:
    return Gis(small_world)


POINTS = [
    ((0.0, 0.0, 10.0), False),  # inside the wall
    ((0.0, 0.0, 30.0), False),  # 5 m above the roof: within the margin
    ((0.0, 0.0, 32.0), True),  # 7 m above the roof
    ((-15.0, 0.0, 10.0), False),  # 5 m beside the wall
    ((-17.0, 0.0, 10.0), True),  # 7 m beside it
    ((-60.0, 0.0, 4.0), False),  # near the ground
    ((-60.0, 0.0, 7.0), True),
    ((55.0, 55.0, 20.0), False),  # inside the tower's L-shaped footprint
    ((45.0, 55.0, 20.0), False),  # in the L's notch, 5 m from a face
    ((43.0, 57.0, 20.0), True),  # in the notch, 7 m from both faces
    ((-60.0, 75.0, 12.0), False),  # in the hedge's margin
    ((65.0, -65.0, 20.0), True),  # a no-fly zone is not a solid
]


@pytest.mark.parametrize(("p", "free"), POINTS)
def test_point_clearance_follows_solids_and_margin(
    gis: Gis, p: tuple[float, float, float], free: bool
) -> None:
    assert gis.point_free(p) is free


SEGMENTS = [
    ((-40.0, 0.0, 10.0), (40.0, 0.0, 10.0), False),  # through the wall
    ((-40.0, 0.0, 35.0), (40.0, 0.0, 35.0), True),  # over it
    ((-40.0, -70.0, 10.0), (40.0, -70.0, 10.0), True),  # past its south end (10 m away)
    ((-40.0, -64.0, 10.0), (40.0, -64.0, 10.0), False),  # 4 m from its south face
    ((-40.0, 0.0, 35.0), (-40.0, 0.0, 35.0), True),  # a point
    ((-60.0, 0.0, 30.0), (-60.0, 0.0, 3.0), False),  # descending into the ground margin
]


@pytest.mark.parametrize(("a", "b", "free"), SEGMENTS)
def test_segment_capsule_test(gis: Gis, a, b, free: bool) -> None:  # type: ignore[no-untyped-def]
    assert gis.segment_free(a, b) is free
    assert gis.segment_free(b, a) is free


def test_polyline_test_is_conservative_on_curves(gis: Gis) -> None:
    s = np.linspace(0.0, math.pi, 60)
    arc = np.stack([-17.5 - 5.0 * np.sin(s), 70.0 * np.cos(s), np.full_like(s, 10.0)], axis=1)
    assert gis.polyline_free(arc)
    bulge = arc.copy()
    bulge[30, 0] = -12.0  # one sample 2 m from the wall
    assert not gis.polyline_free(bulge)


def test_runtime_obstacles_and_zones_can_be_added_and_removed(gis: Gis) -> None:
    p = (-60.0, -60.0, 15.0)
    rev = gis.revision
    gis.add_obstacle(
        "crane", ((-65.0, -65.0), (-55.0, -65.0), (-55.0, -55.0), (-65.0, -55.0)), 0.0, 40.0
    )
    assert not gis.point_free(p)
    assert gis.point_free(p, static=True) is False and gis.obstacle_names == ("crane",)
    assert not gis.segment_free((-80.0, -60.0, 15.0), (-40.0, -60.0, 15.0), static=False)
    gis.remove_obstacle("crane")
    assert gis.point_free(p)
    gis.add_no_fly_zone(Zone("fire", ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)), 0.0, 10.0))
    assert [z.name for z in gis.no_fly_zones] == ["zone", "fire"]
    gis.remove_no_fly_zone("fire")
    assert gis.revision == rev + 4


@pytest.mark.parametrize(
    "call",
    [
        lambda g: g.remove_obstacle("nope"),
        lambda g: g.remove_no_fly_zone("nope"),
        lambda g: g.add_obstacle("x", ((0.0, 0.0), (1.0, 1.0)), 0.0, 1.0),
        lambda g: g.add_obstacle("x", ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)), 5.0, 1.0),
        lambda g: g.add_no_fly_zone(Zone("x", ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)))),
        lambda g: g.add_no_fly_zone(Zone("x", ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)), 5.0, 1.0)),
    ],
)
def test_bad_updates_raise_config_errors(gis: Gis, call) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError):
        call(gis)


def test_margin_and_volume(small_world: World) -> None:
    with pytest.raises(ConfigError):
        Gis(small_world, margin=0.0)
    assert Gis(small_world, margin=4.0).point_free((-15.0, 0.0, 10.0))
    gis = Gis(small_world)
    (e0, n0, z0), (e1, n1, z1) = gis.bounds
    assert (e0, n0, e1, n1) == (-100.0, -100.0, 100.0, 100.0)
    assert z0 == 0.0 and z1 == pytest.approx(max(b.top for b in small_world.buildings) + 40.0)
    assert gis.static_key() != Gis(small_world, margin=5.0).static_key()
