from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pytest

from hdrc3_control.velocity_profile import ProfileLimits, compatible_speed
from hdrc3_navigation.multilevel import (
    Checks,
    align,
    eliminate,
    multilevel,
    replace_curves,
    sample,
    segments_with_velocities,
)

LIMITS = ProfileLimits()


def free_space() -> Checks:
    return Checks(lambda a, b: True, lambda pts: True)


def forbidden_box(lo: Sequence[float], hi: Sequence[float]) -> Checks:
    """Nothing may come into an axis-aligned box (tested on dense samples)."""
    lo_a, hi_a = np.array(lo), np.array(hi)

    def clear(pts: np.ndarray) -> bool:  # type: ignore[type-arg]
        return not bool(np.any(np.all((pts >= lo_a) & (pts <= hi_a), axis=1)))

    def line(a: Sequence[float], b: Sequence[float]) -> bool:
        return clear(np.linspace(a, b, 200))

    return Checks(line, clear)


ZIGZAG = np.array([[0.0, 0, 10], [50, 20, 10], [100, 0, 10], [150, 20, 10], [200, 0, 10]])


def test_alignment_straightens_free_nodes_to_the_midpoint() -> None:
    out = align(ZIGZAG, free_space())
    # node 1 moves all the way to the midpoint of nodes 0 and 2 (its moved predecessor counts)
    assert out[1] == pytest.approx([50.0, 0.0, 10.0])
    assert out[0] == pytest.approx(ZIGZAG[0]) and out[-1] == pytest.approx(ZIGZAG[-1])


def test_alignment_stops_half_way_when_the_midpoint_is_blocked() -> None:
    pts = np.array([[0.0, 0, 10], [50, 40, 10], [100, 0, 10]])
    checks = forbidden_box((45, -5, 0), (55, 5, 20))  # covers the midpoint (50, 0)
    out = align(pts, checks)
    assert out[1] == pytest.approx([50.0, 20.0, 10.0])


def test_elimination_removes_nodes_that_the_neighbours_see() -> None:
    pts = np.array([[0.0, 0, 10], [50, 0, 10], [100, 0, 10], [100, 50, 10]])
    out, _ = eliminate(pts, replace_curves(pts, free_space()), free_space())
    assert len(out) == 2  # even the corner goes: the diagonal is free
    checks = forbidden_box((60, 10, 0), (90, 40, 20))  # blocks the diagonal and short cuts
    out, _flags = eliminate(pts, replace_curves(pts, checks), checks)
    assert [list(p) for p in out] == [[0, 0, 10], [100, 0, 10], [100, 50, 10]]


def test_curves_replace_lines_and_a_blocked_curve_becomes_a_hover_stop() -> None:
    pts = np.array([[0.0, 0, 10], [100, 0, 10], [100, 100, 10]])
    smooth = replace_curves(pts, free_space())
    assert smooth == [False, True, False]
    # the cubic swings out beyond the corner (y < 0 before it): forbid that side
    checks = forbidden_box((20, -40, 0), (99, -0.5, 20))
    smooth = replace_curves(pts, checks)
    assert smooth == [False, False, False]
    out = segments_with_velocities(pts, smooth, 10.0, LIMITS)
    assert out.corners == 1
    assert out.segments[0].end_velocity == 0.0  # stop and hover at the corner
    for seg in out.segments:
        assert seg.curvature(0.5) == pytest.approx(0.0, abs=1e-9)


def test_velocities_follow_speed_and_curvature_limit() -> None:
    pts = np.array([[0.0, 0, 10], [100, 0, 10], [100, 100, 10], [0, 100, 10]])
    out = segments_with_velocities(pts, [False, True, True, False], 30.0, LIMITS)
    for seg in out.segments:
        kmax = max(seg.curvature(float(s)) for s in np.linspace(0, 1, 17))
        assert (
            seg.target_velocity
            <= min(LIMITS.max_speed, compatible_speed(kmax, LIMITS.max_roll)) + 1e-9
        )
    assert out.segments[0].end_velocity > 0.0  # smooth: no stop
    assert out.segments[-1].end_velocity == 0.0
    assert out.segments[0].end == out.segments[1].start


def test_multilevel_path_is_continuous_and_keeps_its_ends() -> None:
    out = multilevel(ZIGZAG, free_space(), 8.0, LIMITS)
    assert out.segments[0].start == tuple(ZIGZAG[0]) and out.segments[-1].end == tuple(ZIGZAG[-1])
    assert sum(out.lengths) == pytest.approx(200.0, rel=1e-3)  # straightened out completely


def test_samples_are_dense_enough_for_the_checks() -> None:
    out = segments_with_velocities(ZIGZAG, [False, True, True, True, False], 8.0, LIMITS)
    for seg in out.segments:
        pts = sample(seg)
        gaps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        assert gaps.max() <= 3.0 and math.dist(pts[0], seg.start) == 0.0


def _unit(v: Sequence[float]) -> np.ndarray:  # type: ignore[type-arg]
    a = np.array(v, float)
    return a / np.linalg.norm(a)


