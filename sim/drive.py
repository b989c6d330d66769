"""A car driving along a road route: its pose as a pure function of sim time.

A kinematic road follower, hand-written because no library fits: the route's corners are
rounded with circular fillets, and the speed profile is the fastest one that keeps the
longitudinal acceleration within ``ACCELERATION`` and the lateral acceleration in the fillets
within ``LATERAL_ACCELERATION``. Vehicle-dynamics simulators steer a car model by integration
(drift, state to checkpoint); trajectory generators (ruckig, toppra) plan joint motions, not
road corners. Here the profile is solved once per drive in closed form, as phases of constant
acceleration, so the pose at sim time ``t`` is exact and the same for the same ``t``: nothing is
integrated, and a checkpoint needs only the sim time.

Geometry: the route is a polyline; at every corner a fillet of radius ``r`` replaces the
corner, tangent to both segments. ``r`` is the largest radius whose arc passes at most
``CORNER_CUT`` inside the waypoint (so the car stays within a road's half width at a
crossing), at least ``MIN_RADIUS`` (a car's turning circle), and small enough that the fillets
at both ends of a segment fit on it. Speeds: cruise on straights, ``sqrt(LATERAL_ACCELERATION
* r)`` (at most cruise) in a fillet, forward-backward passes over the piece boundaries for the
acceleration bound, departure from rest, and either a stop at the last waypoint or, on a loop,
a periodic lap after the first one.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from dataclasses import dataclass

from sim.world import Drive, Point2

MAX_SPEED = 15.0
"""m/s, the fastest cruise speed a drive may ask for."""
ACCELERATION = 2.0
"""m/s^2, longitudinal acceleration and braking of a driving car."""
LATERAL_ACCELERATION = 2.5
"""m/s^2, the most a car's speed in a corner fillet may ask for (v^2 / r)."""
CORNER_CUT = 2.5
"""m, how far a rounded corner's arc may pass inside its waypoint."""
MIN_RADIUS = 5.0
"""m, smallest corner fillet unless the segments are too short for it."""
MAX_TURN = math.radians(150.0)
"""rad, the sharpest turn a route may take at a waypoint (a U-turn cannot be rounded)."""
MIN_SEGMENT = 0.1
"""m, the shortest route segment (two waypoints closer than this are one)."""
_STRAIGHT = 1e-9
"""rad: a turn smaller than this is no corner."""


@dataclass(frozen=True, slots=True)
class DrivePose:
    """Where a driving car is at one instant."""

    east: float
    north: float
    heading: float
    """rad clockwise from north, in [0, 2 pi)."""
    speed: float
    """m/s along the path."""
    distance: float
    """m driven since it set off."""


@dataclass(frozen=True, slots=True)
class _Piece:
    """A straight or a circular arc of the path, starting ``s0`` m along it."""

    s0: float
    length: float
    east: float
    north: float
    heading: float
    """At the piece's start, rad clockwise from north."""
    curvature: float
    """1/m, positive turning right (clockwise), 0 on a straight."""
    limit: float
    """Speed limit on the piece, m/s."""

    def at(self, x: float) -> tuple[float, float, float]:
        """East, north and heading ``x`` m into the piece."""
        h0, k = self.heading, self.curvature
        if k == 0.0:
            return self.east + x * math.sin(h0), self.north + x * math.cos(h0), h0
        h = h0 + k * x
        return (
            self.east + (math.cos(h0) - math.cos(h)) / k,
            self.north + (math.sin(h) - math.sin(h0)) / k,
            h,
        )


@dataclass(frozen=True, slots=True)
class _Phase:
    """Constant acceleration from time ``t0`` (relative to departure) and distance ``s0``."""

    t0: float
    s0: float
    v0: float
    accel: float
    duration: float

    def at(self, t: float) -> tuple[float, float]:
        """Distance and speed at time ``t`` (clamped to the phase)."""
        tau = min(max(t - self.t0, 0.0), self.duration)
        return self.s0 + tau * (self.v0 + 0.5 * self.accel * tau), self.v0 + self.accel * tau


