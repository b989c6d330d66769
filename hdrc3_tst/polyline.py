"""Fly-path's polyline: cubic segments through waypoints (§7.2).

The scan-area coverage geometry lives in :mod:`hdrc3_navigation.coverage`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from hdrc3_control.path_segment import PathSegment
from hdrc3_tst.errors import TstError


def polyline(points: Sequence[tuple[float, float, float]], speed: float) -> list[PathSegment]:
    """Segments through ``points`` with tangents along the neighbouring chords (fly-path).

    At each inner waypoint the tangent is the mean of the incoming and outgoing chord
    directions, so the path passes through every point without stopping; it stops at the last.

    Raises:
        TstError: fewer than two distinct points.
    """
    pts = [p for i, p in enumerate(points) if i == 0 or math.dist(p, points[i - 1]) >= 0.1]
    if len(pts) < 2:
        raise TstError("a path needs at least two distinct points")

    def unit(a: Sequence[float], b: Sequence[float]) -> tuple[float, float, float]:
        n = math.dist(a, b)
        return ((b[0] - a[0]) / n, (b[1] - a[1]) / n, (b[2] - a[2]) / n)

    chords = [unit(pts[i], pts[i + 1]) for i in range(len(pts) - 1)]
    tangents = [chords[0]]
    for i in range(1, len(pts) - 1):
        mean = tuple(chords[i - 1][k] + chords[i][k] for k in range(3))
        norm = math.sqrt(sum(v * v for v in mean))
        tangents.append(
            chords[i] if norm < 1e-6 else (mean[0] / norm, mean[1] / norm, mean[2] / norm)
        )
    tangents.append(chords[-1])
    return [
        PathSegment(
            pts[i],
            pts[i + 1],
            tangents[i],
            tangents[i + 1],
            speed,
            0.0 if i == len(pts) - 2 else speed,
            i,
        )
        for i in range(len(pts) - 1)
    ]
