"""The world's derived geometry: the top surface that a laser map is compared with."""

from __future__ import annotations

import numpy as np
import pytest

from tests.unit.sim.test_world_geometry import SLOPE, WORLD  # a slope, a box, trees


@pytest.mark.parametrize(
    ("east", "north", "top"),
    [
        (5.0, 5.0, 15.0),  # the box's roof (base 5, 10 high)
        (35.0, 0.0, 8.0 + SLOPE.height(35.0, 0.0)),  # canopy above the ground at the centroid
        (35.0, 4.0, 8.0 + SLOPE.height(35.0, 0.0)),  # a flat canopy on the slope
        (20.0, 50.0, SLOPE.height(20.0, 50.0)),  # bare ground
    ],
)
def test_surface_heights_are_the_top_of_whatever_stands_there(
    east: float, north: float, top: float
) -> None:
    got = WORLD.surface_heights(np.array([[east, east]]), np.array([[north, north]]))
    assert got.shape == (1, 2)
    assert got == pytest.approx(top)


def test_vegetation_stands_on_the_ground_at_its_centroid() -> None:
    (trees,) = WORLD.vegetation
    base, top = WORLD.vegetation_top(trees)
    assert (base, top) == pytest.approx((SLOPE.height(35.0, 0.0), SLOPE.height(35.0, 0.0) + 8.0))