def drive_problem(drive: Drive) -> str | None:
    """Why ``drive`` cannot be driven (readable reason naming the waypoint), or None."""
    numbers = [drive.speed, drive.depart, *(c for p in drive.route for c in p)]
    if not all(math.isfinite(v) for v in numbers):
        return "drive values must be finite numbers"
    if not 0.0 < drive.speed <= MAX_SPEED:
        return f"speed must be > 0 and <= {MAX_SPEED} m/s, got {drive.speed}"
    if drive.depart < 0.0:
        return f"depart must be >= 0 s, got {drive.depart}"
    points = _waypoints(drive)
    needed = 3 if drive.loop else 2
    if len(points) < needed:
        what = "a looping route" if drive.loop else "a route"
        return f"{what} needs at least {needed} distinct waypoints, got {len(points)}"
    closing = len(points) if drive.loop else len(points) - 1
    for j in range(closing):
        (e0, n0), (e1, n1) = points[j], points[(j + 1) % len(points)]
        if math.hypot(e1 - e0, n1 - n0) < MIN_SEGMENT:
            return (
                f"route waypoints {j} and {(j + 1) % len(points)} are closer than {MIN_SEGMENT} m"
            )
    for k, turn in _turns(points, drive.loop).items():
        if abs(turn) > MAX_TURN:
            return (
                f"route turns by {math.degrees(abs(turn)):.0f} deg at waypoint {k} "
                f"(at most {math.degrees(MAX_TURN):.0f})"
            )
    return None


@dataclass(frozen=True, slots=True)
class DrivePlan:
    """A drive solved once: its path and speed profile; :meth:`pose` answers any sim time."""

    drive: Drive
    pieces: tuple[_Piece, ...]
    length: float
    """m, the whole path (one lap of a loop)."""
    start: tuple[_Phase, ...]
    """From departure at rest: the whole drive, or a loop's first laps."""
    start_laps: int
    """Laps the ``start`` phases cover (0 unless looping)."""
    lap: tuple[_Phase, ...]
    """A loop's periodic lap after the start laps (empty unless looping)."""

    @classmethod
    def of(cls, drive: Drive) -> DrivePlan:
        """Solve ``drive`` (ValueError with :func:`drive_problem`'s reason if undrivable)."""
        problem = drive_problem(drive)
        if problem is not None:
            raise ValueError(problem)
        pieces = _path(_waypoints(drive), drive.loop, drive.speed)
        length = pieces[-1].s0 + pieces[-1].length
        if not drive.loop:
            speeds = _boundary_speeds(pieces, loop=False)
            return cls(drive, pieces, length, _phases(pieces, speeds, 0.0, 0.0), 0, ())
        periodic = _boundary_speeds(pieces, loop=True)
        laps = max(1, math.ceil(drive.speed**2 / (2.0 * ACCELERATION * length)))
        unrolled = [
            _Piece(p.s0 + lap * length, p.length, p.east, p.north, p.heading, p.curvature, p.limit)
            for lap in range(laps)
            for p in pieces
        ]
        # From rest: the periodic speeds, capped by what accelerating from 0 reaches.
        start = [
            min(periodic[i % len(pieces)], math.sqrt(2.0 * ACCELERATION * p.s0))
            for i, p in enumerate(unrolled)
        ]
        start.append(periodic[0])
        for i, p in enumerate(unrolled):
            start[i + 1] = min(
                start[i + 1], math.sqrt(start[i] ** 2 + 2.0 * ACCELERATION * p.length)
            )
        first = _phases(tuple(unrolled), start, 0.0, 0.0)
        t_start = first[-1].t0 + first[-1].duration
        lap = _phases(pieces, [*periodic, periodic[0]], t_start, 0.0)
        return cls(drive, pieces, length, first, laps, lap)

    @property
    def start_time(self) -> float:
        """Seconds from departure to the end of the start phases (the stop, or the first laps)."""
        last = self.start[-1]
        return last.t0 + last.duration

    @property
    def lap_time(self) -> float:
        """Seconds per periodic lap of a loop (0 unless looping)."""
        if not self.lap:
            return 0.0
        return self.lap[-1].t0 + self.lap[-1].duration - self.lap[0].t0

    def pose(self, t: float) -> DrivePose:
        """The car's pose at sim time ``t``, s."""
        since = t - self.drive.depart
        if since <= 0.0:
            distance, speed = 0.0, 0.0
        elif since < self.start_time or not self.lap:
            distance, speed = _evaluate(self.start, since)
        else:
            laps, rest = divmod(since - self.start_time, self.lap_time)
            along, speed = _evaluate(self.lap, self.start_time + rest)
            distance = (self.start_laps + laps) * self.length + along
        east, north, heading = self._point(distance)
        return DrivePose(east, north, heading % math.tau, speed, distance)

    def _point(self, distance: float) -> tuple[float, float, float]:
        s = distance % self.length if self.lap else min(distance, self.length)
        starts = [p.s0 for p in self.pieces]
        piece = self.pieces[max(0, bisect_right(starts, s) - 1)]
        return piece.at(min(s - piece.s0, piece.length))


