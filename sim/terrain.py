"""Terrain elevation: a coarse regular grid with bilinear interpolation.

The grid is data from the world file (gentle slopes, no cliffs); heights are metres in the
world's local up axis, i.e. relative to the geodetic origin's altitude.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, slots=True)
class Terrain:
    """Elevation grid: ``heights[row][col]`` at (east0 + col*spacing, north0 + row*spacing).

    Row 0 is the southernmost row. Queries outside the grid clamp to the border value, so the
    terrain continues flat beyond its extent instead of failing.
    """

    east0: float
    north0: float
    spacing: float
    heights: tuple[tuple[float, ...], ...]
    _grid: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _last_col: int = field(init=False, repr=False, compare=False)
    """cols - 1 and rows - 1, kept for :meth:`height` (called ~4 times per 5 ms physics step
    by the payload's ground planes; the two properties cost a third of it)."""
    _last_row: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Check the grid shape and values."""
        if not (math.isfinite(self.spacing) and self.spacing > 0.0):
            raise ValueError(f"terrain spacing must be > 0, got {self.spacing}")
        if len(self.heights) < 2 or any(len(r) != len(self.heights[0]) for r in self.heights):
            raise ValueError("terrain heights must be a rectangular grid of at least 2x2")
        if len(self.heights[0]) < 2:
            raise ValueError("terrain heights must be a rectangular grid of at least 2x2")
        if not all(math.isfinite(h) for row in self.heights for h in row):
            raise ValueError("terrain heights must be finite")
        # Cached array for vectorised queries (the tuples keep the dataclass hashable).
        grid = np.asarray(self.heights, dtype=np.float64)
        grid.setflags(write=False)
        object.__setattr__(self, "_grid", grid)
        object.__setattr__(self, "_last_col", len(self.heights[0]) - 1)
        object.__setattr__(self, "_last_row", len(self.heights) - 1)

    @staticmethod
    def flat(east0: float, north0: float, east1: float, north1: float) -> Terrain:
        """Make a flat terrain at height 0 covering a rectangle."""
        spacing = max(east1 - east0, north1 - north0)
        return Terrain(east0, north0, spacing, ((0.0, 0.0), (0.0, 0.0)))

    @property
    def rows(self) -> int:
        """Number of grid rows (north direction)."""
        return len(self.heights)

    @property
    def cols(self) -> int:
        """Number of grid columns (east direction)."""
        return len(self.heights[0])

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(east_min, north_min, east_max, north_max) of the grid."""
        return (
            self.east0,
            self.north0,
            self.east0 + (self.cols - 1) * self.spacing,
            self.north0 + (self.rows - 1) * self.spacing,
        )

    def contains(self, east: float, north: float) -> bool:
        """Tell whether (east, north) lies on the grid (borders included)."""
        e0, n0, e1, n1 = self.bounds
        return e0 <= east <= e1 and n0 <= north <= n1

    def array(self) -> NDArray[np.float64]:
        """Return the grid as a read-only (rows, cols) float array."""
        return self._grid

    def height(self, east: float, north: float) -> float:
        """Terrain height at a point, bilinear between the four surrounding grid nodes."""
        last_col, last_row = self._last_col, self._last_row
        x = min(max((east - self.east0) / self.spacing, 0.0), float(last_col))
        y = min(max((north - self.north0) / self.spacing, 0.0), float(last_row))
        c = min(int(x), last_col - 1)
        r = min(int(y), last_row - 1)
        fx, fy = x - c, y - r
        h = self.heights
        south = h[r][c] * (1.0 - fx) + h[r][c + 1] * fx
        north_ = h[r + 1][c] * (1.0 - fx) + h[r + 1][c + 1] * fx
        return south * (1.0 - fy) + north_ * fy

    def heights_at(
        self, east: NDArray[np.float64], north: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Vectorised :meth:`height` for arrays of points (same shape)."""
        grid = self._grid
        x = np.clip((np.asarray(east) - self.east0) / self.spacing, 0.0, self.cols - 1.0)
        y = np.clip((np.asarray(north) - self.north0) / self.spacing, 0.0, self.rows - 1.0)
        c = np.minimum(x.astype(np.int64), self.cols - 2)
        r = np.minimum(y.astype(np.int64), self.rows - 2)
        fx, fy = x - c, y - r
        south = grid[r, c] * (1.0 - fx) + grid[r, c + 1] * fx
        north_ = grid[r + 1, c] * (1.0 - fx) + grid[r + 1, c + 1] * fx
        result: NDArray[np.float64] = south * (1.0 - fy) + north_ * fy
        return result
