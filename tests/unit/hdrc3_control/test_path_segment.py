"""Cubic segments: boundary conditions, curvature, arc length, closest point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_control.path_segment import PathSegment

TURN = PathSegment((0.0, 0.0, 10.0), (30.0, 30.0, 10.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 5.0)
CLIMB = PathSegment.straight((1.0, 2.0, 3.0), (1.0, 2.0, 23.0), 2.0)
DIAG = PathSegment.straight((0.0, 0.0, 0.0), (30.0, 40.0, 0.0), 8.0)


@pytest.mark.parametrize("seg", [TURN, CLIMB, DIAG])
def test_boundary_conditions(seg: PathSegment) -> None:
    np.testing.assert_allclose(seg.position(0.0), seg.start, atol=1e-12)
    np.testing.assert_allclose(seg.position(1.0), seg.end, atol=1e-12)
    for s, direction in ((0.0, seg.start_direction), (1.0, seg.end_direction)):
        d = np.array(direction) / np.linalg.norm(direction)
        np.testing.assert_allclose(seg.tangent(s), d, atol=1e-12)


@pytest.mark.parametrize(("seg", "length"), [(CLIMB, 20.0), (DIAG, 50.0), (TURN, None)])
def test_arc_length(seg: PathSegment, length: float | None) -> None:
    pts = np.array([seg.position(s) for s in np.linspace(0, 1, 4001)])
    polyline = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    assert seg.arc_length() == pytest.approx(polyline, rel=1e-5)
    if length is not None:
        assert seg.arc_length() == pytest.approx(length)


def test_curvature_zero_on_straight_and_matches_osculating_circle() -> None:
    assert max(DIAG.curvature(s) for s in np.linspace(0, 1, 11)) < 1e-12
    # a quarter turn of radius ~30 m: curvature between 1/60 and 1/15 and pointing inwards
    k = TURN.curvature(0.5)
    assert 1 / 60 < k < 1 / 15
    kv = TURN.curvature_vector(0.5)
    assert np.linalg.norm(kv) == pytest.approx(k)
    centre_dir = np.array([0.0, 30.0, 10.0]) - TURN.position(0.5)
    assert float(kv @ centre_dir) > 0.0


@pytest.mark.parametrize(
    ("point", "expected"),
    [((15.0, 20.0, 5.0), 0.5), ((-10.0, -10.0, 0.0), 0.0), ((100.0, 100.0, 0.0), 1.0)],
)
def test_closest_parameter_on_straight(point: tuple[float, float, float], expected: float) -> None:
    assert DIAG.closest_parameter(point) == pytest.approx(expected, abs=1e-9)


def test_closest_point_on_curve_is_orthogonal() -> None:
    x = np.array([20.0, 5.0, 10.0])
    s = TURN.closest_parameter((20.0, 5.0, 10.0))
    assert 0.0 < s < 1.0
    assert float((x - TURN.position(s)) @ TURN.tangent(s)) == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"end": (0.0, 0.0, 10.0)},
        {"start_direction": (0.0, 0.0, 0.0)},
        {"target_velocity": -1.0},
        {"end_velocity": math.nan},
    ],
)
def test_bad_segments_raise(kwargs: dict[str, object]) -> None:
    base: dict[str, object] = {
        "start": (0.0, 0.0, 10.0),
        "end": (10.0, 0.0, 10.0),
        "start_direction": (1.0, 0.0, 0.0),
        "end_direction": (1.0, 0.0, 0.0),
        "target_velocity": 3.0,
    }
    base.update(kwargs)
    with pytest.raises(ConfigError):
        PathSegment(**base)  # type: ignore[arg-type]
