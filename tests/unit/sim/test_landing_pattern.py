"""The landing pad's pattern: five triplets that never touch, told apart by their inner circles."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from sim.landing_pattern import (
    CIRCLES,
    CODES,
    INNER_RATIOS,
    PAD_HALF_WIDTH_M,
    TRIPLETS,
    is_black,
    triplet_of_codes,
)


def test_five_triplets_of_the_chapters_sizes() -> None:
    radii = sorted({c.radius for c in CIRCLES})
    assert len(CIRCLES) == 3 * TRIPLETS
    assert radii[0] == pytest.approx(0.02) and radii[-1] == pytest.approx(0.32)  # 2 to 32 cm
    for k in range(TRIPLETS):
        corners = [c for c in CIRCLES if c.triplet == k]
        sides = {
            round(math.dist((p.x, p.y), (q.x, q.y)), 9)
            for p, q in itertools.combinations(corners, 2)
        }
        assert sides == {round(0.08 * 2**k, 9)}  # 8 to 128 cm, equilateral


def test_no_two_circles_touch_and_all_lie_on_the_pad() -> None:
    for p, q in itertools.combinations(CIRCLES, 2):
        assert math.dist((p.x, p.y), (q.x, q.y)) > p.radius + q.radius
    for c in CIRCLES:
        assert max(abs(c.x), abs(c.y)) + c.radius < PAD_HALF_WIDTH_M


def test_codes_tell_triplets_and_corners_apart() -> None:
    assert len({frozenset(code) for code in CODES}) == TRIPLETS
    for k, code in enumerate(CODES):
        assert len(set(code)) == 3
        assert triplet_of_codes(frozenset(code)) == k
        mirrored = tuple(reversed(code))  # read clockwise: a different cyclic order
        assert all(mirrored[i:] + mirrored[:i] != code for i in range(3))
    assert triplet_of_codes(frozenset({0, 1, 4})) is None
    assert all(b - a > 0.1 for a, b in itertools.pairwise(INNER_RATIOS))


@pytest.mark.parametrize(
    ("where", "black"),
    [
        ("ring", True),  # between the hole and the edge of a circle
        ("hole", False),  # the white inner circle
        ("centre", False),  # the pad's centre is white
    ],
)
def test_is_black(where: str, black: bool) -> None:
    c = CIRCLES[7]
    point = {
        "ring": (c.x + c.radius * (1 + c.inner_ratio) / 2, c.y),
        "hole": (c.x, c.y),
        "centre": (0.0, 0.0),
    }[where]
    assert bool(is_black(np.array(point[0]), np.array(point[1]))) is black