def drive_pose(drive: Drive, t: float) -> DrivePose:
    """The pose of a car on ``drive`` at sim time ``t`` (solves the drive: keep a plan instead)."""
    return DrivePlan.of(drive).pose(t)


def _evaluate(phases: tuple[_Phase, ...], t: float) -> tuple[float, float]:
    index = max(0, bisect_right([p.t0 for p in phases], t) - 1)
    return phases[index].at(t)


def _waypoints(drive: Drive) -> tuple[Point2, ...]:
    """The route without repeated points (and without a loop's closing repeat of the first)."""
    points: list[Point2] = []
    for p in drive.route:
        if not points or p != points[-1]:
            points.append(p)
    if drive.loop and len(points) > 1 and points[-1] == points[0]:
        points.pop()
    return tuple(points)


def _heading(a: Point2, b: Point2) -> float:
    return math.atan2(b[0] - a[0], b[1] - a[1])


def _turns(points: tuple[Point2, ...], loop: bool) -> dict[int, float]:
    """Signed turn (rad, positive right) at each corner waypoint."""
    n = len(points)
    corners = range(n) if loop else range(1, n - 1)
    turns = {}
    for k in corners:
        h_in = _heading(points[k - 1], points[k])
        h_out = _heading(points[k], points[(k + 1) % n])
        turns[k] = (h_out - h_in + math.pi) % math.tau - math.pi
    return turns


def _fillet_radius(turn: float, room: float) -> float:
    """Corner fillet radius for a turn of ``turn`` rad with ``room`` m of tangent length."""
    half = abs(turn) / 2.0
    sec_minus_one = 2.0 * math.sin(half / 2.0) ** 2 / math.cos(half)
    cut = CORNER_CUT / sec_minus_one if sec_minus_one > 0.0 else math.inf
    return min(max(MIN_RADIUS, cut), room / math.tan(half))


