"""View-frustum culling: a vertex array cut into ground tiles, and the tiles a camera can see.

llvmpipe (software OpenGL) spends most of a frame transforming vertices, so drawing only the
tiles whose bounding box intersects the camera's view frustum is the main speed-up for a camera
looking down at a small part of the world.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

TILE_M = 40.0


@dataclass(frozen=True, slots=True)
class TiledMesh:
    """Triangles sorted by tile; tile ``i`` is vertices ``first[i]`` .. ``first[i] + count[i]``."""

    vertices: NDArray[np.float32]
    first: NDArray[np.int64]
    count: NDArray[np.int64]
    corners: NDArray[np.float64]
    """(tiles, 8, 4) homogeneous corners of each tile's bounding box."""


def tile_mesh(vertices: NDArray[np.float32], tile: float = TILE_M) -> TiledMesh:
    """Sort whole triangles of ``vertices`` (N x 10) into square tiles by their centroids."""
    if vertices.shape[0] == 0:
        empty = np.zeros(0, dtype=np.int64)
        return TiledMesh(vertices, empty, empty, np.zeros((0, 8, 4)))
    tris = vertices.reshape(-1, 3, vertices.shape[1])
    centroid = tris[:, :, 0:2].mean(axis=1)
    cell = np.floor(centroid / tile).astype(np.int64)
    key = cell[:, 0] * 1_000_003 + cell[:, 1]
    order = np.argsort(key, kind="stable")
    tris, key = tris[order], key[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    ends = np.r_[starts[1:], len(key)]
    corners = np.empty((len(starts), 8, 4))
    for i, (a, b) in enumerate(zip(starts, ends, strict=True)):
        pos = tris[a:b, :, 0:3].reshape(-1, 3)
        lo, hi = pos.min(axis=0), pos.max(axis=0)
        box = np.array(
            [[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        )
        corners[i] = box
    return TiledMesh(tris.reshape(-1, vertices.shape[1]), starts * 3, (ends - starts) * 3, corners)


def visible(mesh: TiledMesh, clip: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Tiles whose bounding box is not entirely outside one plane of the clip volume."""
    if mesh.corners.shape[0] == 0:
        return np.zeros(0, dtype=bool)
    c = mesh.corners @ clip.T  # (tiles, 8, 4)
    x, y, z, w = c[..., 0], c[..., 1], c[..., 2], c[..., 3]
    outside = (
        np.all(x < -w, axis=1)
        | np.all(x > w, axis=1)
        | np.all(y < -w, axis=1)
        | np.all(y > w, axis=1)
        | np.all(z < -w, axis=1)
        | np.all(z > w, axis=1)
    )
    shown: NDArray[np.bool_] = ~outside
    return shown


def ranges(mesh: TiledMesh, clip: NDArray[np.float64]) -> list[tuple[int, int]]:
    """(first, count) vertex ranges to draw, neighbouring visible tiles merged."""
    out: list[tuple[int, int]] = []
    for i in np.flatnonzero(visible(mesh, clip)):
        first, count = int(mesh.first[i]), int(mesh.count[i])
        if out and out[-1][0] + out[-1][1] == first:
            out[-1] = (out[-1][0], out[-1][1] + count)
        else:
            out.append((first, count))
    return out
