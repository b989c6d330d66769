"""Coverage patterns: every point of the area within half a footprint of a leg; smooth joins."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Polygon

from hdrc3_tst.coverage import OVERLAP, footprint_width, lawn_mower, polyline
from hdrc3_tst.errors import TstError

AREAS = {
    "rectangle": [(-280, -40), (-160, -40), (-160, 40), (-280, 40)],
    "slanted": [(0, 0), (100, 60), (70, 110), (-30, 50)],
    "triangle": [(0, 0), (150, 0), (0, 90)],
    "L-shape": [(0, 0), (120, 0), (120, 40), (40, 40), (40, 100), (0, 100)],
    "narrow": [(0, 0), (200, 0), (200, 10), (0, 10)],
}


@pytest.mark.parametrize("name", sorted(AREAS))
def test_the_legs_cover_the_area(name: str) -> None:
    corners = AREAS[name]
    footprint = footprint_width(30.0)
    segments = lawn_mower(corners, 30.0, footprint, 6.0, 3.0)
    legs = [s for i, s in enumerate(segments) if i % 2 == 0]
    swept = shapely.union_all(
        [LineString([s.start[:2], s.end[:2]]).buffer(footprint / 2 + 0.5) for s in legs]
    )
    area = Polygon(corners)
    assert area.difference(swept).area < 0.01 * area.area
    for a, b in itertools.pairwise(segments):
        assert math.dist(a.end, b.start) < 1e-9
        assert np.allclose(
            np.array(a.end_direction) / np.linalg.norm(a.end_direction),
            np.array(b.start_direction) / np.linalg.norm(b.start_direction),
        )
    assert all(s.start[2] == s.end[2] == 30.0 for s in segments)
    assert segments[-1].end_velocity == 0.0
    assert all(s.end_velocity > 0 for s in segments[:-1])


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
    with pytest.raises(TstError):
        lawn_mower(corners, 30.0, footprint, 6.0, 3.0)


def test_footprint_grows_with_altitude() -> None:
    assert footprint_width(30.0) == pytest.approx(2 * 30 * math.tan(math.radians(24)))
    assert footprint_width(60.0) == pytest.approx(2 * footprint_width(30.0))


def test_polyline_passes_through_every_point_and_stops_at_the_last() -> None:
    points = [(0.0, 0.0, 30.0), (100.0, 0.0, 30.0), (100.0, 100.0, 40.0), (100.0, 100.0, 40.0)]
    segments = polyline(points, 5.0)
    assert [s.start for s in segments] == points[:2]
    assert segments[-1].end == points[2]
    assert [s.end_velocity for s in segments] == [5.0, 0.0]
    with pytest.raises(TstError):
        polyline([(0.0, 0.0, 1.0)], 5.0)
