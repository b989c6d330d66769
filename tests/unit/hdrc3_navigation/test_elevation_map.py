from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from hdrc3_base.errors import DataError
from hdrc3_navigation.elevation_map import MAX_CELLS, ChangeKind, ElevationMap

NAN = math.nan


def grid(rows: int, cols: int, holes: tuple[tuple[int, int], ...] = ()) -> np.ndarray:
    h = np.arange(rows * cols, dtype=np.float64).reshape(rows, cols) * 0.1
    for r, c in holes:
        h[r, c] = NAN
    return h


TRIANGLES = [
    # (rows, cols, unmapped cells, vertices, faces)
    (2, 2, (), 9, 8),  # two triangles per cell, between its corners
    (3, 4, (), 20, 24),
    (3, 4, ((1, 1),), 20, 22),  # an inner hole: its corners still belong to its neighbours
    (3, 4, ((0, 0),), 19, 22),  # a corner hole: its outer corner belongs to no cell
    (3, 3, ((0, 1), (1, 0)), 16, 14),
    (1, 5, (), 12, 10),  # a single row is a surface too
    (2, 2, ((0, 0), (1, 1)), 7, 4),
    (2, 2, ((0, 0), (0, 1), (1, 0), (1, 1)), 0, 0),
]


@pytest.mark.parametrize(("rows", "cols", "holes", "vertices", "faces"), TRIANGLES)
def test_triangles_cover_each_mapped_cell_between_its_corners(
    rows: int, cols: int, holes: tuple[tuple[int, int], ...], vertices: int, faces: int
) -> None:
    m = ElevationMap("m", 10.0, 20.0, 2.0, grid(rows, cols, holes))
    verts, tris = m.triangles()
    assert verts.shape == (vertices, 3) and tris.shape == (faces, 3)
    assert tris.dtype == np.int32
    if faces:
        assert tris.min() >= 0 and tris.max() < vertices
    # vertices sit on cell corners, at the highest mapped cell around each
    assert np.all((verts[:, 0] - 10.0) % 2.0 == pytest.approx(0.0))
    around = [m.heights_at(verts[:, 0] + de, verts[:, 1] + dn) for de in (-1, 1) for dn in (-1, 1)]
    assert np.allclose(verts[:, 2], np.nanmax(np.vstack(around), axis=0))


def test_a_solid_is_never_smaller_than_its_cells() -> None:
    heights = np.zeros((5, 5))
    heights[2, 2] = 5.0  # one roof cell: east 2..3, north 2..3
    verts, tris = ElevationMap("m", 0.0, 0.0, 1.0, heights).triangles()
    roof = [t for t in tris if np.all(verts[t, 2] == 5.0)]
    assert len(roof) == 2  # the roof cell's square is flat at the roof, to its edges
    assert {tuple(verts[i, :2]) for t in roof for i in t} == {(2, 2), (3, 2), (2, 3), (3, 3)}


HEIGHTS_AT = [
    # (east, north, expected) on a 3 x 4 grid at 1 m from (0, 0), cell (1, 2) unmapped
    (0.5, 0.5, 0.0),
    (3.99, 0.0, 0.3),  # the south-east cell, its south edge
    (0.0, 2.5, 0.8),  # the west edge of row 2
    (2.5, 1.5, NAN),  # the unmapped cell
    (-0.01, 0.5, NAN),  # west of the map
    (4.0, 0.5, NAN),  # the east edge of the last column is outside
    (0.5, 3.0, NAN),  # north of the map
    (NAN, 0.5, NAN),
]


@pytest.mark.parametrize(("east", "north", "expected"), HEIGHTS_AT)
def test_heights_at_is_the_height_of_the_cell_holding_the_point(
    east: float, north: float, expected: float
) -> None:
    m = ElevationMap("m", 0.0, 0.0, 1.0, grid(3, 4, ((1, 2),)))
    got = m.heights_at(np.array([east]), np.array([north]))
    assert got.shape == (1,)
    if math.isnan(expected):
        assert math.isnan(got[0])
    else:
        assert got[0] == pytest.approx(expected)


