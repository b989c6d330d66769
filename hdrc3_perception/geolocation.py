"""Closed-form geolocation and thermal -> colour correspondence (§11.1.1).

A pixel's ray from the camera centre meets the ground: first in closed form on a flat world at a
given height, then - with the elevation model - by marching along the ray over the terrain
heightfield. The march is conservative for terrain whose slope stays below ``max_slope``: at each
step the ray advances by its vertical clearance divided by how fast the clearance can shrink, so
it cannot jump through a hill, and ends when the clearance is below ``tolerance``. (Written here
because a heightfield ray march is a few lines; a mesh ray caster would need the whole terrain
as triangles.) The correspondence locates a thermal pixel on the ground and projects the point
into the colour camera, which needs no feature matching between the two modalities.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_perception.camera import CameraPose, Intrinsics

HeightFn = Callable[[float, float], float]
"""Terrain height (m, ENU up) at (east, north)."""


@dataclass(frozen=True, slots=True)
class Ground:
    """What the geolocation knows about the ground: a flat plane or a heightfield."""

    flat_up: float = 0.0
    """Plane height (m, ENU up) when there is no heightfield."""
    height: HeightFn | None = None
    max_slope: float = 1.0
    """Largest terrain slope (rise over run) the ray march must not miss."""
    max_range: float = 2000.0
    """m: rays that meet no ground within this range find nothing."""
    tolerance: float = 0.01
    """m: vertical clearance at which the march stops."""

    def up(self, east: float, north: float) -> float:
        """Ground height at a point."""
        return self.flat_up if self.height is None else float(self.height(east, north))


def flat_hit(
    origin: NDArray[np.float64], direction: NDArray[np.float64], ground_up: float
) -> NDArray[np.float64] | None:
    """Where a ray meets the plane up = ``ground_up``; None if it points level or upwards."""
    if direction[2] >= -1e-9:
        return None
    t = (ground_up - origin[2]) / direction[2]
    if t <= 0.0:
        return None
    hit: NDArray[np.float64] = origin + t * direction
    return hit


def terrain_hit(
    origin: NDArray[np.float64], direction: NDArray[np.float64], ground: Ground
) -> NDArray[np.float64] | None:
    """First point where a ray meets ``ground`` (heightfield march, or the flat plane)."""
    if ground.height is None:
        return flat_hit(origin, direction, ground.flat_up)
    horizontal = math.hypot(direction[0], direction[1])
    closing = -direction[2] + ground.max_slope * horizontal
    if closing <= 1e-9:
        return None
    t = 0.0
    for _ in range(200):
        point = origin + t * direction
        clearance = point[2] - ground.up(point[0], point[1])
        if clearance < ground.tolerance:
            if clearance < -ground.tolerance:
                return None  # the camera itself is below the ground
            hit: NDArray[np.float64] = point
            return hit
        t += clearance / closing
        if t > ground.max_range:
            return None
    return None


def geolocate(
    pose: CameraPose, intrinsics: Intrinsics, u: float, v: float, ground: Ground
) -> NDArray[np.float64] | None:
    """ENU ground point (3,) seen at pixel (u, v); None if the ray meets no ground."""
    return terrain_hit(pose.position, pose.ray(intrinsics, u, v), ground)


@dataclass(frozen=True, slots=True)
class Correspondence:
    """A thermal pixel's ground point and where the colour camera sees it."""

    ground: NDArray[np.float64]
    color_pixel: tuple[float, float]
    range_m: float
    """Distance from the thermal camera to the ground point."""


def correspond(
    thermal_pose: CameraPose,
    thermal: Intrinsics,
    color_pose: CameraPose,
    color: Intrinsics,
    pixel: tuple[float, float],
    ground: Ground,
) -> Correspondence | None:
    """Colour pixel of a thermal pixel (ground point projected); None if off the colour image."""
    point = geolocate(thermal_pose, thermal, pixel[0], pixel[1], ground)
    if point is None:
        return None
    uv = color_pose.project(color, point)[0]
    if not (0.0 <= uv[0] <= color.width and 0.0 <= uv[1] <= color.height):
        return None  # also false for NaN (behind the colour camera)
    distance = float(np.linalg.norm(point - thermal_pose.position))
    return Correspondence(point, (float(uv[0]), float(uv[1])), distance)
