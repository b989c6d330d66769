"""Paths the flight executors stream: lawn-mower coverage of a polygon, and a polyline (§7.2).

Coverage sweeps the polygon along the long side of its minimum rotated rectangle (fewest
turns). Legs are spaced by at most the camera's ground footprint at the scan altitude less an
overlap, the first and last leg half a footprint inside the edge, and each leg is the part of
its line inside the polygon (shapely), so a concave or slanted area is covered without flying
far outside it. Neighbouring legs alternate direction and are joined by cubic U-turn segments
(:class:`~hdrc3_control.path_segment.PathSegment`), so the path is tangent-continuous and the
path-following mode flies it without stopping; the last segment ends with zero velocity.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import shapely
from shapely.geometry import LineString, Polygon

from hdrc3_control.path_segment import PathSegment
from hdrc3_control.ppc_hardware import COLOR, CameraSpec
from hdrc3_tst.errors import TstError

OVERLAP = 0.2
"""Fraction of the footprint neighbouring legs share."""
MIN_LEG = 1.0
"""m: shorter leg pieces are dropped (the footprint of the neighbours covers them)."""


def footprint_width(altitude: float, camera: CameraSpec = COLOR, zoom: float = 0.0) -> float:
    """Width (m) of the ground strip a nadir camera sees from ``altitude`` m above ground."""
    return 2.0 * altitude * math.tan(camera.hfov(zoom) / 2.0)


def _legs(area: Polygon, footprint: float) -> list[tuple[tuple[float, float], ...]]:
    """Leg lines (start, end) in sweep order, alternating direction."""
    rect = area.minimum_rotated_rectangle
    corners = list(rect.exterior.coords)[:4]
    sides = [(corners[i], corners[(i + 1) % 4]) for i in range(2)]
    a, b = max(sides, key=lambda s: math.dist(*s))
    length = max(math.dist(a, b), 1e-9)
    across_len = min(math.dist(*s) for s in sides)
    along = ((b[0] - a[0]) / length, (b[1] - a[1]) / length)
    across = (-along[1], along[0])
    centre = rect.centroid
    if (centre.x - a[0]) * across[0] + (centre.y - a[1]) * across[1] < 0:
        across = (-across[0], -across[1])
    spacing = footprint * (1.0 - OVERLAP)
    usable = max(across_len - footprint, 0.0)
    count = math.ceil(usable / spacing) + 1 if usable > 0 else 1
    offsets = (
        [across_len / 2.0]
        if count == 1
        else [footprint / 2.0 + i * usable / (count - 1) for i in range(count)]
    )
    reach = length + 2.0
    legs: list[tuple[tuple[float, float], ...]] = []
    for offset in offsets:
        ox, oy = a[0] + across[0] * offset, a[1] + across[1] * offset
        line = LineString(
            [(ox - along[0], oy - along[1]), (ox + along[0] * reach, oy + along[1] * reach)]
        )
        cut = line.intersection(area)
        pieces = [g for g in getattr(cut, "geoms", [cut]) if isinstance(g, LineString)]
        pieces = [p for p in pieces if p.length >= MIN_LEG]
        if not pieces:
            continue
        # one leg per line: from the first to the last point inside (concave gaps are flown over)
        coords = [pt for p in pieces for pt in p.coords]
        start = min(coords, key=lambda p: (p[0] - a[0]) * along[0] + (p[1] - a[1]) * along[1])
        end = max(coords, key=lambda p: (p[0] - a[0]) * along[0] + (p[1] - a[1]) * along[1])
        leg = ((float(start[0]), float(start[1])), (float(end[0]), float(end[1])))
        legs.append(leg if len(legs) % 2 == 0 else leg[::-1])
    return legs


def lawn_mower(
    polygon: Sequence[tuple[float, ...]],
    altitude_up: float,
    footprint: float,
    leg_speed: float,
    turn_speed: float,
) -> list[PathSegment]:
    """Coverage segments of a polygon (local ENU metres) flown at ``altitude_up`` (ENU up).

    Args:
        polygon: The area's corners (east, north).
        altitude_up: Flight height, m (ENU up of the world's origin).
        footprint: Width of the ground strip the camera sees, m (:func:`footprint_width`);
            neighbouring legs share :data:`OVERLAP` of it.
        leg_speed: Target speed on the legs, m/s.
        turn_speed: Target speed on the U-turns, m/s.

    Returns:
        Segments in flight order; only the last has ``end_velocity == 0``.

    Raises:
        TstError: the polygon is not a simple polygon with an area, or the numbers are not
            positive and finite (the resolver rejects such areas first: this is misuse).
    """
    area = Polygon([(p[0], p[1]) for p in polygon])
    numbers = (altitude_up, footprint, leg_speed, turn_speed)
    if not all(math.isfinite(v) for v in numbers) or min(footprint, leg_speed, turn_speed) <= 0:
        raise TstError(f"coverage needs a positive finite footprint and speeds, got {numbers}")
    if not area.is_valid or area.area <= 0.0:
        raise TstError(f"coverage needs a simple polygon with an area: {shapely.to_wkt(area)}")
    legs = _legs(area, footprint)
    z = altitude_up
    segments: list[PathSegment] = []
    for index, (start, end) in enumerate(legs):
        last = index == len(legs) - 1
        d = (end[0] - start[0], end[1] - start[1], 0.0)
        if math.hypot(d[0], d[1]) < 0.1:
            continue
        segments.append(
            PathSegment(
                (*start, z), (*end, z), d, d, leg_speed, 0.0 if last else turn_speed, len(segments)
            )
        )
        if last:
            break
        nxt = legs[index + 1][0]
        reverse = (-d[0], -d[1], 0.0)
        segments.append(
            PathSegment((*end, z), (*nxt, z), d, reverse, turn_speed, turn_speed, len(segments))
        )
    if segments and segments[-1].end_velocity != 0.0:
        last_seg = segments[-1]
        segments[-1] = PathSegment(
            last_seg.start,
            last_seg.end,
            last_seg.start_direction,
            last_seg.end_direction,
            last_seg.target_velocity,
            0.0,
            last_seg.segment_id,
        )
    return segments


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
