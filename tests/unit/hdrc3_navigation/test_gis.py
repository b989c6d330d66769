from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_base.errors import ConfigError, DataError
from hdrc3_navigation.elevation_map import ElevationMap
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


# --- elevation maps (§11.2) ---------------------------------------------------------------------

BLOCK_TOP = 10.0
"""A 20 m x 20 m block (east -80..-60, north -40..-20), 10 m high, on a flat 40 m x 40 m map."""


def block_map(name: str = "scan", top: float = BLOCK_TOP, east0: float = -95.0) -> ElevationMap:
    heights = np.zeros((40, 40))
    heights[10:30, 15:35] = top  # cells: east -95 + 15..35, north -50 + 10..30
    heights[0, 0] = np.nan  # an unmapped corner
    return ElevationMap(name, east0, -50.0, 1.0, heights)


MAP_POINTS = [
    # (point, static world too, free)
    ((-70.0, -30.0, 14.0), True, False),  # 4 m above the block: within the margin
    ((-70.0, -30.0, 17.0), True, True),  # 7 m above it
    ((-70.0, -30.0, 3.0), False, False),  # inside: below the surface, 7 m from it
    ((-70.0, -30.0, 3.0), True, False),
    ((-70.0, -47.0, 8.0), True, True),  # 7 m south of it, 8 m above the ground
    ((-70.0, -44.0, 8.0), True, False),  # 4 m south of its cells
    ((-70.0, -10.0, 3.0), False, False),  # 3 m above the map's own ground
    ((-70.0, -10.0, 8.0), False, True),
    ((-94.8, -49.8, -20.0), False, True),  # below the unmapped corner: no verdict
    ((-90.0, -45.0, -20.0), False, False),  # below a mapped cell
    ((-20.0, -30.0, 3.0), False, True),  # outside the map
]


@pytest.mark.parametrize(("p", "static", "free"), MAP_POINTS)
def test_points_near_or_under_an_elevation_map(
    gis: Gis, p: tuple[float, float, float], static: bool, free: bool
) -> None:
    gis.add_elevation_map(block_map())
    assert gis.point_free(p, static=static) is free


MAP_SEGMENTS = [
    # (a, b, static world too, free)
    ((-90.0, -30.0, 8.0), (-50.0, -30.0, 8.0), False, False),  # through the block
    ((-90.0, -30.0, 20.0), (-50.0, -30.0, 20.0), False, True),  # 10 m over it
    ((-90.0, -30.0, 14.0), (-50.0, -30.0, 14.0), False, False),  # 4 m over it
    ((-72.0, -30.0, 3.0), (-68.0, -30.0, 3.0), False, False),  # inside it, far from the surface
    ((-72.0, -30.0, 3.0), (-72.0, -30.0, 3.0), False, False),  # a point inside
    ((-90.0, -47.0, 8.0), (-50.0, -47.0, 8.0), True, True),  # 7 m south of it
    ((-70.0, -10.0, 8.0), (-70.0, -60.0, 30.0), True, False),  # climbing through its corner
]


@pytest.mark.parametrize(("a", "b", "static", "free"), MAP_SEGMENTS)
def test_segments_near_or_through_an_elevation_map(
    gis: Gis,
    a: tuple[float, float, float],
    b: tuple[float, float, float],
    static: bool,
    free: bool,
) -> None:
    gis.add_elevation_map(block_map())
    assert gis.segment_free(a, b, static=static) is free
    assert gis.segment_free(b, a, static=static) is free


def test_polyline_under_a_map_surface_is_not_free(gis: Gis) -> None:
    gis.add_elevation_map(block_map())
    inside = np.stack([np.linspace(-73.0, -67.0, 7), np.full(7, -30.0), np.full(7, 3.0)], axis=1)
    assert not gis.polyline_free(inside)
    above = inside + np.array([0.0, 0.0, 14.0])
    assert gis.polyline_free(above)


def test_elevation_maps_are_replaced_and_removed_by_name(gis: Gis) -> None:
    rev = gis.revision
    inside = (-70.0, -30.0, 3.0)
    assert gis.add_elevation_map(block_map()) == 2 * (40 * 40 - 1)  # two per mapped cell
    assert gis.elevation_map_names == ("scan",) and gis.revision == rev + 1
    assert not gis.point_free(inside, static=False)
    assert gis.runtime_boxes().tolist() == [[-95.0, -50.0, 0.0, -55.0, -10.0, BLOCK_TOP]]
    assert gis.obstacle_names == () and gis.runtime_regions() == ((), ())
    gis.add_elevation_map(block_map("other", east0=50.0))
    assert gis.elevation_map_names == ("scan", "other") and len(gis.runtime_boxes()) == 2
    gis.add_elevation_map(block_map(top=-10.0))  # "scan" again, a pit instead: replaced
    assert gis.elevation_map_names == ("scan", "other") and gis.revision == rev + 3
    assert gis.point_free(inside, static=False)
    gis.remove_elevation_map("scan")
    gis.remove_elevation_map("other")
    assert gis.elevation_map_names == () and gis.revision == rev + 5
    assert len(gis.runtime_boxes()) == 0
    assert gis.segment_free((-90.0, -30.0, 8.0), (-50.0, -30.0, 8.0), static=False)


def test_obstacles_and_maps_share_the_runtime_checks(gis: Gis) -> None:
    square = ((-65.0, 30.0), (-55.0, 30.0), (-55.0, 40.0), (-65.0, 40.0))
    gis.add_obstacle("crane", square, 0.0, 40.0)
    gis.add_elevation_map(block_map())
    gis.remove_obstacle("crane")  # the map stays checked with no obstacle left
    assert not gis.point_free((-70.0, -30.0, 3.0), static=False)
    assert gis.point_free((-60.0, 35.0, 20.0), static=False)
    gis.add_obstacle("crane", square, 0.0, 40.0)
    gis.remove_elevation_map("scan")  # and the obstacle with no map left
    assert not gis.point_free((-60.0, 35.0, 20.0), static=False)
    assert gis.point_free((-70.0, -30.0, 3.0), static=False)


@pytest.mark.parametrize(
    ("call", "error"),
    [
        (lambda g: g.remove_elevation_map("nope"), ConfigError),
        (lambda g: g.add_elevation_map("not a map"), ConfigError),
        (
            lambda g: g.add_elevation_map(
                ElevationMap("x", 0.0, 0.0, 1.0, np.full((2, 2), np.nan))
            ),
            DataError,
        ),
    ],
)
def test_bad_elevation_maps_are_refused(gis: Gis, call, error) -> None:  # type: ignore[no-untyped-def]
    rev = gis.revision
    with pytest.raises(error):
        call(gis)
    assert gis.revision == rev and gis.elevation_map_names == ()
