"""Multi-level paths (chapter section 7.1.2, Figures 20-21): from a linear path to cubic segments.

In the chapter's order: the linear path from the graph search; node alignment (move a node half
way, then all the way, to the midpoint of its neighbours when the new linear pieces are valid);
curve replacement (each linear piece becomes a cubic ``p(s) = A s^3 + B s^2 + C s + D`` whose
end tangents follow the neighbours; a waypoint where a cubic does not fit becomes a stop-and-hover
corner with straight pieces); node elimination (drop a node when its neighbours connect
directly, curves included). Segment target and end velocities come from the requested speed and
the curvature limit ``V = sqrt(phi_max g R)`` of :mod:`hdrc3_control.velocity_profile`.

A fixed start direction (a replan that joins the segment the aircraft is flying, whose end tangent
it is) makes the first segment's start tangent that direction: the start cannot be a corner. The
first cubic must then pass the curve check and be regular (no loop, no cusp: no turn tighter than
:data:`JOIN_MIN_RADIUS`, ``|p'(s)|`` at least a quarter of the chord); if it does not, a waypoint
:data:`JOIN_STEPS` metres along the direction is tried before the rest of the path (straight pieces
to it and on from it checked; elimination keeps the first segment joined); if nothing fits,
:func:`multilevel` answers None (the planner then searches on from such a waypoint).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_control.path_segment import PathSegment
from hdrc3_control.velocity_profile import ProfileLimits, compatible_speed
from hdrc3_navigation.gis import Point3

LineTest = Callable[[Point3, Point3], bool]
CurveTest = Callable[[NDArray[np.float64]], bool]
SAMPLE_SPACING = 3.0
"""Curves are checked as polylines with pieces of at most this length, m."""
_CURVATURE_SAMPLES = 17
JOIN_STEPS = (20.0, 10.0, 5.0)
"""Distances along a fixed start direction where a joining waypoint is tried, in this order, m:
the longest first, the gentlest join (where the waypoint becomes a hover stop, the least
braking); the first that joins is taken."""
JOIN_MIN_RADIUS = 5.0
"""Tightest turn of the first segment from a fixed start direction, m (no cusps or loops)."""
_JOIN_SAMPLES = 65


@dataclass(frozen=True, slots=True)
class Checks:
    """Validity tests of the current query: straight pieces and sampled curves."""

    line: LineTest
    curve: CurveTest


def align(points: NDArray[np.float64], checks: Checks) -> NDArray[np.float64]:
    """Node alignment (Figure 21): half way to the neighbours' midpoint, then all the way."""
    out = points.copy()
    for k in range(1, len(out) - 1):
        a, c = out[k - 1], out[k + 1]
        mid = (a + c) / 2.0
        for target in ((out[k] + mid) / 2.0, mid):
            if checks.line(a, target) and checks.line(target, c):
                out[k] = target
    return out


Direction = NDArray[np.float64] | None
"""A fixed start direction of the path (None: free)."""


def _direction(
    points: NDArray[np.float64],
    k: int,
    smooth: Sequence[bool],
    incoming: bool,
    start: Direction = None,
) -> NDArray[np.float64]:
    if k == 0 and start is not None:
        return start
    if smooth[k]:
        out: NDArray[np.float64] = points[k + 1] - points[k - 1]
    elif incoming:
        out = points[k] - points[k - 1]
    else:
        out = points[k + 1] - points[k]
    return out


def _segment(
    points: NDArray[np.float64],
    smooth: Sequence[bool],
    i: int,
    speed: float = 1.0,
    start: Direction = None,
) -> PathSegment:
    a, b = points[i], points[i + 1]
    d0 = _direction(points, i, smooth, incoming=False, start=start)
    d1 = _direction(points, i + 1, smooth, incoming=True)
    return PathSegment(
        tuple(map(float, a)),  # type: ignore[arg-type]
        tuple(map(float, b)),  # type: ignore[arg-type]
        tuple(map(float, d0)),  # type: ignore[arg-type]
        tuple(map(float, d1)),  # type: ignore[arg-type]
        speed,
        segment_id=i,
    )


def sample(segment: PathSegment) -> NDArray[np.float64]:
    """The segment as a polyline with pieces of at most :data:`SAMPLE_SPACING` (approx.)."""
    chord = math.dist(segment.start, segment.end)
    n = max(2, math.ceil(1.6 * chord / SAMPLE_SPACING))
    s = np.linspace(0.0, 1.0, n + 1)[:, None]
    a, b, c, d = (np.array(v) for v in segment.coefficients)
    out: NDArray[np.float64] = ((a * s + b) * s + c) * s + d
    return out


def _curve_ok(
    points: NDArray[np.float64],
    smooth: Sequence[bool],
    i: int,
    checks: Checks,
    start: Direction = None,
) -> bool:
    if i == 0 and start is not None:
        seg = _segment(points, smooth, 0, start=start)
        return _regular(seg) and checks.curve(sample(seg))
    if not (smooth[i] or smooth[i + 1]):
        return True  # straight piece between corners: valid since the linear path is
    return checks.curve(sample(_segment(points, smooth, i)))


def _regular(segment: PathSegment) -> bool:
    """No loop or cusp in a joining cubic.

    No turn tighter than JOIN_MIN_RADIUS, and ``|p'(s)|`` stays above a quarter of the chord (it
    falls to 0 where the curve turns back).
    """
    chord = math.dist(segment.start, segment.end)
    for x in np.linspace(0.0, 1.0, _JOIN_SAMPLES):
        s = float(x)
        if float(np.linalg.norm(segment.derivative(s))) < 0.25 * chord:
            return False
        if segment.curvature(s) * JOIN_MIN_RADIUS > 1.0:
            return False
    return True


