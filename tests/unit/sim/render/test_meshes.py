"""Mesh primitives: closed boxes with outward normals, extruded footprints, flat polygons."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from sim.render.meshes import FLOATS_PER_VERTEX, MeshBuilder, rot_up


def _area(vertices: np.ndarray) -> float:
    tris = vertices[:, 0:3].reshape(-1, 3, 3)
    cross = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    return float(0.5 * np.linalg.norm(cross, axis=1).sum())


@pytest.mark.parametrize("heading", [0.0, 0.7, math.pi])
def test_box_normals_point_out_and_surface_is_right(heading: float) -> None:
    mesh = MeshBuilder()
    centre = np.array([3.0, -2.0, 1.0])
    mesh.box(centre, (2.0, 1.0, 0.5), rot_up(heading), (0.5, 0.5, 0.5), 300.0)
    v = mesh.array()
    assert v.shape == (36, FLOATS_PER_VERTEX)
    tris = v[:, 0:3].reshape(-1, 3, 3)
    outward = tris.mean(axis=1) - centre
    assert np.all(np.einsum("ij,ij->i", outward, v[::3, 3:6]) > 0.0)
    assert _area(v) == pytest.approx(2 * (2.0 * 1.0 + 2.0 * 0.5 + 1.0 * 0.5))
    assert np.all(v[:, 9] == 300.0)


def test_rot_up_points_forward_along_the_heading() -> None:
    east = rot_up(math.pi / 2) @ np.array([1.0, 0.0, 0.0])
    assert east == pytest.approx([1.0, 0.0, 0.0])
    left_of_north = rot_up(0.0) @ np.array([0.0, 1.0, 0.0])
    assert left_of_north == pytest.approx([-1.0, 0.0, 0.0])


@pytest.mark.parametrize("clockwise", [False, True])
def test_prism_walls_face_out_and_roof_covers_an_l_shaped_footprint(clockwise: bool) -> None:
    ring = [(0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (4.0, 4.0), (4.0, 10.0), (0.0, 10.0)]
    if clockwise:
        ring.reverse()
    mesh = MeshBuilder()
    mesh.prism(ring, 1.0, 7.0, ((0.6, 0.6, 0.6), 290.0), ((0.5, 0.2, 0.1), 305.0))
    v = mesh.array()
    roof = v[v[:, 9] == 305.0]
    walls = v[v[:, 9] == 290.0]
    assert np.all(roof[:, 2] == 7.0) and np.all(roof[:, 5] == 1.0)
    assert _area(roof) == pytest.approx(Polygon(ring).area)
    assert _area(walls) == pytest.approx(Polygon(ring).length * 6.0)
    for tri in walls.reshape(-1, 3, FLOATS_PER_VERTEX):
        mid = tri[:, 0:2].mean(axis=0)
        # each wall's normal points away from the inside of the footprint
        assert not Polygon(ring).contains(Point(*(mid + 0.1 * tri[0, 3:5]))), mid


def test_sphere_is_closed_and_smooth() -> None:
    mesh = MeshBuilder()
    mesh.sphere((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), np.eye(3), (1.0, 1.0, 1.0), 300.0)
    v = mesh.array()
    assert np.allclose(np.linalg.norm(v[:, 0:3], axis=1), 1.0)
    assert np.allclose(v[:, 0:3], v[:, 3:6])  # unit sphere: normal = position
    assert _area(v) == pytest.approx(4 * math.pi, rel=0.1)