def test_heights_at_vectorised_and_scalar() -> None:
    m = ElevationMap("m", 0.0, 0.0, 1.0, grid(3, 4))
    got = m.heights_at(np.array([[0.5, 1.5], [2.5, 9.0]]), np.array([[0.5, 0.5], [2.5, 0.5]]))
    assert got.shape == (2, 2)
    assert np.allclose(got[0], [0.0, 0.1]) and got[1, 0] == pytest.approx(1.0)
    assert math.isnan(got[1, 1])
    assert float(m.heights_at(np.float64(1.5), np.float64(2.5))) == pytest.approx(0.9)


def flat(value: float = 0.0):  # type: ignore[no-untyped-def]
    return lambda e, n: np.full(np.shape(e), value)


def test_compare_finds_a_new_block_and_a_removed_one() -> None:
    h = np.zeros((30, 40))
    h[5:8, 10:15] = 4.0  # a 3 x 5 m container, 4 m high

    def model(e: np.ndarray, n: np.ndarray) -> np.ndarray:  # a 6 x 6 m shed, gone from the map
        out = np.zeros(np.shape(e))
        out[(e >= 25.0) & (e < 31.0) & (n >= 20.0) & (n < 26.0)] = 5.0
        return out

    m = ElevationMap("scan", 0.0, 0.0, 1.0, h)
    changes = m.compare(model, tolerance=0.0)
    assert [c.kind for c in changes] == [ChangeKind.REMOVED, ChangeKind.NEW]  # largest first
    removed, new = changes
    assert (new.cells, new.area, new.bounds) == (15, 15.0, (10.0, 5.0, 15.0, 8.0))
    assert new.centre == pytest.approx((12.5, 6.5)) and new.height == pytest.approx(4.0)
    assert removed.cells == 36 and removed.height == pytest.approx(-5.0)
    assert removed.bounds == (25.0, 20.0, 31.0, 26.0)


def test_compare_ignores_one_cell_wide_seams_small_regions_and_unmapped_cells() -> None:
    h = np.zeros((30, 40))
    h[10, 2:30] = 3.0  # a seam along a wall (horizontal position error)
    h[15:25, 20] = -3.0  # and a one-cell trench
    h[2:3, 35:37] = 5.0  # 1 x 2 cells: a seam too
    h[25:27, 35:37] = 5.0  # 2 x 2 m: survives the opening, below min_area 5
    h[0:4, 0:4] = NAN  # unmapped: no difference
    m = ElevationMap("scan", 0.0, 0.0, 1.0, h)
    assert m.compare(flat(), min_area=5.0) == ()
    (small,) = m.compare(flat(), min_area=4.0)
    assert small.kind is ChangeKind.NEW and small.cells == 4
    assert m.compare(flat(-10.0), threshold=20.0) == ()


def shed(dx: float = 0.0, dy: float = 0.0, up: float = 0.0):  # type: ignore[no-untyped-def]
    """A surface: ground at ``up``, a 10 x 8 m shed 5 m high at (20..30, 10..18) moved by dx, dy."""

    def surface(e: np.ndarray, n: np.ndarray) -> np.ndarray:
        e, n = np.asarray(e) - dx, np.asarray(n) - dy
        return np.where((e >= 20.0) & (e < 30.0) & (n >= 10.0) & (n < 18.0), 5.0, 0.0) + up

    return surface


@pytest.mark.parametrize(("tolerance", "seams"), [(0.0, 2), (2.0, 0)])
def test_a_map_a_metre_or_two_off_along_walls_is_no_change_within_the_tolerance(
    tolerance: float, seams: int
) -> None:
    m = ElevationMap("scan", 0.0, 0.0, 1.0, np.zeros((30, 50)))
    m = ElevationMap("scan", 0.0, 0.0, 1.0, m.cell_tops(shed(2.0, -2.0)))
    changes = m.compare(shed(), tolerance=tolerance)
    assert sorted(c.kind.value for c in changes) == ["new", "removed"][:seams]


