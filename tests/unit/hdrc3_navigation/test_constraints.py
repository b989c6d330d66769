from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_navigation.constraints import ConstraintChecker, Constraints
from hdrc3_navigation.gis import Gis, Zone
from sim.world import World

BOX = ((-50.0, -10.0), (-30.0, -10.0), (-30.0, 10.0), (-50.0, 10.0))


@pytest.fixture
def gis(small_world: World) -> Gis:
    return Gis(small_world)


@pytest.mark.parametrize(
    ("constraints", "problem"),
    [
        (Constraints(), None),
        (Constraints(min_altitude=20.0, max_altitude=10.0), "above max altitude"),
        (Constraints(max_climb_rate=0.0), "max_climb_rate must be > 0"),
        (Constraints(max_descent_rate=math.inf), "max_descent_rate must be finite"),
        (Constraints(no_fly=(((0.0, 0.0), (1.0, 0.0)),)), "at least 3"),
        (Constraints(no_fly=(((0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)),)), "self-inter"),
    ],
)
def test_inconsistent_constraints_are_named(constraints: Constraints, problem: str | None) -> None:
    problems = constraints.problems()
    if problem is None:
        assert problems == []
    else:
        assert len(problems) == 1 and problem in problems[0]


POINTS = [
    (Constraints(), (-40.0, 0.0, 10.0), True),
    (Constraints(no_fly=(BOX,)), (-40.0, 0.0, 10.0), False),
    (Constraints(no_fly=(BOX,)), (-25.0, 0.0, 10.0), False),  # within the margin of the box
    (Constraints(no_fly=(BOX,)), (-23.0, 0.0, 10.0), True),
    (Constraints(min_altitude=12.0), (-40.0, 0.0, 10.0), False),
    (Constraints(max_altitude=8.0), (-40.0, 0.0, 10.0), False),
    (Constraints(), (65.0, -65.0, 100.0), False),  # the world's zone reaches 150 m
    (Constraints(), (65.0, -65.0, 160.0), True),
]


@pytest.mark.parametrize(("constraints", "p", "ok"), POINTS)
def test_configurations(gis: Gis, constraints: Constraints, p, ok: bool) -> None:  # type: ignore[no-untyped-def]
    checker = ConstraintChecker(gis, constraints, 10.0)
    assert checker.point_ok(p) is ok
    assert bool(checker.points_ok(np.array([p]))[0]) is ok


EDGES = [
    (Constraints(no_fly=(BOX,)), (-60.0, 0.0, 10.0), (-20.0, 0.0, 10.0), False),
    (Constraints(no_fly=(BOX,)), (-60.0, 30.0, 10.0), (-20.0, 30.0, 10.0), True),
    (Constraints(max_climb_rate=2.0), (-60.0, 0.0, 10.0), (-20.0, 0.0, 20.0), False),  # 2.4 m/s
    (Constraints(max_climb_rate=3.0), (-60.0, 0.0, 10.0), (-20.0, 0.0, 20.0), True),
    (Constraints(max_climb_rate=2.0), (-20.0, 0.0, 20.0), (-60.0, 0.0, 10.0), True),  # descends
    (Constraints(max_descent_rate=2.0), (-20.0, 0.0, 20.0), (-60.0, 0.0, 10.0), False),
    (Constraints(max_altitude=15.0), (-60.0, 0.0, 10.0), (-20.0, 0.0, 20.0), False),
    (Constraints(min_altitude=15.0), (-60.0, 0.0, 10.0), (-20.0, 0.0, 20.0), False),
]


@pytest.mark.parametrize(("constraints", "a", "b", "ok"), EDGES)
def test_straight_pieces(gis: Gis, constraints: Constraints, a, b, ok: bool) -> None:  # type: ignore[no-untyped-def]
    checker = ConstraintChecker(gis, constraints, 10.0)
    assert checker.polyline_ok(np.array([a, b])) is ok
    fwd, bwd = checker.edges_ok(np.array([a]), np.array([b]))
    assert bool(fwd[0]) is ok
    assert bool(bwd[0]) is checker.polyline_ok(np.array([b, a]))


def test_a_zone_band_is_entered_only_where_the_piece_is_inside_the_band(gis: Gis) -> None:
    gis.add_no_fly_zone(Zone("band", BOX, 20.0, 30.0))
    checker = ConstraintChecker(gis, Constraints(), 10.0)
    # climbs steeply through the box's column: below the band inside the footprint, above it after
    below_then_above = np.array([(-60.0, 0.0, 5.0), (-20.0, 0.0, 60.0)])
    assert not checker.polyline_ok(below_then_above)  # crosses the band over the footprint
    under = np.array([(-60.0, 0.0, 5.0), (-20.0, 0.0, 8.0)])
    assert checker.polyline_ok(under)


def test_vectorised_and_scalar_tests_agree(gis: Gis) -> None:
    rng = np.random.default_rng(3)
    c = Constraints(
        min_altitude=5.0, max_altitude=50.0, max_climb_rate=3.0, max_descent_rate=2.0, no_fly=(BOX,)
    )
    checker = ConstraintChecker(gis, c, 10.0)
    a = rng.uniform((-100, -100, 0), (100, 100, 60), (400, 3))
    b = a + rng.normal(0.0, 25.0, (400, 3))
    cache: dict[bytes, np.ndarray] = {}  # type: ignore[type-arg]
    for _ in range(2):  # the second time with the zone's crossings from the cache
        vec, back = checker.edges_ok(a, b, zone_cache=cache)
        assert list(vec) == [
            checker.polyline_ok(np.array([p, q])) for p, q in zip(a, b, strict=True)
        ]
        assert list(back) == [
            checker.polyline_ok(np.array([q, p])) for p, q in zip(a, b, strict=True)
        ]
        assert len(cache) == 2  # the world's zone and BOX
    assert 0 < vec.sum() < len(vec)
    pts = checker.points_ok(a)
    assert list(pts) == [checker.point_ok(p) for p in a]
