"""Coverage: every point of the area within half a footprint of a leg, smooth joins; n platforms
share the area in proportion to their sweep rates; bad areas and fleets answer with a status."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Polygon

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.coverage import (
    OVERLAP,
    CoverageError,
    CoverageStatus,
    Platform,
    footprint_width,
    lawn_mower,
    pair_footprint_width,
    plan_coverage,
    plan_part,
)

AREAS = {
    "rectangle": [(-280, -40), (-160, -40), (-160, 40), (-280, 40)],
    "slanted": [(0, 0), (100, 60), (70, 110), (-30, 50)],
    "triangle": [(0, 0), (150, 0), (0, 90)],
    "L-shape": [(0, 0), (120, 0), (120, 40), (40, 40), (40, 100), (0, 100)],
    "narrow": [(0, 0), (200, 0), (200, 10), (0, 10)],
    "U-shape": [(0, 0), (160, 0), (160, 120), (120, 120), (120, 40), (40, 40), (40, 120), (0, 120)],
}


def uncovered(
    corners: list[tuple[float, float]], segments: list[PathSegment], footprint: float
) -> float:
    """Fraction of the area farther than half a footprint from every leg."""
    legs = [s for s in segments if np.allclose(s.start_direction, s.end_direction)]
    swept = shapely.union_all(
        [LineString([s.start[:2], s.end[:2]]).buffer(footprint / 2 + 0.01) for s in legs]
    )
    area = Polygon(corners)
    return float(area.difference(swept).area / area.area)


def assert_smooth(segments: list[PathSegment], z: float) -> None:
    for a, b in itertools.pairwise(segments):
        assert math.dist(a.end, b.start) < 1e-9
        assert np.allclose(
            np.array(a.end_direction) / np.linalg.norm(a.end_direction),
            np.array(b.start_direction) / np.linalg.norm(b.start_direction),
        )
    assert all(s.start[2] == s.end[2] == z for s in segments)
    assert segments[-1].end_velocity == 0.0
    assert all(s.end_velocity > 0 for s in segments[:-1])


@pytest.mark.parametrize("name", sorted(AREAS))
def test_the_legs_cover_the_area(name: str) -> None:
    footprint = footprint_width(30.0)
    segments = lawn_mower(AREAS[name], 30.0, footprint, 6.0, 3.0)
    assert uncovered(AREAS[name], segments, footprint) < 1e-6
    assert_smooth(segments, 30.0)


def test_neighbouring_legs_overlap_by_at_least_the_overlap() -> None:
    footprint = footprint_width(30.0)
    segments = lawn_mower(AREAS["rectangle"], 30.0, footprint, 6.0, 3.0)
    norths = sorted({round(s.start[1], 6) for s in segments[::2]})
    gaps = np.diff(norths)
    assert len(norths) == 4
    assert np.all(gaps <= footprint * (1 - OVERLAP) + 1e-9)


@pytest.mark.parametrize(
    ("corners", "footprint"),
    [
        ([(0, 0), (10, 10), (0, 10), (10, 0)], 20.0),
        ([(0, 0), (1, 1), (2, 2)], 20.0),
        (AREAS["rectangle"], 0.0),
        (AREAS["rectangle"], math.nan),
    ],
)
def test_bad_areas_and_numbers_are_misuse(
    corners: list[tuple[float, float]], footprint: float
) -> None:
    with pytest.raises(CoverageError):
        lawn_mower(corners, 30.0, footprint, 6.0, 3.0)


def test_footprint_grows_with_altitude() -> None:
    assert footprint_width(30.0) == pytest.approx(2 * 30 * math.tan(math.radians(24)))
    assert footprint_width(60.0) == pytest.approx(2 * footprint_width(30.0))
    assert pair_footprint_width(40.0) == pytest.approx(2 * 40 * math.tan(math.radians(12.5)))


FLEETS = {
    1: [Platform("uav0", footprint_width(40.0), 8.0, (-300.0, -100.0))],
    2: [
        Platform("uav0", footprint_width(40.0), 8.0, (-300.0, -100.0)),
        Platform("uav1", footprint_width(30.0), 5.0, (200.0, 150.0)),
    ],
    3: [
        Platform("uav0", footprint_width(40.0), 8.0, (-300.0, -100.0)),
        Platform("uav1", footprint_width(30.0), 5.0, (200.0, 150.0)),
        Platform("uav2", footprint_width(50.0), 10.0, (0.0, 300.0)),
    ],
}


@pytest.mark.parametrize("name", ["rectangle", "L-shape", "U-shape", "slanted"])
@pytest.mark.parametrize("n", sorted(FLEETS))
def test_n_platforms_cover_the_area_with_balanced_shares(name: str, n: int) -> None:
    corners = AREAS[name]
    area = Polygon(corners)
    plan = plan_coverage(corners, FLEETS[n], 40.0)
    assert plan.status is CoverageStatus.PLANNED, plan.reason
    assert [a.platform.name for a in plan.assignments] == [p.name for p in FLEETS[n]]
    total_rate = sum(p.sweep_rate for p in FLEETS[n])
    swept = []
    for a in plan.assignments:
        segments = list(a.segments)
        assert_smooth(segments, 40.0)
        # the part is this platform's share of the area, and its own legs cover it entirely
        assert a.part.area / area.area == pytest.approx(
            a.platform.sweep_rate / total_rate, rel=1e-3
        )
        legs = [s for s in segments if np.allclose(s.start_direction, s.end_direction)]
        reach = shapely.union_all(
            [
                LineString([s.start[:2], s.end[:2]]).buffer(a.platform.footprint / 2 + 0.01)
                for s in legs
            ]
        )
        assert a.part.difference(reach).area < 1e-6 * area.area
        swept.append(reach)
        assert a.segments[0].start[:2] == pytest.approx(
            np.add(a.platform.start, 0.0), abs=a.transit + 1e-6
        )
    assert area.difference(shapely.union_all(swept)).area < 0.01 * area.area
    assert sum(a.part.area for a in plan.assignments) == pytest.approx(area.area, rel=1e-6)


def test_the_makespan_shrinks_with_more_platforms_and_sweep_times_are_balanced() -> None:
    corners = [(0, 0), (600, 0), (600, 400), (0, 400)]
    spans = [plan_coverage(corners, FLEETS[n], 40.0).makespan for n in (1, 2, 3)]
    assert spans[0] > spans[1] > spans[2]
    plan = plan_coverage(corners, FLEETS[2], 40.0)
    sweeps = [a.duration - a.transit / a.platform.speed for a in plan.assignments]
    assert max(sweeps) / min(sweeps) < 1.25  # turns and the last partial legs differ


def test_each_platform_starts_at_the_corner_nearest_to_it() -> None:
    corners = [(0, 0), (400, 0), (400, 200), (0, 200)]
    fleet = [
        Platform("west", footprint_width(40.0), 8.0, (-100.0, 100.0)),
        Platform("east", footprint_width(40.0), 8.0, (500.0, 100.0)),
    ]
    plan = plan_coverage(corners, fleet, 40.0)
    west, east = plan.assignments
    assert west.segments[0].start[0] < 50.0
    assert east.segments[0].start[0] > 350.0


@pytest.mark.parametrize(
    ("corners", "fleet", "altitude", "bounds", "status"),
    [
        (AREAS["rectangle"], [], 40.0, None, CoverageStatus.NO_PLATFORMS),
        (
            AREAS["rectangle"],
            [Platform("a", 0.0, 5.0, (0, 0))],
            40.0,
            None,
            CoverageStatus.BAD_PLATFORM,
        ),
        (
            AREAS["rectangle"],
            [Platform("a", 20.0, math.nan, (0, 0))],
            40.0,
            None,
            CoverageStatus.BAD_PLATFORM,
        ),
        (
            AREAS["rectangle"],
            [Platform("a", 20.0, 5.0, (math.inf, 0))],
            40.0,
            None,
            CoverageStatus.BAD_PLATFORM,
        ),
        (AREAS["rectangle"], FLEETS[1] * 2, 40.0, None, CoverageStatus.BAD_PLATFORM),  # same name
        (AREAS["rectangle"], FLEETS[1], math.nan, None, CoverageStatus.BAD_NUMBERS),
        ([(0, 0), (10, 10), (0, 10), (10, 0)], FLEETS[1], 40.0, None, CoverageStatus.INVALID_AREA),
        ([(0, 0), (1, 1), (2, 2)], FLEETS[1], 40.0, None, CoverageStatus.INVALID_AREA),
        ([(0, 0), (1, 1)], FLEETS[1], 40.0, None, CoverageStatus.INVALID_AREA),
        ([(0, 0), (math.nan, 1), (2, 0)], FLEETS[1], 40.0, None, CoverageStatus.INVALID_AREA),
        (
            AREAS["rectangle"],
            FLEETS[1],
            40.0,
            (-250.0, -500.0, 500.0, 500.0),
            CoverageStatus.OUTSIDE_WORLD,
        ),
        (
            AREAS["rectangle"],
            FLEETS[1],
            40.0,
            (-500.0, -500.0, 500.0, 500.0),
            CoverageStatus.PLANNED,
        ),
    ],
)
def test_bad_requests_answer_with_a_status(
    corners: list[tuple[float, float]],
    fleet: list[Platform],
    altitude: float,
    bounds: tuple[float, float, float, float] | None,
    status: CoverageStatus,
) -> None:
    plan = plan_coverage(corners, fleet, altitude, bounds=bounds)
    assert plan.status is status
    assert bool(plan.reason) == (status is not CoverageStatus.PLANNED)


@pytest.mark.parametrize("name", ["rectangle", "L-shape", "slanted"])
@pytest.mark.parametrize("parts", [1, 2, 3])
def test_parts_planned_apart_agree_on_the_split_and_cover_the_area(name: str, parts: int) -> None:
    corners, area = AREAS[name], Polygon(AREAS[name])
    footprint = pair_footprint_width(30.0)
    starts = [(-300.0, -100.0), (200.0, 150.0), (0.0, 300.0)]
    plans = [
        plan_part(corners, k, parts, Platform(f"uav{k}", footprint, 6.0, starts[k - 1]), 30.0)
        for k in range(1, parts + 1)
    ]
    assert all(p.status is CoverageStatus.PLANNED for p in plans), [p.reason for p in plans]
    bands = [p.assignments[0].part for p in plans]
    for a, b in itertools.combinations(bands, 2):
        assert a.intersection(b).area < 1e-6 * area.area  # each aircraft its own band
    assert shapely.union_all(bands).symmetric_difference(area).area < 1e-6 * area.area
    for k, plan in enumerate(plans):
        # the same band whatever the aircraft's start: only the entry corner follows it
        elsewhere = Platform("x", footprint, 6.0, (1000.0, -1000.0))
        again = plan_part(corners, k + 1, parts, elsewhere, 30.0).assignments[0]
        assert again.part.equals(plan.assignments[0].part)
        assert plan.assignments[0].platform.name == f"uav{k + 1}"


@pytest.mark.parametrize(
    ("part", "parts", "corners", "status"),
    [
        (0, 2, AREAS["rectangle"], CoverageStatus.BAD_NUMBERS),
        (3, 2, AREAS["rectangle"], CoverageStatus.BAD_NUMBERS),
        (1, 2, [(0, 0), (10, 10), (10, 0), (0, 10)], CoverageStatus.INVALID_AREA),
    ],
)
def test_a_bad_part_answers_with_a_status(
    part: int, parts: int, corners: list[tuple[float, float]], status: CoverageStatus
) -> None:
    me = Platform("uav0", 10.0, 5.0, (0.0, 0.0))
    assert plan_part(corners, part, parts, me, 30.0).status is status
