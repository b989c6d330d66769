"""Frustum culling never drops a tile the camera can see."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.render.materials import ThermalEnvironment
from sim.render.projection import clip_matrix, look_at
from sim.render.scene import static_mesh
from sim.render.tiles import TiledMesh, ranges, tile_mesh, visible
from sim.sensors.camera_model import CameraPose, Intrinsics, project
from sim.world_loader import load_world

K = Intrinsics.from_fov(160, 120, math.radians(48.0))


@pytest.fixture(scope="module")
def tiled() -> TiledMesh:
    return tile_mesh(static_mesh(load_world("revinge"), ThermalEnvironment()))


@pytest.mark.parametrize(
    "pose",
    [
        look_at((0.0, 0.0, 40.0), (0.0, 0.0, 0.0)),
        look_at((-150.0, -40.0, 40.0), (-127.0, -40.0, 0.0)),
        look_at((100.0, 50.0, 12.0), (300.0, 100.0, 5.0)),
    ],
)
def test_every_tile_with_a_vertex_in_view_is_drawn(tiled: TiledMesh, pose: CameraPose) -> None:
    clip = clip_matrix(pose, K)
    shown = visible(tiled, clip)
    assert 0 < shown.sum() < len(shown)  # culling does something, and not everything
    for i in np.flatnonzero(~shown):
        start, count = tiled.first[i], tiled.count[i]
        for vertex in tiled.vertices[start : start + count : 7, 0:3]:
            assert project(pose, K, tuple(float(v) for v in vertex)) is None
    drawn = sum(c for _, c in ranges(tiled, clip))
    assert drawn == int(tiled.count[shown].sum())


def test_tiles_keep_every_triangle(tiled: TiledMesh) -> None:
    assert tiled.vertices.shape[0] == int(tiled.count.sum())
    assert tiled.vertices.shape[0] % 3 == 0
    assert np.all(tiled.first[1:] == tiled.first[:-1] + tiled.count[:-1])
