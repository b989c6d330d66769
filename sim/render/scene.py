"""The renderable scene of a world: static meshes and the meshes of the dynamic objects.

Static: terrain (grass and crop fields), roads, pads, buildings (sun-heated roofs), trees. The
materials are resolved here to albedo and temperature per vertex.
"""

from __future__ import annotations

import itertools
import math
import zlib
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from shapely.geometry import Point, Polygon

from sim.landing_pattern import CIRCLES, PAD_HALF_WIDTH_M, PRINT_HEIGHT_M, pad_axes
from sim.render.bodies import add_object
from sim.render.materials import Material, ThermalEnvironment
from sim.render.meshes import MeshBuilder
from sim.world import DynamicObject, LandingPad, World

TERRAIN_STEP_M = 10.0
"""Terrain mesh spacing (the heightfield is bilinear on a much coarser grid)."""
TERRAIN_MARGIN_M = 150.0
"""The ground continues flat this far beyond the world's extent (the horizon is not empty)."""
FIELD_CELL_M = 70.0
"""Size of the patchwork of grass and crop fields on open ground."""
ROAD_PIECE_M = 10.0
"""Roads are draped over the terrain in pieces at most this long."""
DRAPE_M = 0.05
"""Roads and pads lie this far above the terrain (no depth fighting)."""
PATTERN_LIFT_M = 0.01
"""The landing pattern's plate lies this far below its black rings (at ``PRINT_HEIGHT_M``)."""
RING_SEGMENTS = 64
"""Straight pieces per circle of the landing pattern (0.1 % radius error)."""
TREE_SPACING_M = 7.0


@dataclass(frozen=True, slots=True)
class SceneMeshes:
    """Vertex arrays of one world: static geometry and dynamic objects (see meshes.py)."""

    static: NDArray[np.float32]
    objects: NDArray[np.float32]


def _cell_hash(i: int, j: int, salt: int) -> float:
    """Deterministic value in [0, 1) for an integer cell."""
    return (zlib.crc32(f"{i},{j},{salt}".encode()) % 10_000) / 10_000.0


def _terrain(mesh: MeshBuilder, world: World, env: ThermalEnvironment) -> None:
    e0, n0, e1, n1 = world.bounds
    m = TERRAIN_MARGIN_M
    es = np.arange(e0 - m, e1 + m + 1e-6, TERRAIN_STEP_M)
    ns = np.arange(n0 - m, n1 + m + 1e-6, TERRAIN_STEP_M)
    ee, nn = np.meshgrid(es, ns)
    hh = world.terrain.heights_at(ee, nn)
    # smooth normals from the height gradient
    gn, ge = np.gradient(hh, TERRAIN_STEP_M)
    normals = np.stack([-ge, -gn, np.ones_like(hh)], axis=-1)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    grass, field = Material.GRASS.surface, Material.FIELD.surface
    cells_e = np.floor(ee / FIELD_CELL_M).astype(int)
    cells_n = np.floor(nn / FIELD_CELL_M).astype(int)
    mix = np.vectorize(lambda i, j: _cell_hash(int(i), int(j), 1))(cells_e, cells_n)
    is_field = (mix > 0.6)[..., None]
    shade = (
        0.85 + 0.3 * np.vectorize(lambda i, j: _cell_hash(int(i), int(j), 2))(cells_e, cells_n)
    )[..., None]
    albedo = np.where(is_field, np.asarray(field.albedo), np.asarray(grass.albedo)) * shade
    temperature = env.ambient + np.where(is_field[..., 0], field.warmth, grass.warmth)
    pos = np.stack([ee, nn, hh], axis=-1)
    r, c = np.meshgrid(np.arange(len(ns) - 1), np.arange(len(es) - 1), indexing="ij")
    corners = [(r, c), (r, c + 1), (r + 1, c + 1), (r + 1, c)]
    order = (0, 1, 2, 0, 2, 3)
    idx = [corners[k] for k in order]

    def triangles(values: NDArray[np.float64]) -> NDArray[np.float64]:
        stacked = np.stack([values[i, j] for i, j in idx], axis=2)
        return stacked.reshape(-1, values.shape[-1])

    mesh.add(
        triangles(pos),
        triangles(normals),
        triangles(albedo),
        triangles(temperature[..., None])[:, 0],
    )


def _draped_quad(
    world: World, a: NDArray[np.float64], b: NDArray[np.float64], width: float
) -> NDArray[np.float64]:
    direction = (b - a) / np.linalg.norm(b - a)
    side = np.array([-direction[1], direction[0]]) * width / 2.0
    ring = [a - side, b - side, b + side, a + side]
    pts = np.array([ring[k] for k in (0, 1, 2, 0, 2, 3)])
    up = world.terrain.heights_at(pts[:, 0], pts[:, 1]) + DRAPE_M
    return np.column_stack([pts, up])


def _roads(mesh: MeshBuilder, world: World, env: ThermalEnvironment) -> None:
    asphalt = Material.ASPHALT.surface
    for road in world.roads:
        points = np.asarray(road.points, dtype=np.float64)
        for a, b in itertools.pairwise(points):
            pieces = max(1, math.ceil(float(np.linalg.norm(b - a)) / ROAD_PIECE_M))
            for k in range(pieces):
                p0 = a + (b - a) * k / pieces
                p1 = a + (b - a) * (k + 1) / pieces
                quad = _draped_quad(world, p0, p1, road.width)
                mesh.add(
                    quad,
                    np.tile([0.0, 0.0, 1.0], (6, 1)),
                    asphalt.albedo,
                    env.ambient + asphalt.warmth,
                )
        for e, n in road.points:  # joints
            disc = Point(e, n).buffer(road.width / 2.0, quad_segs=4)
            mesh.flat_polygon(
                list(disc.exterior.coords),
                world.terrain.height(e, n) + DRAPE_M,
                asphalt.albedo,
                env.ambient + asphalt.warmth,
            )
    pad = Material.PAD.surface
    for landing in world.pads:
        disc = Point(landing.east, landing.north).buffer(landing.radius, quad_segs=6)
        up = world.terrain.height(landing.east, landing.north) + DRAPE_M
        mesh.flat_polygon(list(disc.exterior.coords), up, pad.albedo, env.ambient + pad.warmth)
        if landing.pattern:
            _landing_pattern(mesh, landing, up - DRAPE_M + PRINT_HEIGHT_M, env)


