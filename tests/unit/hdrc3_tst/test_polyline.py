"""Fly-path's polyline passes through every waypoint and stops at the last."""

from __future__ import annotations

import pytest

from hdrc3_tst.errors import TstError
from hdrc3_tst.polyline import polyline


def test_polyline_passes_through_every_point_and_stops_at_the_last() -> None:
    points = [(0.0, 0.0, 30.0), (100.0, 0.0, 30.0), (100.0, 100.0, 40.0), (100.0, 100.0, 40.0)]
    segments = polyline(points, 5.0)
    assert [s.start for s in segments] == points[:2]
    assert segments[-1].end == points[2]
    assert [s.end_velocity for s in segments] == [5.0, 0.0]
    with pytest.raises(TstError):
        polyline([(0.0, 0.0, 1.0)], 5.0)
