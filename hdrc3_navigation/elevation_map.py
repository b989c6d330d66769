"""An elevation map as the GIS keeps it (chapter sections 7 and 11.2): a 1 m grid, triangulated.

The laser mapper (:mod:`hdrc3_perception.laser_mapping`) samples its point cloud into a regular
grid, one height per cell; the chapter then "constructs a set of triangles in order to represent
the elevation" (§11.2, Figure 40). Here two triangles cover each mapped cell between its corners,
each corner at the highest mapped cell around it: a solid is never smaller than its cells (a
planner's margin then holds from every mapped cell), and an unmapped cell is a hole, not a guess.

:meth:`ElevationMap.compare` overlays the map with an existing model (Figure 41a): cells that rose
or fell by more than a threshold, cleaned of one-cell-wide seams (a grid of horizontal position
error draws those along every wall) by a 2 x 2 morphological opening, grouped into connected
regions (``scipy.ndimage``).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from hdrc3_base.errors import DataError

HeightsFn = Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]
"""Model surface height (m, local up) at arrays of (east, north)."""
TRUNCATE = 2.0
"""m: height differences beyond this count as this much when a map is fitted to a model."""
MAX_CELLS = 4_000_000
"""Largest map accepted (2 km x 2 km at 1 m)."""


class ChangeKind(enum.Enum):
    """How the surface differs from the existing model."""

    NEW = "new"
    """Higher than the model: something built or grown (a container, vegetation)."""
    REMOVED = "removed"
    """Lower than the model: something torn down or cut."""


@dataclass(frozen=True, slots=True)
class MapChange:
    """One connected region where the map and the model disagree."""

    kind: ChangeKind
    cells: int
    area: float
    """m^2."""
    centre: tuple[float, float]
    """(east, north) of the region's centroid, m."""
    bounds: tuple[float, float, float, float]
    """(east min, north min, east max, north max) of the region's cells, m."""
    height: float
    """Largest difference map - model in the region (negative for REMOVED), m."""


@dataclass(frozen=True, slots=True)
class Alignment:
    """How far a map was moved onto a model (:meth:`ElevationMap.aligned_to`)."""

    east: float
    north: float
    up: float
    """m subtracted from the map's positions and heights: the navigation error it carried."""
    misfit_before: float
    misfit_after: float
    """Mean truncated height difference to the model before and after, m."""


@dataclass(frozen=True, slots=True)
class MapScore:
    """A map's height error against a reference surface (:meth:`ElevationMap.score`)."""

    cells: int
    rms: float
    """m, over every mapped cell."""
    p95: float
    """m, 95th percentile of the absolute error over every mapped cell."""
    away_cells: int
    """Mapped cells at least ``distance`` m from a step of the reference surface."""
    away_rms: float
    """m, over those cells (NaN if none)."""