def _landing_pattern(
    mesh: MeshBuilder, pad: LandingPad, rings: float, env: ThermalEnvironment
) -> None:
    """The §5.4 pattern on a pad: a white plate and the black rings of ``sim.landing_pattern``.

    ``rings`` is the height of the black rings (the pad frame's origin); the plate lies below.
    """
    white, black = Material.PATTERN_WHITE.surface, Material.PATTERN_BLACK.surface
    axes = pad_axes(pad.heading)[:2, :2]

    def enu(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        points: NDArray[np.float64] = np.column_stack([x, y]) @ axes.T + (pad.east, pad.north)
        return points

    h = PAD_HALF_WIDTH_M
    corners = enu(np.array([-h, h, h, -h]), np.array([-h, -h, h, h]))
    mesh.flat_polygon([tuple(p) for p in corners], rings - PATTERN_LIFT_M, white.albedo,
                      env.ambient + white.warmth)  # fmt: skip
    angles = np.linspace(0.0, math.tau, RING_SEGMENTS + 1)
    for circle in CIRCLES:
        ring = []
        for radius in (circle.radius, circle.inner_ratio * circle.radius):
            ring.append(enu(circle.x + radius * np.cos(angles), circle.y + radius * np.sin(angles)))
        outer, inner = ring
        quads = [(outer[i], outer[i + 1], inner[i + 1], outer[i], inner[i + 1], inner[i])
                 for i in range(RING_SEGMENTS)]  # fmt: skip
        positions = np.array([(e, n, rings) for q in quads for e, n in q])
        normals = np.tile([0.0, 0.0, 1.0], (positions.shape[0], 1))
        mesh.add(positions, normals, black.albedo, env.ambient + black.warmth)


def _buildings(mesh: MeshBuilder, world: World, env: ThermalEnvironment) -> None:
    wall, roof = Material.WALL.surface, Material.ROOF.surface
    for building in world.buildings:
        tint = 0.8 + 0.4 * _cell_hash(zlib.crc32(building.name.encode()), 0, 3)
        roof_tint = 0.7 + 0.6 * _cell_hash(zlib.crc32(building.name.encode()), 0, 4)
        mesh.prism(
            building.footprint,
            building.base,
            building.top,
            (np.asarray(wall.albedo) * tint, env.ambient + wall.warmth),
            (np.asarray(roof.albedo) * roof_tint, env.ambient + roof.warmth),
        )


def _trees(mesh: MeshBuilder, world: World, env: ThermalEnvironment) -> None:
    trunk, crown = Material.TRUNK.surface, Material.CROWN.surface
    eye = np.eye(3)
    for area in world.vegetation:
        polygon = Polygon(area.polygon)
        rng = np.random.default_rng(zlib.crc32(area.name.encode()))
        e0, n0, e1, n1 = polygon.bounds
        for e in np.arange(e0 + TREE_SPACING_M / 2, e1, TREE_SPACING_M):
            for n in np.arange(n0 + TREE_SPACING_M / 2, n1, TREE_SPACING_M):
                te, tn = e + rng.uniform(-2.0, 2.0), n + rng.uniform(-2.0, 2.0)
                if not polygon.contains(Point(te, tn)):
                    continue
                ground = world.terrain.height(te, tn)
                h = area.height * rng.uniform(0.75, 1.05)
                mesh.box(
                    (te, tn, ground + 0.2 * h),
                    (0.35, 0.35, 0.4 * h),
                    eye,
                    trunk.albedo,
                    env.ambient + trunk.warmth,
                )
                radius = min(3.5, 0.3 * h + 1.0) * rng.uniform(0.8, 1.2)
                colour = np.asarray(crown.albedo) * rng.uniform(0.75, 1.25)
                mesh.sphere(
                    (te, tn, ground + 0.62 * h),
                    (radius, radius, 0.38 * h),
                    eye,
                    colour,
                    env.ambient + crown.warmth,
                    slices=8,
                    stacks=4,
                )


def static_mesh(world: World, env: ThermalEnvironment) -> NDArray[np.float32]:
    """Vertex array of everything in ``world`` that does not move."""
    mesh = MeshBuilder()
    _terrain(mesh, world, env)
    _roads(mesh, world, env)
    _buildings(mesh, world, env)
    _trees(mesh, world, env)
    return mesh.array()


def object_mesh(
    world: World, objects: Iterable[DynamicObject], env: ThermalEnvironment
) -> NDArray[np.float32]:
    """Vertex array of the dynamic objects, each on the terrain at its position."""
    mesh = MeshBuilder()
    for obj in objects:
        add_object(mesh, obj, world.terrain.height(obj.east, obj.north), env)
    return mesh.array()


def build_scene(world: World, env: ThermalEnvironment | None = None) -> SceneMeshes:
    """Static and object meshes of ``world`` (objects as in the world file)."""
    env = env or ThermalEnvironment()
    return SceneMeshes(static_mesh(world, env), object_mesh(world, world.objects, env))
