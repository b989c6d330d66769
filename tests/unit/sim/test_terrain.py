"""Terrain grid: bilinear interpolation, clamping, vectorised queries, validation."""

from __future__ import annotations

import numpy as np
import pytest

from sim.terrain import Terrain

GRID = Terrain(-10.0, -10.0, 10.0, ((0.0, 1.0, 2.0), (2.0, 3.0, 4.0), (4.0, 5.0, 8.0)))


@pytest.mark.parametrize(
    ("east", "north", "expected"),
    [
        (-10.0, -10.0, 0.0),  # grid nodes
        (0.0, 0.0, 3.0),
        (10.0, 10.0, 8.0),
        (-5.0, -10.0, 0.5),  # along the south edge
        (-10.0, -5.0, 1.0),  # along the west edge
        (-5.0, -5.0, 1.5),  # cell centre: mean of the four corners
        (5.0, 5.0, 5.0),  # (3 + 4 + 5 + 8) / 4
        (-100.0, -100.0, 0.0),  # clamped beyond the grid
        (100.0, 0.0, 4.0),
    ],
)
def test_bilinear_height(east: float, north: float, expected: float) -> None:
    assert GRID.height(east, north) == pytest.approx(expected)


def test_vectorised_heights_match_scalar() -> None:
    rng = np.random.default_rng(3)
    east = rng.uniform(-15.0, 15.0, 200)
    north = rng.uniform(-15.0, 15.0, 200)
    expected = [GRID.height(e, n) for e, n in zip(east, north, strict=True)]
    assert np.allclose(GRID.heights_at(east, north), expected)


def test_bounds_and_contains() -> None:
    assert GRID.bounds == (-10.0, -10.0, 10.0, 10.0)
    assert GRID.contains(0.0, 10.0) and not GRID.contains(0.0, 10.1)
    assert Terrain.flat(0.0, 0.0, 50.0, 20.0).height(25.0, 10.0) == 0.0


@pytest.mark.parametrize(
    ("spacing", "heights"),
    [
        (0.0, ((0.0, 0.0), (0.0, 0.0))),
        (1.0, ((0.0,),)),
        (1.0, ((0.0, 0.0), (0.0,))),
        (1.0, ((0.0, float("nan")), (0.0, 0.0))),
    ],
)
def test_invalid_grids_are_rejected(spacing: float, heights: tuple[tuple[float, ...], ...]) -> None:
    with pytest.raises(ValueError):
        Terrain(0.0, 0.0, spacing, heights)