@dataclass(frozen=True, eq=False)
class ElevationMap:
    """A named height grid (rows south to north, columns west to east; NaN = unmapped).

    Raises:
        DataError: A malformed map (non-positive or non-finite resolution or origin, a heights
            array that is not 2-D, too large, or holding infinities).

    """

    name: str
    east0: float
    north0: float
    resolution: float
    heights: NDArray[np.float64]
    returns: NDArray[np.int64] = field(default_factory=lambda: np.zeros((0, 0), dtype=np.int64))
    """Laser returns per cell (empty: not known)."""

    def __post_init__(self) -> None:
        """Validate and freeze the arrays."""
        if not self.name or len(self.name) > 64 or not self.name.isprintable():
            raise DataError(f"elevation map name must be 1-64 printable characters: {self.name!r}")
        if not (math.isfinite(self.east0) and math.isfinite(self.north0)):
            raise DataError("elevation map origin must be finite")
        if not (math.isfinite(self.resolution) and 0.05 <= self.resolution <= 100.0):
            raise DataError(f"resolution must be within [0.05, 100] m, got {self.resolution}")
        heights = np.array(self.heights, dtype=np.float64)  # a copy: the caller keeps theirs
        if heights.ndim != 2 or heights.size == 0 or heights.size > MAX_CELLS:
            raise DataError(f"heights must be a non-empty 2-D grid of at most {MAX_CELLS} cells")
        if np.isinf(heights).any():
            raise DataError("heights must be finite or NaN (unmapped)")
        returns = np.array(self.returns, dtype=np.int64)
        if returns.size and returns.shape != heights.shape:
            raise DataError(f"returns {returns.shape} must match heights {heights.shape}")
        heights.setflags(write=False)
        returns.setflags(write=False)
        object.__setattr__(self, "heights", heights)
        object.__setattr__(self, "returns", returns)

    @property
    def rows(self) -> int:
        """Cells from south to north."""
        return int(self.heights.shape[0])

    @property
    def columns(self) -> int:
        """Cells from west to east."""
        return int(self.heights.shape[1])

    @property
    def mapped(self) -> NDArray[np.bool_]:
        """Which cells hold a height."""
        return ~np.isnan(self.heights)

    def centres(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """East and north of every cell centre (rows x columns each)."""
        east = self.east0 + (np.arange(self.columns) + 0.5) * self.resolution
        north = self.north0 + (np.arange(self.rows) + 0.5) * self.resolution
        grid_e, grid_n = np.meshgrid(east, north)
        return grid_e, grid_n

    def heights_at(
        self, east: NDArray[np.float64], north: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Height of the cell holding each point (NaN outside the map or unmapped)."""
        col = np.floor((np.asarray(east) - self.east0) / self.resolution)
        row = np.floor((np.asarray(north) - self.north0) / self.resolution)
        inside = (col >= 0) & (col < self.columns) & (row >= 0) & (row < self.rows)
        out = np.full(np.shape(col), np.nan)
        out[inside] = self.heights[row[inside].astype(int), col[inside].astype(int)]
        return out

    def aligned_to(
        self, model: HeightsFn, search: float = 6.0, step: float = 0.25
    ) -> tuple[ElevationMap, Alignment]:
        """The map moved onto the model by the shift that fits it best (a map-to-model match).

        A map carries the navigation solution's error: GPS offsets of metres move every return
        alike. The shift is searched on a ``step`` grid within ``search`` m east and north; the
        fit is the mean of ``|map - model - dz|`` truncated at ``TRUNCATE`` m, with ``dz`` the
        median difference, so what really changed (or a wall's edge cells) weighs no more than
        a few metres. The model is sampled once on a ``step`` raster and shifted by indexing.

        Args:
            model: The existing model's surface height.
            search: Largest shift tried east and north, m.
            step: Shift resolution, m.

        Returns:
            The moved map and the shift it was moved by.

        """
        if not (math.isfinite(search) and math.isfinite(step) and 0.0 < step <= search <= 50.0):
            raise DataError(f"need 0 < step <= search <= 50 m, got {step}, {search}")
        rows, cols = np.nonzero(self.mapped)
        heights = self.heights[rows, cols]
        pad = math.ceil(search / step)
        scale = round(self.resolution / step)
        if not math.isclose(scale * step, self.resolution):
            raise DataError(f"step {step} m must divide the resolution {self.resolution} m")
        # raster sample (i, j) lies (j - pad) steps east of the centre of cell (0, 0)
        n_rows, n_cols = self.rows * scale + 2 * pad, self.columns * scale + 2 * pad
        half = self.resolution / 2.0
        east = self.east0 + half + (np.arange(n_cols) - pad) * step
        north = self.north0 + half + (np.arange(n_rows) - pad) * step
        raster = np.asarray(model(*np.meshgrid(east, north)), dtype=np.float64)
        base_r, base_c = rows * scale + pad, cols * scale + pad
        best: tuple[float, int, int, float] | None = None
        before = 0.0
        for di in range(-pad, pad + 1):
            for dj in range(-pad, pad + 1):
                diff = heights - raster[base_r - di, base_c - dj]
                dz = float(np.median(diff))
                misfit = float(np.minimum(np.abs(diff - dz), TRUNCATE).mean())
                if di == 0 and dj == 0:
                    before = misfit
                if best is None or misfit < best[0]:
                    best = (misfit, di, dj, dz)
        assert best is not None
        misfit, di, dj, dz = best
        moved = ElevationMap(
            self.name,
            self.east0 - dj * step,
            self.north0 - di * step,
            self.resolution,
            self.heights - dz,
            self.returns,
        )
        return moved, Alignment(dj * step, di * step, dz, before, misfit)

    def cell_tops(self, surface: HeightsFn, samples: int = 4) -> NDArray[np.float64]:
        """The highest point of ``surface`` within each cell (``samples`` x ``samples`` points).

        What a cell of a laser map should hold (the top surface a planner must clear): the
        reference to score a map against.
        """
        east, north = self.centres()
        offsets = ((np.arange(samples) + 0.5) / samples - 0.5) * self.resolution
        tops = np.full(east.shape, -np.inf)
        for dx in offsets:
            for dy in offsets:
                tops = np.maximum(tops, np.asarray(surface(east + dx, north + dy)))
        return tops

    def score(self, surface: HeightsFn, step: float = 1.0, distance: float = 2.0) -> MapScore:
        """Height error of the mapped cells against :meth:`cell_tops` of a reference surface.

        Also on the cells at least ``distance`` m from a step of the reference (a cell whose
        3 x 3 neighbourhood spans more than ``step`` m): a wall's neighbours take the roof's
        height when the map is off by a metre, which the RMS over all cells is dominated by.
        """
        reference = self.cell_tops(surface)
        error = self.heights - reference
        spans = ndimage.maximum_filter(reference, 3) - ndimage.minimum_filter(reference, 3)
        away = ndimage.distance_transform_edt(spans <= step) * self.resolution >= distance
        mapped = self.mapped
        far = error[mapped & away]
        every = error[mapped]
        return MapScore(
            int(mapped.sum()),
            float(np.sqrt(np.mean(every**2))) if every.size else math.nan,
            float(np.percentile(np.abs(every), 95)) if every.size else math.nan,
            int(far.size),
            float(np.sqrt(np.mean(far**2))) if far.size else math.nan,
        )

    def triangles(self) -> tuple[NDArray[np.float64], NDArray[np.int32]]:
        """The triangulated surface: vertices (k x 3, cell corners) and faces (m x 3 indices).

        Two triangles over each mapped cell, between its four corners; a corner stands at the
        highest of the mapped cells around it. A cell is thus covered at its own height (a roof
        reaches the roof cell's edge) and the surface slopes down within the lower neighbour:
        the solid is never smaller than the cells that hold it, only up to a cell larger.
        """
        mapped = self.mapped
        rows, cols = self.heights.shape
        padded = np.full((rows + 2, cols + 2), -np.inf)
        padded[1:-1, 1:-1] = np.where(mapped, self.heights, -np.inf)
        corner = np.maximum.reduce(
            [padded[:-1, :-1], padded[:-1, 1:], padded[1:, :-1], padded[1:, 1:]]
        )  # (rows + 1) x (cols + 1): corner (i, j) is the south-west corner of cell (i, j)
        used = np.isfinite(corner)
        index = np.full(corner.shape, -1, dtype=np.int64)
        index[used] = np.arange(int(used.sum()))
        east = self.east0 + np.arange(cols + 1) * self.resolution
        north = self.north0 + np.arange(rows + 1) * self.resolution
        grid_e, grid_n = np.meshgrid(east, north)
        vertices = np.column_stack([grid_e[used], grid_n[used], corner[used]])
        a, b = index[:-1, :-1][mapped], index[:-1, 1:][mapped]  # south-west, south-east
        c, d = index[1:, :-1][mapped], index[1:, 1:][mapped]  # north-west, north-east
        faces = np.vstack([np.column_stack([a, b, d]), np.column_stack([a, d, c])])
        return vertices, faces.astype(np.int32)

    def compare(
        self,
        model: HeightsFn,
        threshold: float = 1.5,
        min_area: float = 4.0,
        tolerance: float = 2.0,
    ) -> tuple[MapChange, ...]:
        """Regions where the map differs from the model by more than ``threshold`` m.

        A cell is higher than the model when it rises above the model's highest point within
        ``tolerance`` m, and lower when it sinks below the lowest: a map a metre or two off
        along a wall (navigation error, the attitude error at long range) is not a change.

        Args:
            model: The existing model's surface height.
            threshold: Smallest height difference that counts, m.
            min_area: Smallest region reported, m^2.
            tolerance: Horizontal distance within which the map may be off, m.

        Returns:
            The changes, largest first.

        """
        size = 2 * math.ceil(tolerance / self.resolution) + 1
        tops = self.cell_tops(model)
        above = self.heights - ndimage.maximum_filter(tops, size, mode="nearest")
        below = self.heights - ndimage.minimum_filter(tops, size, mode="nearest")
        grid_e, grid_n = self.centres()
        diff = np.where(above > 0.0, above, np.minimum(below, 0.0))
        diff[np.isnan(diff)] = 0.0
        opening = np.ones((2, 2), dtype=bool)
        changes = []
        for kind, mask in (
            (ChangeKind.NEW, diff > threshold),
            (ChangeKind.REMOVED, diff < -threshold),
        ):
            labels, count = ndimage.label(ndimage.binary_opening(mask, opening), np.ones((3, 3)))
            for region in range(1, count + 1):
                rows, cols = np.nonzero(labels == region)
                area = len(rows) * self.resolution**2
                if area < min_area:
                    continue
                values = diff[rows, cols]
                r = self.resolution
                changes.append(
                    MapChange(
                        kind,
                        len(rows),
                        area,
                        (float(grid_e[rows, cols].mean()), float(grid_n[rows, cols].mean())),
                        (
                            self.east0 + float(cols.min()) * r,
                            self.north0 + float(rows.min()) * r,
                            self.east0 + float(cols.max() + 1) * r,
                            self.north0 + float(rows.max() + 1) * r,
                        ),
                        float(values.max() if kind is ChangeKind.NEW else values.min()),
                    )
                )
        return tuple(sorted(changes, key=lambda ch: -ch.area))
