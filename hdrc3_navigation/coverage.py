"""Area coverage for one or n heterogeneous platforms with full camera coverage (§11.1.1).

One platform flies a lawn-mower: legs along the long side of the polygon's minimum rotated
rectangle (fewest turns), spaced by the camera's ground footprint less :data:`OVERLAP`, the
first and last half a footprint inside the edge. Each leg is responsible for the strip of one
footprint width centred on it, and spans that strip's whole extent inside the polygon (shapely),
so every point of the area is within half a footprint of a leg: full coverage also for slanted
and non-convex areas (gaps of a concave area are flown over). Neighbouring legs alternate
direction and are joined by cubic U-turn segments, so the path is tangent-continuous.

n platforms (footprint from FOV and altitude, speed, start position) split the polygon into
bands parallel to the legs with area shares proportional to each platform's sweep rate
(footprint spacing x speed), so the sweep times are balanced; the band order and each
platform's entry corner are chosen to minimise the makespan including the transit from the
start (all orders for up to :data:`MAX_PERMUTED` platforms, else by the starts' positions across
the sweep). Each band is covered as above. Written here because the band split with a sweep
rate per platform is a few shapely calls; no maintained library plans camera coverage for
heterogeneous fleets.
"""

from __future__ import annotations

import enum
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import shapely
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry

from hdrc3_base.errors import Hdrc3Error
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.ppc_hardware import CAMERAS, COLOR, CameraSpec

OVERLAP = 0.2
"""Fraction of the footprint neighbouring legs share."""
MIN_LEG = 1.0
"""m: shorter strips are flown as a leg of this length."""
MAX_PERMUTED = 4
"""Up to this many platforms every band order is tried."""

Point2 = tuple[float, float]
Leg = tuple[Point2, Point2]


class CoverageError(Hdrc3Error):
    """The single-platform API was misused (bad polygon or numbers)."""


def footprint_width(altitude: float, camera: CameraSpec = COLOR, zoom: float = 0.0) -> float:
    """Width (m) of the ground strip a nadir camera sees from ``altitude`` m above ground."""
    return 2.0 * altitude * math.tan(camera.hfov(zoom) / 2.0)


def pair_footprint_width(altitude: float) -> float:
    """Ground strip both cameras see at zoom 0 (Algorithm 4 needs a thermal and a colour view).

    The thermal camera's 25 degrees bind, not the colour camera's 48.
    """
    return min(footprint_width(altitude, camera) for camera in CAMERAS.values())


@dataclass(frozen=True, slots=True)
class SweepAxes:
    """Unit vectors along the legs and across them, with an origin."""

    origin: Point2
    along: Point2
    across: Point2

    @staticmethod
    def of(area: BaseGeometry) -> SweepAxes:
        """Legs along the long side of the area's minimum rotated rectangle."""
        rect = area.minimum_rotated_rectangle
        corners = list(rect.exterior.coords)[:4]
        a, b = max(
            ((corners[0], corners[1]), (corners[1], corners[2])), key=lambda s: math.dist(*s)
        )
        length = max(math.dist(a, b), 1e-9)
        along = ((b[0] - a[0]) / length, (b[1] - a[1]) / length)
        return SweepAxes((a[0], a[1]), along, (-along[1], along[0]))

    def coords(self, point: Sequence[float]) -> Point2:
        """(along, across) coordinates of a point."""
        dx, dy = point[0] - self.origin[0], point[1] - self.origin[1]
        return (
            dx * self.along[0] + dy * self.along[1],
            dx * self.across[0] + dy * self.across[1],
        )

    def point(self, s: float, o: float) -> Point2:
        """The point at (along, across) coordinates."""
        return (
            self.origin[0] + s * self.along[0] + o * self.across[0],
            self.origin[1] + s * self.along[1] + o * self.across[1],
        )

    def band(self, o0: float, o1: float, reach: float) -> Polygon:
        """The band across in [o0, o1], along in [-reach, reach]."""
        return Polygon(
            [
                self.point(-reach, o0),
                self.point(reach, o0),
                self.point(reach, o1),
                self.point(-reach, o1),
            ]
        )

    def extent(self, area: BaseGeometry) -> tuple[float, float, float, float]:
        """(along min, along max, across min, across max) of an area's vertices."""
        pts = [self.coords(p) for p in shapely.get_coordinates(area)]
        s = [p[0] for p in pts]
        o = [p[1] for p in pts]
        return min(s), max(s), min(o), max(o)


