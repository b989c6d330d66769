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

Pad frame: origin at the common centre, x and y in the pad's plane, z up out of the pattern;
on a world's pad (``pattern = true``) x points east and y north when the pad's heading is 0, and
the frame turns clockwise with the heading. The printed pattern is data, like the world file:
the simulator's renderer draws it and the pose estimator (``hdrc3_perception.pad_pose``) knows it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

TRIPLETS = 5
BASE_RADIUS_M = 0.02
BASE_SIDE_M = 0.08
INNER_RATIOS = (0.2, 0.33, 0.46, 0.59, 0.72)
"""Inner (white) radius over outer (black) radius; neighbours differ by 0.13."""
CODES = ((0, 1, 2), (0, 2, 4), (1, 3, 4), (0, 3, 4), (1, 2, 3))
"""Per triplet, the indices into :data:`INNER_RATIOS` of its corners, counter-clockwise."""
PAD_HALF_WIDTH_M = 1.1
"""The white plate is a 2.2 m square: the largest triplet's circles end 1.06 m from the centre."""
PRINT_HEIGHT_M = 0.07
"""Height of the printed pattern (the pad frame's origin) above the terrain at the pad's centre:
the pad's surface and the plate on it (the renderer draws it there)."""


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


def pad_axes(heading: float) -> NDArray[np.float64]:
    """Rotation taking pad-frame vectors to ENU for a pad turned ``heading`` (rad, clockwise)."""
    s, c = math.sin(heading), math.cos(heading)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def pad_origin(east: float, north: float, ground: float) -> NDArray[np.float64]:
    """ENU position of the pad frame's origin for a pad centred at (east, north) on ``ground``."""
    return np.array([east, north, ground + PRINT_HEIGHT_M])