LINE = np.array([[0.0, 0, 10], [100, 0, 10]])
# (direction, checks, joining waypoint expected after the start (None: none), hover stops)
JOINS = {
    "along the path": ((1.0, 0.0, 0.0), free_space(), None, 0),
    "sideways: a cubic": ((0.0, 1.0, 0.0), free_space(), None, 0),
    "climbing: a cubic": ((1.0, 0.0, 0.5), free_space(), None, 0),
    "backwards: a cusp, so a stop 20 m on": (
        (-1.0, 0.0, 0.0), free_space(), (-20.0, 0.0, 10.0), 1
    ),
    # the sideways cubic swings out to y = 14.8: blocked beyond y = 10.5, so is a waypoint 20 m
    # on; one 10 m on is clear, but the cubic to it would turn on a 1 m radius: a stop there
    "sideways, the wide cubic blocked: a stop 10 m on": (
        (0.0, 1.0, 0.0), forbidden_box((-50, 10.5, 0), (150, 80, 20)), (0.0, 10.0, 10.0), 1
    ),
}  # fmt: skip


@pytest.mark.parametrize(("direction", "checks", "waypoint", "stops"), JOINS.values(), ids=JOINS)
def test_the_first_segment_leaves_along_the_start_direction(
    direction: tuple[float, float, float],
    checks: Checks,
    waypoint: tuple[float, float, float] | None,
    stops: int,
) -> None:
    out = multilevel(LINE, checks, 8.0, LIMITS, np.array(direction))
    assert out is not None
    first = out.segments[0]
    assert first.start == tuple(LINE[0]) and out.segments[-1].end == tuple(LINE[-1])
    assert first.tangent(0.0) == pytest.approx(_unit(direction))
    assert out.corners == stops
    if waypoint is None:
        assert len(out.segments) == 1
    else:
        assert first.end == pytest.approx(waypoint)
    for seg in out.segments:
        assert checks.curve(np.array([seg.position(s) for s in np.linspace(0, 1, 201)]))


@pytest.mark.parametrize(
    ("direction", "checks"),
    [
        ((0.0, 1.0, 0.0), forbidden_box((-30, 2, 0), (30, 30, 20))),
        ((-1.0, 0.0, 0.0), forbidden_box((-30, -30, 0), (-2, 30, 20))),
    ],
    ids=["sideways into a wall", "backwards into a wall"],
)
def test_a_start_direction_into_a_wall_cannot_be_joined(
    direction: tuple[float, float, float], checks: Checks
) -> None:
    assert multilevel(LINE, checks, 8.0, LIMITS, np.array(direction)) is None
    assert multilevel(LINE, checks, 8.0, LIMITS) is not None  # free, the line is fine


def test_elimination_keeps_the_node_that_joins_the_start_direction() -> None:
    # Sideways from the start, the cubic to (100, 0) swings out to y = 14.8 (blocked beyond
    # 10.5), the one to (50, 0) to y = 7.4: eliminating (50, 0) first left nothing to join
    # (a waypoint 5 or 10 m along the direction cannot see (100, 0) past the box).
    pts = np.array([[0.0, 0, 10], [50, 0, 10], [100, 0, 10]])
    wide = forbidden_box((-50, 10.5, 0), (150, 80, 20))
    box = forbidden_box((70, 1, 0), (80, 4, 20))
    checks = Checks(
        lambda a, b: wide.line(a, b) and box.line(a, b),
        lambda p: wide.curve(p) and box.curve(p),
    )
    out = multilevel(pts, checks, 8.0, LIMITS, np.array([0.0, 1.0, 0.0]))
    assert out is not None and out.corners == 0
    assert [seg.end for seg in out.segments] == [(50.0, 0.0, 10.0), (100.0, 0.0, 10.0)]
    assert out.segments[0].tangent(0.0) == pytest.approx([0.0, 1.0, 0.0])
    assert len(multilevel(pts, checks, 8.0, LIMITS).segments) == 1  # free start: eliminated


@pytest.mark.parametrize(
    "start_direction", [None, np.array([1.0, 0.0, 0.0])], ids=["free", "fixed"]
)
def test_a_waypoint_aligned_onto_its_neighbour_leaves_no_zero_length_segment(
    start_direction: np.ndarray | None,  # type: ignore[type-arg]
) -> None:
    # the path doubles back: alignment moves (5, 0) to the midpoint of its neighbours, 5 cm from
    # the start (a replanned path in flight did this and raised ConfigError)
    points = np.array([[0.0, 0, 10], [5, 0, 10], [0, 0.1, 10], [60, 60, 10]])
    assert float(np.linalg.norm(align(points, free_space())[1] - points[0])) < 0.1
    out = multilevel(points, free_space(), 8.0, LIMITS, start_direction)
    assert out is not None
    assert out.segments[0].start == tuple(points[0]) and out.segments[-1].end == tuple(points[-1])
    assert min(out.lengths) > 0.1
