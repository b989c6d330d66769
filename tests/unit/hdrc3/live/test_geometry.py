from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3.live.geometry import attitude_quaternion, height_color, timestamp


def rotate(q: tuple[float, ...], v: tuple[float, float, float]) -> np.ndarray:
    x, y, z, w = q
    m = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return m @ np.array(v)


@pytest.mark.parametrize(
    ("roll", "pitch", "heading", "body_axis", "enu"),
    [
        (0.0, 0.0, 0.0, (1, 0, 0), (0, 1, 0)),  # heading north: nose along +y (north)
        (0.0, 0.0, math.pi / 2, (1, 0, 0), (1, 0, 0)),  # heading east: nose along +x
        (0.0, 0.0, math.pi, (1, 0, 0), (0, -1, 0)),
        (0.0, math.pi / 2, math.pi / 2, (1, 0, 0), (0, 0, 1)),  # nose up
        (math.pi / 2, 0.0, math.pi / 2, (0, 1, 0), (0, 0, 1)),  # right wing down: left wing up
    ],
)
def test_attitude_quaternion_turns_the_body_axes(roll, pitch, heading, body_axis, enu):
    q = attitude_quaternion(roll, pitch, heading)
    assert math.isclose(sum(c * c for c in q), 1.0)
    assert rotate(q, body_axis) == pytest.approx(np.array(enu, float), abs=1e-9)


@pytest.mark.parametrize(("ns", "sec", "nsec"), [(0, 0, 0), (1_500_000_000, 1, 500_000_000)])
def test_timestamp_splits_nanoseconds(ns, sec, nsec):
    t = timestamp(ns)
    assert (t.sec, t.nsec) == (sec, nsec)


def test_height_color_is_defined_for_a_flat_terrain():
    height_color(5.0, 5.0, 5.0)  # no division by zero