def sweep_legs(area: BaseGeometry, footprint: float, axes: SweepAxes) -> list[Leg]:
    """Legs covering ``area`` (in order across, all in the +along direction)."""
    s0, s1, o0, o1 = axes.extent(area)
    reach = max(abs(s0), abs(s1)) + footprint + 10.0
    spacing = footprint * (1.0 - OVERLAP)
    usable = max(o1 - o0 - footprint, 0.0)
    count = math.ceil(usable / spacing) + 1 if usable > 0 else 1
    offsets = (
        [(o0 + o1) / 2.0]
        if count == 1
        else [o0 + footprint / 2.0 + i * usable / (count - 1) for i in range(count)]
    )
    legs: list[Leg] = []
    for offset in offsets:
        strip = area.intersection(
            axes.band(offset - footprint / 2.0, offset + footprint / 2.0, reach)
        )
        if strip.is_empty or strip.area <= 1e-9:
            continue
        a0, a1, _, _ = axes.extent(strip)
        if a1 - a0 < MIN_LEG:
            middle = (a0 + a1) / 2.0
            a0, a1 = middle - MIN_LEG / 2.0, middle + MIN_LEG / 2.0
        legs.append((axes.point(a0, offset), axes.point(a1, offset)))
    if not legs:  # a sliver: one short leg through it
        s, o = axes.coords(area.representative_point().coords[0])
        legs.append((axes.point(s - MIN_LEG / 2.0, o), axes.point(s + MIN_LEG / 2.0, o)))
    return legs


def _segments(
    legs: Sequence[Leg], z: float, leg_speed: float, turn_speed: float
) -> list[PathSegment]:
    """Legs (already in flight order and direction) joined by U-turns; stops at the end."""
    segments: list[PathSegment] = []
    for index, (start, end) in enumerate(legs):
        last = index == len(legs) - 1
        d = (end[0] - start[0], end[1] - start[1], 0.0)
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
    return segments


def _boustrophedon(legs: Sequence[Leg], reverse_order: bool, flip_first: bool) -> list[Leg]:
    ordered = list(reversed(legs)) if reverse_order else list(legs)
    return [
        (leg[1], leg[0]) if (i % 2 == 0) == flip_first else leg for i, leg in enumerate(ordered)
    ]


def _check_area(polygon: Sequence[Sequence[float]]) -> tuple[Polygon | None, str]:
    """The polygon, or None and why it cannot be covered."""
    if len(polygon) < 3 or any(len(p) < 2 for p in polygon):
        return None, f"an area needs at least 3 corners, got {len(polygon)}"
    if not all(math.isfinite(float(v)) for p in polygon for v in p[:2]):
        return None, "area corners must be finite"
    area = Polygon([(float(p[0]), float(p[1])) for p in polygon])
    if area.area <= 1e-6:
        return None, f"the area is empty: {shapely.to_wkt(area, rounding_precision=2)}"
    if not area.is_valid or not area.exterior.is_simple:
        return (
            None,
            f"the area is not a simple polygon: {shapely.to_wkt(area, rounding_precision=2)}",
        )
    return area, ""


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
        CoverageError: the polygon is not a simple polygon with an area, or the numbers are not
            positive and finite (callers validate areas first: :func:`plan_coverage` answers
            with a status instead).
    """
    numbers = (altitude_up, footprint, leg_speed, turn_speed)
    if not all(math.isfinite(v) for v in numbers) or min(footprint, leg_speed, turn_speed) <= 0:
        raise CoverageError(f"coverage needs a positive finite footprint and speeds, got {numbers}")
    area, reason = _check_area(polygon)
    if area is None:
        raise CoverageError(reason)
    legs = _boustrophedon(sweep_legs(area, footprint, SweepAxes.of(area)), False, False)
    return _segments(legs, altitude_up, leg_speed, turn_speed)


@dataclass(frozen=True, slots=True)
class Platform:
    """One aircraft of the fleet as coverage sees it."""

    name: str
    footprint: float
    """Ground strip width of its camera at the scan altitude, m (:func:`footprint_width`)."""
    speed: float
    """Leg speed, m/s."""
    start: Point2
    """Where it is when the scan is planned (east, north)."""

    @property
    def sweep_rate(self) -> float:
        """Area covered per second on the legs, m^2/s."""
        return self.footprint * (1.0 - OVERLAP) * self.speed


class CoverageStatus(enum.Enum):
    """Outcome of a coverage query."""

    PLANNED = "planned"
    NO_PLATFORMS = "no_platforms"
    BAD_PLATFORM = "bad_platform"
    BAD_NUMBERS = "bad_numbers"
    INVALID_AREA = "invalid_area"
    """Fewer than 3 corners, non-finite, empty or not a simple polygon."""
    OUTSIDE_WORLD = "outside_world"


@dataclass(frozen=True, slots=True)
class Assignment:
    """One platform's part of the area and its path."""

    platform: Platform
    part: BaseGeometry
    segments: tuple[PathSegment, ...]
    transit: float
    """Straight distance from the platform's start to its first leg, m."""
    duration: float
    """Transit at leg speed plus the path at its target speeds, s."""