@pytest.mark.parametrize("offset", [(2.25, -1.5, 0.4), (-3.0, 0.75, -0.2), (0.0, 0.0, 0.0)])
def test_a_map_is_moved_onto_the_model_by_the_offset_it_carries(
    offset: tuple[float, float, float],
) -> None:
    east, north, up = offset
    blank = ElevationMap("scan", 0.0, 0.0, 1.0, np.zeros((30, 50)))
    carried = ElevationMap("scan", 0.0, 0.0, 1.0, blank.cell_tops(shed(east, north, up), 1))
    moved, shift = carried.aligned_to(shed())
    # a 1 m grid of sharp edges places the shed only to within a cell
    assert shift.east == pytest.approx(east, abs=1.0)
    assert shift.north == pytest.approx(north, abs=1.0)
    assert shift.up == pytest.approx(up)
    assert shift.misfit_after <= shift.misfit_before
    assert (moved.east0, moved.north0) == (-shift.east, -shift.north)
    assert moved.compare(shed(), tolerance=0.0) == ()


@pytest.mark.parametrize(("search", "step"), [(0.0, 0.25), (6.0, 0.3), (60.0, 1.0), (6.0, NAN)])
def test_impossible_alignments_raise_data_errors(search: float, step: float) -> None:
    with pytest.raises(DataError):
        ElevationMap("m", 0.0, 0.0, 1.0, np.zeros((2, 3))).aligned_to(flat(), search, step)


def test_the_score_separates_the_cells_beside_a_step_from_the_rest() -> None:
    blank = ElevationMap("scan", 0.0, 0.0, 1.0, np.zeros((30, 50)))
    heights = blank.cell_tops(shed()) + 0.1  # 10 cm high everywhere
    heights[10:18, 19] = 5.0  # and a roof that bleeds one cell west of the shed's wall
    score = ElevationMap("scan", 0.0, 0.0, 1.0, heights).score(shed())
    assert score.cells == 1500 and score.rms > 3.0 * score.away_rms
    assert score.away_rms == pytest.approx(0.1)
    assert 1000 < score.away_cells < 1500


BAD: list[tuple[dict[str, Any], str]] = [
    ({"name": ""}, "name"),
    ({"name": "x" * 65}, "name"),
    ({"name": "a\nb"}, "name"),
    ({"east0": NAN}, "origin"),
    ({"north0": math.inf}, "origin"),
    ({"resolution": 0.0}, "resolution"),
    ({"resolution": -1.0}, "resolution"),
    ({"resolution": NAN}, "resolution"),
    ({"resolution": 200.0}, "resolution"),
    ({"heights": np.zeros(4)}, "2-D"),
    ({"heights": np.zeros((0, 3))}, "2-D"),
    ({"heights": np.zeros((1, MAX_CELLS + 1))}, "2-D"),
    ({"heights": np.array([[0.0, math.inf]])}, "finite"),
    ({"returns": np.zeros((3, 2), dtype=np.int64)}, "returns"),
]


@pytest.mark.parametrize(("change", "words"), BAD)
def test_malformed_maps_raise_data_errors(change: dict[str, Any], words: str) -> None:
    fields: dict[str, Any] = {
        "name": "m",
        "east0": 0.0,
        "north0": 0.0,
        "resolution": 1.0,
        "heights": np.zeros((2, 3)),
        "returns": np.ones((2, 3), dtype=np.int64),
    }
    fields.update(change)
    with pytest.raises(DataError, match=words):
        ElevationMap(**fields)


def test_a_map_keeps_a_copy_of_the_callers_heights() -> None:
    heights = np.zeros((2, 3))
    ElevationMap("m", 0.0, 0.0, 1.0, heights)
    heights[0, 0] = 1.0  # still writable


def test_a_map_freezes_its_arrays() -> None:
    m = ElevationMap("m", 0.0, 0.0, 1.0, np.zeros((2, 3)), np.ones((2, 3), dtype=np.int64))
    assert (m.rows, m.columns) == (2, 3) and m.returns.shape == (2, 3)
    with pytest.raises(ValueError):
        m.heights[0, 0] = 1.0
    with pytest.raises(ValueError):
        m.returns[0, 0] = 1
