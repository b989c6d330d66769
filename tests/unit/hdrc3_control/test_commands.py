"""Horizontal vectors between ENU and the frame of the aircraft's nose."""

from __future__ import annotations

import math

import pytest

from hdrc3_control.commands import from_heading_frame, to_heading_frame


@pytest.mark.parametrize(
    ("east", "north", "heading", "forward", "right"),
    [
        (0.0, 1.0, 0.0, 1.0, 0.0),  # nose north: north is ahead
        (1.0, 0.0, 0.0, 0.0, 1.0),  # nose north: east is to the right
        (1.0, 0.0, math.pi / 2, 1.0, 0.0),  # nose east: east is ahead
        (0.0, 1.0, math.pi / 2, 0.0, -1.0),  # nose east: north is to the left
        (-2.0, 0.0, math.pi, 0.0, 2.0),  # nose south: west is to the right
    ],
)
def test_heading_frame_both_ways(
    east: float, north: float, heading: float, forward: float, right: float
) -> None:
    assert to_heading_frame(east, north, heading) == pytest.approx((forward, right), abs=1e-12)
    assert from_heading_frame(forward, right, heading) == pytest.approx((east, north), abs=1e-12)