def _path(points: tuple[Point2, ...], loop: bool, cruise: float) -> tuple[_Piece, ...]:
    """Straights and fillets from the start (a loop: the first corner's end) to the end."""
    n = len(points)
    turns = _turns(points, loop)
    segments = n if loop else n - 1
    lengths = [math.dist(points[j], points[(j + 1) % n]) for j in range(segments)]

    def room(j: int) -> float:  # tangent length a corner may take of segment j
        shared = loop or 0 < j < segments - 1 or segments == 1
        return lengths[j] / 2.0 if shared else lengths[j]

    tangent: dict[int, float] = {}
    radius: dict[int, float] = {}
    for k, turn in turns.items():
        if abs(turn) < _STRAIGHT:
            tangent[k] = 0.0
            continue
        r = _fillet_radius(turn, min(room((k - 1) % segments), room(k % segments)))
        radius[k] = r
        tangent[k] = r * math.tan(abs(turn) / 2.0)

    pieces: list[_Piece] = []

    def add(east: float, north: float, heading: float, length: float, curv: float) -> None:
        if length <= 1e-9:
            return
        s0 = pieces[-1].s0 + pieces[-1].length if pieces else 0.0
        limit = cruise if curv == 0.0 else min(cruise, math.sqrt(LATERAL_ACCELERATION / abs(curv)))
        pieces.append(_Piece(s0, length, east, north, heading, curv, limit))

    for j in range(segments):
        a, b = points[j], points[(j + 1) % n]
        h = _heading(a, b)
        d0, d1 = tangent.get(j, 0.0), tangent.get((j + 1) % n, 0.0)
        add(a[0] + d0 * math.sin(h), a[1] + d0 * math.cos(h), h, lengths[j] - d0 - d1, 0.0)
        corner = (j + 1) % n
        if corner in radius:
            turn, r = turns[corner], radius[corner]
            east, north = b[0] - d1 * math.sin(h), b[1] - d1 * math.cos(h)
            add(east, north, h, r * abs(turn), math.copysign(1.0 / r, turn))
    return tuple(pieces)


def _boundary_speeds(pieces: tuple[_Piece, ...], loop: bool) -> list[float]:
    """Speed at each piece's start (and, open routes, at the end): the fastest feasible profile."""
    m = len(pieces)
    a2 = 2.0 * ACCELERATION
    if not loop:
        u = [0.0] + [min(pieces[i - 1].limit, pieces[i].limit) for i in range(1, m)] + [0.0]
        for i in reversed(range(m)):
            u[i] = min(u[i], math.sqrt(u[i + 1] ** 2 + a2 * pieces[i].length))
        for i in range(m):
            u[i + 1] = min(u[i + 1], math.sqrt(u[i] ** 2 + a2 * pieces[i].length))
        return u
    u = [min(pieces[i - 1].limit, pieces[i].limit) for i in range(m)]
    for _ in range(2):  # two rounds reach every boundary from the slowest one
        for i in reversed(range(m)):
            u[i] = min(u[i], math.sqrt(u[(i + 1) % m] ** 2 + a2 * pieces[i].length))
        for i in range(m):
            j = (i + 1) % m
            u[j] = min(u[j], math.sqrt(u[i] ** 2 + a2 * pieces[i].length))
    return u


def _phases(
    pieces: tuple[_Piece, ...], speeds: list[float], t0: float, s0: float
) -> tuple[_Phase, ...]:
    """Constant-acceleration phases over ``pieces`` with ``speeds`` at their boundaries."""
    phases: list[_Phase] = []
    t = t0
    a = ACCELERATION
    for i, piece in enumerate(pieces):
        u0, u1, top, length = speeds[i], speeds[i + 1], piece.limit, piece.length
        x_acc = max(0.0, (top**2 - u0**2) / (2.0 * a))
        x_dec = max(0.0, (top**2 - u1**2) / (2.0 * a))
        start = piece.s0 - pieces[0].s0 + s0
        if x_acc + x_dec <= length:
            steps = [
                (0.0, u0, a, (top - u0) / a),
                (x_acc, top, 0.0, (length - x_acc - x_dec) / top),
                (length - x_dec, top, -a, (top - u1) / a),
            ]
        else:
            peak = math.sqrt(max(u0**2, u1**2, (u0**2 + u1**2 + 2.0 * a * length) / 2.0))
            x_peak = min(length, max(0.0, (peak**2 - u0**2) / (2.0 * a)))
            steps = [(0.0, u0, a, (peak - u0) / a), (x_peak, peak, -a, (peak - u1) / a)]
        for x, v0, accel, duration in steps:
            if duration > 1e-12:
                phases.append(_Phase(t, start + x, v0, accel, duration))
                t += duration
    return tuple(phases)