@dataclass(frozen=True, slots=True)
class CoveragePlan:
    """Result of :func:`plan_coverage`."""

    status: CoverageStatus
    reason: str = ""
    assignments: tuple[Assignment, ...] = ()

    @property
    def makespan(self) -> float:
        """Time until the last platform finishes, s."""
        return max((a.duration for a in self.assignments), default=0.0)


def _fail(status: CoverageStatus, reason: str) -> CoveragePlan:
    return CoveragePlan(status, reason)


def plan_coverage(
    polygon: Sequence[Sequence[float]],
    platforms: Sequence[Platform],
    altitude_up: float,
    turn_speed: float = 3.0,
    bounds: tuple[float, float, float, float] | None = None,
) -> CoveragePlan:
    """Split ``polygon`` over ``platforms`` and plan each part's lawn-mower (see module doc).

    Args:
        polygon: The area's corners (east, north), m.
        platforms: The fleet; names must differ.
        altitude_up: Flight height, m (ENU up).
        turn_speed: Speed on the U-turns, m/s (capped by each platform's speed).
        bounds: (east_min, north_min, east_max, north_max) the area must lie in (the world).
    """
    area = _checked(polygon, platforms, altitude_up, turn_speed, bounds)
    if isinstance(area, CoveragePlan):
        return area
    axes = SweepAxes.of(area)
    if len(platforms) <= MAX_PERMUTED:
        orders = list(itertools.permutations(platforms))
    else:
        orders = [tuple(sorted(platforms, key=lambda p: axes.coords(p.start)[1]))]
    best: tuple[Assignment, ...] | None = None
    for order in orders:
        plan = _plan_order(area, axes, order, altitude_up, turn_speed)
        if best is None or max(a.duration for a in plan) < max(a.duration for a in best):
            best = plan
    assert best is not None
    by_name = {a.platform.name: a for a in best}
    return CoveragePlan(CoverageStatus.PLANNED, "", tuple(by_name[p.name] for p in platforms))


def plan_part(
    polygon: Sequence[Sequence[float]],
    part: int,
    parts: int,
    platform: Platform,
    altitude_up: float,
    turn_speed: float = 3.0,
    bounds: tuple[float, float, float, float] | None = None,
) -> CoveragePlan:
    """Band ``part`` (1-based) of ``parts`` equal bands of ``polygon``, flown by ``platform``.

    For aircraft that plan their share each on its own (a TST's concurrent scan nodes): the
    bands come in a fixed order across the sweep (band 1 at the low offset), so aircraft given
    the same polygon and number of parts agree on the split without talking; each enters its
    band at the corner nearest its own start. Equal bands assume equal sweep rates (use
    :func:`plan_coverage` when one planner knows the whole fleet).
    """
    if not (isinstance(part, int) and isinstance(parts, int) and 1 <= part <= parts):
        return _fail(CoverageStatus.BAD_NUMBERS, f"part {part} of {parts}: need 1 <= part <= parts")
    area = _checked(polygon, (platform,), altitude_up, turn_speed, bounds)
    if isinstance(area, CoveragePlan):
        return area
    axes = SweepAxes.of(area)
    cuts = _cuts(area, axes, [platform.sweep_rate] * parts)
    band = _assign(area, axes, platform, cuts[part - 1], cuts[part], altitude_up, turn_speed)
    return CoveragePlan(CoverageStatus.PLANNED, "", (band,))


