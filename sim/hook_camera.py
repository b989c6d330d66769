"""The hook camera: a downward camera beside the winch that sees the payload objects below.

The chapter's prototype carried a camera looking down at the package (Figure 38, top left).
Here it reports, for every box or carrier inside its cone, the object's tag and the offset of
the point the magnet grips (a box's top centre, a carrier's lifting plate) from the winch, in
local ENU metres, with a noise that grows with range. A GPS fix is metres off; this relative
measurement lets an executor hover the hook over a box. Noise is drawn from a generator seeded
by (agent seed, tick, object index): deterministic, and independent of who listens.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Vec3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class HookCameraParams:
    """Field of view and noise."""

    half_angle: float = math.radians(35.0)
    """rad, half the cone's opening around straight down."""
    max_range: float = 30.0
    """m."""
    sigma: float = 0.03
    """m, noise per axis at zero range."""
    sigma_per_metre: float = 0.004
    """m of noise per axis for each metre of range."""


def observe(
    winch: Vec3,
    targets: list[tuple[str, Vec3]],
    seed: tuple[int, ...],
    params: HookCameraParams | None = None,
) -> list[tuple[str, Vec3]]:
    """Tags and noisy offsets (target - winch, ENU m) of the targets the camera sees."""
    p = params or HookCameraParams()
    seen: list[tuple[str, Vec3]] = []
    for index, (tag, point) in enumerate(targets):
        de, dn, du = point[0] - winch[0], point[1] - winch[1], point[2] - winch[2]
        distance = math.sqrt(de * de + dn * dn + du * du)
        if du >= 0.0 or distance > p.max_range:
            continue
        if math.atan2(math.hypot(de, dn), -du) > p.half_angle:
            continue
        sigma = p.sigma + p.sigma_per_metre * distance
        noise = np.random.default_rng([*seed, index]).normal(0.0, sigma, 3)
        seen.append((tag, (de + float(noise[0]), dn + float(noise[1]), du + float(noise[2]))))
    return seen
