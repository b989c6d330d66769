"""The landing pad's reference pattern (chapter §5.4, Figure 8): five circle triplets.

Black circles on white. Triplet ``k`` (0..4) has three circles of radius ``2 * 2**k`` cm on the
corners of an equilateral triangle of side ``8 * 2**k`` cm; all five triangles share the pad's
centre, and each is turned 60 degrees against the previous one so that no two circles touch
(the nearest circles of neighbouring triplets are one side length of the smaller triangle apart,
their radii add up to three quarters of it). The chapter says each triplet "is uniquely
determined by a combination of differently sized inner circles": here every black circle has a
concentric white inner circle whose radius is one of :data:`INNER_RATIOS` of the outer radius.
The three ratios of a triplet are distinct (so its corners are told apart and the pose has no
three-fold ambiguity) and the five sets of ratios are distinct (so triplets are told apart).
Read counter-clockwise (seen from above) the ratios of triplet ``k`` increase; a camera that
reads them clockwise sees a mirrored pattern.

Pad frame: origin at the common centre, x and y in the pad's plane, z up out of the pattern.
:func:`render` rasterises the pattern as a pinhole camera sees it (exact plane-ray
intersection, supersampled): the image source of the pose estimator's tests and benchmark.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_perception.camera import Intrinsics

TRIPLETS = 5
BASE_RADIUS_M = 0.02
BASE_SIDE_M = 0.08
INNER_RATIOS = (0.2, 0.33, 0.46, 0.59, 0.72)
"""Inner (white) radius over outer (black) radius; neighbours differ by 0.13."""
CODES = ((0, 1, 2), (0, 2, 4), (1, 3, 4), (0, 3, 4), (1, 2, 3))
"""Per triplet, the indices into :data:`INNER_RATIOS` of its corners, counter-clockwise."""
PAD_HALF_WIDTH_M = 1.1
"""The white plate is a 2.2 m square: the largest triplet's circles end 1.06 m from the centre."""

WHITE = 235
BLACK = 25


@dataclass(frozen=True, slots=True)
class PadCircle:
    """One black circle of the pattern (pad frame, metres)."""

    triplet: int
    corner: int
    x: float
    y: float
    radius: float
    inner_ratio: float


def _circles() -> tuple[PadCircle, ...]:
    out = []
    for k in range(TRIPLETS):
        side = BASE_SIDE_M * 2**k
        circumradius = side / math.sqrt(3.0)
        for corner, code in enumerate(CODES[k]):
            angle = math.pi / 2.0 + k * math.pi / 3.0 + corner * 2.0 * math.pi / 3.0
            out.append(
                PadCircle(
                    triplet=k,
                    corner=corner,
                    x=circumradius * math.cos(angle),
                    y=circumradius * math.sin(angle),
                    radius=BASE_RADIUS_M * 2**k,
                    inner_ratio=INNER_RATIOS[code],
                )
            )
    return tuple(out)


CIRCLES: tuple[PadCircle, ...] = _circles()
"""Every circle of the pattern, by triplet then counter-clockwise corner."""


def triplet_of_codes(codes: frozenset[int]) -> int | None:
    """The triplet whose corners carry these inner-ratio indices (None: no such triplet)."""
    for k, code in enumerate(CODES):
        if frozenset(code) == codes:
            return k
    return None


def is_black(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether pad-frame points (metres) are on black: inside a circle, outside its hole."""
    black = np.zeros(np.broadcast(x, y).shape, dtype=bool)
    for c in CIRCLES:
        d2 = (x - c.x) ** 2 + (y - c.y) ** 2
        black |= (d2 <= c.radius**2) & (d2 > (c.inner_ratio * c.radius) ** 2)
    return black


def render(
    intrinsics: Intrinsics,
    rotation: NDArray[np.float64],
    translation: NDArray[np.float64],
    background: int = 110,
    supersample: int = 2,
) -> NDArray[np.uint8]:
    """The pad as a camera sees it: 8-bit grey image, ``height`` x ``width``.

    Args:
        intrinsics: The camera's pinhole model (no distortion).
        rotation: Pad frame -> camera frame (x right, y down, z forward).
        translation: The pad's origin in the camera frame (metres).
        background: Grey level of the ground around the pad.
        supersample: Samples per pixel side (anti-aliasing).
    """
    n = supersample
    offsets = (np.arange(n) + 0.5) / n - 0.5
    u = (np.arange(intrinsics.width)[:, None] + offsets[None, :]).reshape(-1)
    v = (np.arange(intrinsics.height)[:, None] + offsets[None, :]).reshape(-1)
    uu, vv = np.meshgrid(u, v)
    rays = np.stack(
        [
            (uu - intrinsics.cx) / intrinsics.fx,
            (vv - intrinsics.cy) / intrinsics.fy,
            np.ones_like(uu),
        ]
    )
    centre = -rotation.T @ translation  # the camera in the pad frame
    directions = np.tensordot(rotation.T, rays, axes=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        reach = -centre[2] / directions[2]
    x = centre[0] + reach * directions[0]
    y = centre[1] + reach * directions[1]
    on_pad = (reach > 0) & (np.abs(x) <= PAD_HALF_WIDTH_M) & (np.abs(y) <= PAD_HALF_WIDTH_M)
    grey = np.full(on_pad.shape, float(background))
    grey[on_pad] = np.where(is_black(x[on_pad], y[on_pad]), BLACK, WHITE)
    pixels = grey.reshape(intrinsics.height, n, intrinsics.width, n).mean(axis=(1, 3))
    out: NDArray[np.uint8] = np.round(pixels).astype(np.uint8)
    return out


def look_at(
    camera: tuple[float, float, float], roll: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotation and translation of a camera at ``camera`` (pad frame) aimed at the pad's centre.

    ``roll`` turns the camera about its optical axis. Returns (pad -> camera rotation, the pad's
    origin in the camera frame), as :func:`render` takes them.
    """
    eye = np.asarray(camera, dtype=np.float64)
    forward = -eye / np.linalg.norm(eye)
    helper = np.array([0.0, 1.0, 0.0]) if abs(forward[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(forward, helper)
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    c, s = math.cos(roll), math.sin(roll)
    right, down = c * right + s * down, -s * right + c * down
    rotation = np.stack([right, down, forward])
    return rotation, -rotation @ eye