def _checked(
    polygon: Sequence[Sequence[float]],
    platforms: Sequence[Platform],
    altitude_up: float,
    turn_speed: float,
    bounds: tuple[float, float, float, float] | None,
) -> Polygon | CoveragePlan:
    """The area to cover, or the failed plan that says what is wrong with the request."""
    if not platforms:
        return _fail(CoverageStatus.NO_PLATFORMS, "no platforms to cover the area")
    for p in platforms:
        values = (p.footprint, p.speed, *p.start)
        if not all(math.isfinite(v) for v in values) or p.footprint <= 0 or p.speed <= 0:
            return _fail(CoverageStatus.BAD_PLATFORM, f"{p.name}: footprint, speed, start {values}")
    if len({p.name for p in platforms}) != len(platforms):
        return _fail(CoverageStatus.BAD_PLATFORM, "platform names must differ")
    if not (math.isfinite(altitude_up) and math.isfinite(turn_speed) and turn_speed > 0):
        return _fail(CoverageStatus.BAD_NUMBERS, f"altitude {altitude_up}, turn speed {turn_speed}")
    area, reason = _check_area(polygon)
    if area is None:
        return _fail(CoverageStatus.INVALID_AREA, reason)
    if bounds is not None and not box(*bounds).covers(area):
        return _fail(CoverageStatus.OUTSIDE_WORLD, f"the area leaves the world's extent {bounds}")
    return area


def _cut(
    area: Polygon, axes: SweepAxes, fraction: float, o0: float, o1: float, reach: float
) -> float:
    """Across offset below which ``fraction`` of the area lies (bisection)."""
    target = fraction * area.area
    low, high = o0, o1
    for _ in range(48):
        middle = (low + high) / 2.0
        if area.intersection(axes.band(o0 - 1.0, middle, reach)).area < target:
            low = middle
        else:
            high = middle
    return (low + high) / 2.0


def _plan_order(
    area: Polygon,
    axes: SweepAxes,
    order: Sequence[Platform],
    altitude_up: float,
    turn_speed: float,
) -> tuple[Assignment, ...]:
    cuts = _cuts(area, axes, [p.sweep_rate for p in order])
    return tuple(
        _assign(area, axes, p, low, high, altitude_up, turn_speed)
        for p, low, high in zip(order, cuts, cuts[1:], strict=False)
    )


def _reach(area: Polygon, axes: SweepAxes) -> float:
    s0, s1, _, _ = axes.extent(area)
    return max(abs(s0), abs(s1)) + 10.0


def _cuts(area: Polygon, axes: SweepAxes, rates: Sequence[float]) -> list[float]:
    """Across offsets bounding bands whose area shares are the ``rates``' shares, in order."""
    _, _, o0, o1 = axes.extent(area)
    reach = _reach(area, axes)
    total = sum(rates)
    cuts, share = [o0], 0.0
    for rate in rates[:-1]:
        share += rate / total
        cuts.append(_cut(area, axes, share, o0, o1, reach))
    cuts.append(o1)
    return cuts


def _assign(
    area: Polygon,
    axes: SweepAxes,
    p: Platform,
    low: float,
    high: float,
    altitude_up: float,
    turn_speed: float,
) -> Assignment:
    """The band between two across offsets, flown by ``p`` from the corner nearest its start."""
    part = area.intersection(axes.band(low, high, _reach(area, axes)))
    legs = sweep_legs(part, p.footprint, axes)
    turn = min(turn_speed, p.speed)
    options = [_boustrophedon(legs, r, f) for r in (False, True) for f in (False, True)]
    flown = min(options, key=lambda ls: math.dist(p.start, ls[0][0]))
    segments = tuple(_segments(flown, altitude_up, p.speed, turn))
    transit = math.dist(p.start, flown[0][0])
    duration = transit / p.speed + sum(s.arc_length() / s.target_velocity for s in segments)
    return Assignment(p, part, segments, transit, duration)
