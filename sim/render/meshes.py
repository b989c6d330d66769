"""Triangle soup with per-vertex attributes, and the primitives scenes are built from.

A vertex is ``position (3), normal (3), albedo (3), temperature (1)`` as float32, world ENU
metres and kelvin; the renderer uploads the array as one vertex buffer. Primitives (boxes,
spheres, extruded polygons) are written here rather than taken from a mesh library because the
renderer needs the material attributes on every vertex and nothing else.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import Polygon

FLOATS_PER_VERTEX = 10
Vec3 = tuple[float, float, float]

# Unit cube faces: outward normal and the four corners (counter-clockwise seen from outside).
_CUBE_FACES: tuple[tuple[Vec3, tuple[Vec3, Vec3, Vec3, Vec3]], ...] = (
    ((1, 0, 0), ((1, -1, -1), (1, 1, -1), (1, 1, 1), (1, -1, 1))),
    ((-1, 0, 0), ((-1, 1, -1), (-1, -1, -1), (-1, -1, 1), (-1, 1, 1))),
    ((0, 1, 0), ((1, 1, -1), (-1, 1, -1), (-1, 1, 1), (1, 1, 1))),
    ((0, -1, 0), ((-1, -1, -1), (1, -1, -1), (1, -1, 1), (-1, -1, 1))),
    ((0, 0, 1), ((-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1))),
    ((0, 0, -1), ((-1, 1, -1), (1, 1, -1), (1, -1, -1), (-1, -1, -1))),
)
_CUBE_POS = np.array([[c for i in (0, 1, 2, 0, 2, 3) for c in face[1][i]] for face in _CUBE_FACES])
_CUBE_POS = _CUBE_POS.reshape(36, 3).astype(np.float64)
_CUBE_NORMALS = np.repeat(np.array([f[0] for f in _CUBE_FACES], dtype=np.float64), 6, axis=0)


def rot_up(heading: float) -> NDArray[np.float64]:
    """Rotation taking a local frame (x forward, y left, z up) to ENU for a compass heading."""
    s, c = math.sin(heading), math.cos(heading)
    # forward = (sin h, cos h, 0); left = (-cos h, sin h, 0)
    return np.array([[s, -c, 0.0], [c, s, 0.0], [0.0, 0.0, 1.0]])


class MeshBuilder:
    """Collects triangles; :meth:`array` gives the interleaved float32 vertex array."""

    def __init__(self) -> None:
        self._parts: list[NDArray[np.float32]] = []

    def add(
        self,
        positions: NDArray[np.float64],
        normals: NDArray[np.float64],
        albedo: ArrayLike,
        temperature: ArrayLike,
    ) -> None:
        """Append triangles (``positions`` N x 3, N a multiple of 3) with their attributes."""
        n = positions.shape[0]
        block = np.empty((n, FLOATS_PER_VERTEX), dtype=np.float32)
        block[:, 0:3] = positions
        block[:, 3:6] = normals
        block[:, 6:9] = np.broadcast_to(np.asarray(albedo, dtype=np.float64), (n, 3))
        block[:, 9] = np.broadcast_to(np.asarray(temperature, dtype=np.float64), (n,))
        self._parts.append(block)

    def box(
        self,
        center: ArrayLike,
        size: Vec3,
        rotation: NDArray[np.float64],
        albedo: ArrayLike,
        temperature: float,
    ) -> None:
        """An oriented box: ``size`` along the local axes, ``rotation`` local -> ENU."""
        half = 0.5 * np.asarray(size, dtype=np.float64)
        positions = (_CUBE_POS * half) @ rotation.T + np.asarray(center, dtype=np.float64)
        self.add(positions, _CUBE_NORMALS @ rotation.T, albedo, temperature)

    def segment(
        self,
        start: ArrayLike,
        end: ArrayLike,
        width: float,
        thickness: float,
        albedo: ArrayLike,
        temperature: float,
    ) -> None:
        """A limb: a box from ``start`` to ``end`` with a square-ish cross-section."""
        a, b = np.asarray(start, dtype=np.float64), np.asarray(end, dtype=np.float64)
        axis = b - a
        length = float(np.linalg.norm(axis))
        if length < 1e-6:
            return
        x = axis / length
        helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        y = np.cross(helper, x)
        y /= np.linalg.norm(y)
        z = np.cross(x, y)
        self.box(
            (a + b) / 2.0,
            (length, width, thickness),
            np.column_stack([x, y, z]),
            albedo,
            temperature,
        )

    def sphere(
        self,
        center: ArrayLike,
        radius: Vec3,
        rotation: NDArray[np.float64],
        albedo: ArrayLike,
        temperature: float,
        slices: int = 10,
        stacks: int = 6,
    ) -> None:
        """A low-poly ellipsoid with semi-axes ``radius`` (local axes), smooth normals."""
        theta = np.linspace(0.0, math.pi, stacks + 1)
        phi = np.linspace(0.0, math.tau, slices + 1)
        t, p = np.meshgrid(theta, phi, indexing="ij")
        unit = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
        i, j = np.meshgrid(np.arange(stacks), np.arange(slices), indexing="ij")
        quads = np.stack([unit[i, j], unit[i + 1, j], unit[i + 1, j + 1], unit[i, j + 1]], -2)
        tris = quads[..., [0, 1, 2, 0, 2, 3], :].reshape(-1, 3)
        r = np.asarray(radius, dtype=np.float64)
        normals = tris / r
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        positions = (tris * r) @ rotation.T + np.asarray(center, dtype=np.float64)
        self.add(positions, normals @ rotation.T, albedo, temperature)

    def prism(
        self,
        footprint: Sequence[tuple[float, float]],
        base: float,
        top: float,
        wall: tuple[ArrayLike, float],
        roof: tuple[ArrayLike, float],
    ) -> None:
        """A footprint extruded from ``base`` to ``top``: walls and a flat roof."""
        ring = list(footprint)
        if ring[0] == ring[-1]:
            ring = ring[:-1]
        if Polygon(ring).exterior.is_ccw is False:
            ring.reverse()
        quads: list[tuple[float, float, float]] = []
        normals: list[tuple[float, float, float]] = []
        for (e0, n0), (e1, n1) in zip(ring, [*ring[1:], ring[0]], strict=True):
            length = math.hypot(e1 - e0, n1 - n0)
            if length < 1e-9:
                continue
            normal = ((n1 - n0) / length, -(e1 - e0) / length, 0.0)
            quad = [(e0, n0, base), (e1, n1, base), (e1, n1, top), (e0, n0, top)]
            quads.extend(quad[k] for k in (0, 1, 2, 0, 2, 3))
            normals.extend([normal] * 6)
        self.add(np.array(quads), np.array(normals), wall[0], wall[1])
        self.flat_polygon(ring, top, roof[0], roof[1])

    def flat_polygon(
        self,
        ring: Sequence[tuple[float, float]],
        up: float | NDArray[np.float64],
        albedo: ArrayLike,
        temperature: float,
    ) -> None:
        """A horizontal polygon at height ``up`` (one value, or one per triangle vertex)."""
        triangles = shapely.constrained_delaunay_triangles(Polygon(ring))
        corners = [list(t.exterior.coords)[:3] for t in triangles.geoms]
        positions = np.array([(e, n, 0.0) for tri in corners for e, n in tri], dtype=np.float64)
        if positions.size == 0:
            return
        positions[:, 2] = up
        normals = np.tile([0.0, 0.0, 1.0], (positions.shape[0], 1))
        self.add(positions, normals, albedo, temperature)

    def array(self) -> NDArray[np.float32]:
        """All triangles so far as an (N, 10) float32 array."""
        if not self._parts:
            return np.zeros((0, FLOATS_PER_VERTEX), dtype=np.float32)
        return np.concatenate(self._parts)