def replace_curves(
    points: NDArray[np.float64], checks: Checks, start: Direction = None
) -> list[bool]:
    """Curve replacement: which waypoints are smooth (True) and which are hover corners."""
    n = len(points)
    smooth = [0 < k < n - 1 for k in range(n)]
    changed = True
    while changed:
        changed = False
        for i in range(n - 1):
            if not _curve_ok(points, smooth, i, checks, start):
                for k in (i, i + 1):
                    if smooth[k]:
                        smooth[k] = False
                        changed = True
    return smooth


def eliminate(
    points: NDArray[np.float64], smooth: list[bool], checks: Checks, start: Direction = None
) -> tuple[NDArray[np.float64], list[bool]]:
    """Node elimination: drop nodes whose neighbours connect directly (curves included)."""
    pts, flags = points, list(smooth)
    k = 1
    while k < len(pts) - 1:
        if checks.line(pts[k - 1], pts[k + 1]):
            cand = np.delete(pts, k, axis=0)
            cand_flags = flags[:k] + flags[k + 1 :]
            lo, hi = max(0, k - 2), min(len(cand) - 2, k)
            if all(_curve_ok(cand, cand_flags, i, checks, start) for i in range(lo, hi + 1)):
                pts, flags = cand, cand_flags
                continue
        k += 1
    return pts, flags


@dataclass(frozen=True, slots=True)
class Smoothed:
    """The final path: cubic segments, their lengths and the hover corners."""

    segments: list[PathSegment]
    lengths: list[float]
    corners: int
    """Interior waypoints where the aircraft stops and hovers."""


def segments_with_velocities(
    points: NDArray[np.float64],
    smooth: Sequence[bool],
    speed: float,
    limits: ProfileLimits,
    start: Direction = None,
) -> Smoothed:
    """Cubic segments with target velocities (speed, curvature) and end velocities."""
    raw = [_segment(points, smooth, i, start=start) for i in range(len(points) - 1)]
    cruise = min(speed, limits.max_speed)
    s = np.linspace(0.0, 1.0, _CURVATURE_SAMPLES)
    targets, starts, ends = [], [], []
    for seg in raw:
        v = [compatible_speed(seg.curvature(float(x)), limits.max_roll) for x in s]
        targets.append(min(cruise, *v))
        starts.append(min(cruise, v[0]))
        ends.append(min(cruise, v[-1]))
    segments, lengths = [], []
    for i, seg in enumerate(raw):
        last = i == len(raw) - 1
        end_v = 0.0 if last or not smooth[i + 1] else min(targets[i], targets[i + 1], ends[i])
        end_v = min(end_v, starts[i + 1]) if not last else end_v
        segments.append(
            PathSegment(
                seg.start, seg.end, seg.start_direction, seg.end_direction,
                targets[i], end_v, segment_id=i,
            )
        )  # fmt: skip
        lengths.append(seg.arc_length())
    corners = sum(1 for k in range(1, len(points) - 1) if not smooth[k])
    return Smoothed(segments, lengths, corners)


def multilevel(
    points: NDArray[np.float64],
    checks: Checks,
    speed: float,
    limits: ProfileLimits,
    start_direction: NDArray[np.float64] | None = None,
) -> Smoothed | None:
    """Linear path -> alignment -> curve replacement -> elimination -> segments.

    With ``start_direction`` (non-zero) the first segment leaves the start along it; None when no
    first segment along it fits (with or without a joining waypoint). Without it, never None.
    """
    pts = align(_dedupe(points), checks)
    if len(pts) > 2:  # alignment can move two waypoints onto one point: no segment between them
        pts = _dedupe(pts)
    if start_direction is None:
        pts, _ = eliminate(pts, replace_curves(pts, checks), checks)
        return segments_with_velocities(pts, replace_curves(pts, checks), speed, limits)
    direction = start_direction / float(np.linalg.norm(start_direction))
    for candidate in _join_candidates(pts, direction, checks):
        # elimination keeps the first segment joined (a joining waypoint goes only if the
        # cubic from the start along the direction to the node after it fits)
        smooth = replace_curves(candidate, checks, direction)
        cand, smooth = eliminate(candidate, smooth, checks, direction)
        smooth = replace_curves(cand, checks, direction)
        if _curve_ok(cand, smooth, 0, checks, direction):
            return segments_with_velocities(cand, smooth, speed, limits, direction)
    return None


def _join_candidates(
    pts: NDArray[np.float64], direction: NDArray[np.float64], checks: Checks
) -> Iterator[NDArray[np.float64]]:
    """The path as it is, then with a waypoint JOIN_STEPS along the direction after the start."""
    yield pts
    p0, p1 = pts[0], pts[1]
    for step in JOIN_STEPS:
        q = p0 + step * direction
        if float(np.linalg.norm(p1 - q)) < 0.5:
            continue
        if checks.line(p0, q) and checks.line(q, p1):
            yield np.insert(pts, 1, q, axis=0)


def _dedupe(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drop consecutive waypoints closer than 0.5 m (a segment needs a chord of 0.1 m)."""
    keep = [0]
    for i in range(1, len(points)):
        if float(np.linalg.norm(points[i] - points[keep[-1]])) >= 0.5:
            keep.append(i)
    if keep[-1] != len(points) - 1:
        keep[-1] = len(points) - 1
    return points[keep]
