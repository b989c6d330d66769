"""The path planner (chapter section 7.1): requests, results and the PRM / RRT / PRM+RRT query.

Pure core, no ROS: ``PathPlanner(world, cache_dir).plan(PlanRequest(...)) -> PlanResult``. The
result's segments are :class:`hdrc3_control.path_segment.PathSegment` values, ready for the path
following control mode. Bad input never raises: it is answered with a status and a reason.
"""

from __future__ import annotations

import enum
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from hdrc3_control.path_segment import PathSegment
from hdrc3_control.velocity_profile import ProfileLimits
from hdrc3_navigation.constraints import ConstraintChecker, Constraints
from hdrc3_navigation.cost import Criterion, FlightModel
from hdrc3_navigation.gis import DEFAULT_MARGIN, Gis, Point3
from hdrc3_navigation.multilevel import JOIN_STEPS, Checks, Smoothed, multilevel, sample
from hdrc3_navigation.ompl_space import OmplSpace
from hdrc3_navigation.roadmap import (
    DEFAULT_NODES,
    BuildProgress,
    Roadmap,
    RoadmapCache,
    default_cache_dir,
)
from hdrc3_navigation.rrt import rrt_connect
from hdrc3_navigation.search import Deadline, Query, edge_costs
from sim.world import World

Vec3 = tuple[float, float, float]
MIN_FLIGHT_M = 0.5
"""Shortest flight the planner plans: closer goals are where the aircraft already is."""
_BRIDGE_ENDS = 8
"""Roadmap nodes of each component offered to the reconnecting RRT."""


class PlanStatus(enum.Enum):
    """Outcome of one path query."""

    SOLVED = "solved"
    NO_PATH = "no_path"
    TIMEOUT = "timeout"
    INVALID = "invalid"
    START_OUTSIDE_WORLD = "start_outside_world"
    GOAL_OUTSIDE_WORLD = "goal_outside_world"
    START_IN_OBSTACLE = "start_in_obstacle"
    GOAL_IN_OBSTACLE = "goal_in_obstacle"
    START_IN_NO_FLY_ZONE = "start_in_no_fly_zone"
    GOAL_IN_NO_FLY_ZONE = "goal_in_no_fly_zone"


class PlannerKind(enum.Enum):
    """Which planner answers a query (chapter 7.1: individually and in combination)."""

    PRM = "prm"
    RRT = "rrt"
    PRM_RRT = "prm+rrt"


@dataclass(frozen=True, slots=True)
class PlanRequest:
    """One path query in the world's local ENU frame (m, m/s, s)."""

    start: Vec3
    goal: Vec3
    speed: float = 10.0
    constraints: Constraints = field(default_factory=Constraints)
    planner: PlannerKind = PlannerKind.PRM_RRT
    timeout: float = 1.0
    """Seconds; the query answers TIMEOUT when it runs out."""
    criterion: Criterion = Criterion.LENGTH
    start_direction: Vec3 | None = None
    """The first segment's start tangent (a replan joins the segment in flight, whose end
    tangent it is); None or the zero vector: free."""


@dataclass(frozen=True, slots=True)
class PlanResult:
    """Answer to a query; segments are empty unless SOLVED."""

    status: PlanStatus
    reason: str = ""
    segments: tuple[PathSegment, ...] = ()
    length: float = 0.0
    """Arc length of the segments, m."""
    duration: float = 0.0
    """Estimated flight time, s."""
    energy: float = 0.0
    """Estimated energy (the flight model's), J."""
    planning_time: float = 0.0
    """Wall-clock seconds spent on the query."""
    planner: PlannerKind | None = None
    reconnected: bool = False
    """True if an RRT bridged roadmap components cut apart by constraints."""
    hover_stops: int = 0
    """Interior waypoints where no cubic fits and the aircraft stops."""

    @property
    def ok(self) -> bool:
        """True when SOLVED."""
        return self.status is PlanStatus.SOLVED


class PathPlanner:
    """PRM (cached roadmap), RRT-Connect and PRM+RRT with runtime constraints.

    Args:
        world: The world (or a ready GIS of it, whose runtime updates then apply).
        cache_dir: Directory of cached roadmaps (default: :func:`default_cache_dir`).
        margin: Safety margin, m (ignored when a GIS is given).
        roadmap_nodes: Size of the PRM roadmap.
        limits: Platform limits (phi_max, maximum speed) for the segment velocities.
        model: Flight model of the time and energy criteria.

    """

    def __init__(
        self,
        world: World | Gis,
        cache_dir: Path | None = None,
        margin: float = DEFAULT_MARGIN,
        roadmap_nodes: int = DEFAULT_NODES,
        limits: ProfileLimits | None = None,
        model: FlightModel | None = None,
    ) -> None:
        self.gis = world if isinstance(world, Gis) else Gis(world, margin)
        self.cache = RoadmapCache(cache_dir or default_cache_dir())
        self.roadmap_nodes = roadmap_nodes
        self.limits = limits or ProfileLimits()
        self.model = model or FlightModel()
        self._roadmap: Roadmap | None = None
        self._zone_cache: dict[str, dict[bytes, NDArray[np.intp]]] = {}
        """Per roadmap key: which edges cross each no-fly zone seen so far."""
        self._cost_cache: dict[tuple[str, Criterion, float], tuple[list[float], list[float]]] = {}
        """Edge costs per (roadmap, criterion, speed)."""

    def roadmap(
        self, rebuild: bool = False, progress: BuildProgress | None = None
    ) -> tuple[Roadmap, bool]:
        """The roadmap (loaded from the cache or built); True if it was built now."""
        if self._roadmap is not None and not rebuild:
            return self._roadmap, False
        self._roadmap, built = self.cache.load_or_build(
            self.gis, self.roadmap_nodes, rebuild=rebuild, progress=progress
        )
        return self._roadmap, built

    def use_roadmap(self, roadmap: Roadmap) -> None:
        """Query this roadmap instead of the cached one (tests, externally built roadmaps)."""
        self._roadmap = roadmap

    # --- validation ----------------------------------------------------------------------

    @staticmethod
    def _validate(request: PlanRequest) -> PlanResult | None:
        """Numbers and constraints of a request (before any geometry)."""
        try:
            values = (*request.start, *request.goal, request.speed, request.timeout)
        except TypeError:
            return PlanResult(PlanStatus.INVALID, "start and goal must be (east, north, up)")
        if len(request.start) != 3 or len(request.goal) != 3:
            return PlanResult(PlanStatus.INVALID, "start and goal must be (east, north, up)")
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            return PlanResult(PlanStatus.INVALID, "start, goal, speed and timeout must be finite")
        if request.speed <= 0.0:
            return PlanResult(PlanStatus.INVALID, f"speed must be > 0, got {request.speed}")
        if request.timeout <= 0.0:
            return PlanResult(PlanStatus.INVALID, f"timeout must be > 0, got {request.timeout}")
        problems = request.constraints.problems()
        if problems:
            return PlanResult(PlanStatus.INVALID, "; ".join(problems))
        if math.dist(request.start, request.goal) < MIN_FLIGHT_M:
            return PlanResult(
                PlanStatus.INVALID, f"start and goal are closer than {MIN_FLIGHT_M:g} m"
            )
        direction = request.start_direction
        if direction is not None and not (
            isinstance(direction, (tuple, list))
            and len(direction) == 3
            and all(isinstance(v, (int, float)) and math.isfinite(v) for v in direction)
        ):
            return PlanResult(
                PlanStatus.INVALID, f"start_direction must be three finite numbers, got {direction}"
            )
        return None

    def _check_ends(self, request: PlanRequest, checker: ConstraintChecker) -> PlanResult | None:
        """Start and goal: inside the volume, the altitude limits, clear, outside the zones."""
        lo, hi = self.gis.bounds
        for which, p in (("start", request.start), ("goal", request.goal)):
            if not self.gis.inside_bounds(p):
                return PlanResult(
                    PlanStatus[f"{which.upper()}_OUTSIDE_WORLD"],
                    f"{which} {_fmt(p)} is outside the planning volume {_fmt(lo)}..{_fmt(hi)}",
                )
            problem = checker.altitude_problem(p[2])
            if problem:
                return PlanResult(PlanStatus.INVALID, f"{which}: {problem}")
        for which, p in (("start", request.start), ("goal", request.goal)):
            if not self.gis.point_free(p):
                return PlanResult(
                    PlanStatus[f"{which.upper()}_IN_OBSTACLE"],
                    f"{which} {_fmt(p)} is within {self.gis.margin} m of an obstacle or the ground",
                )
        for which, p in (("start", request.start), ("goal", request.goal)):
            zone = checker.zone_at(p)
            if zone is not None:
                return PlanResult(
                    PlanStatus[f"{which.upper()}_IN_NO_FLY_ZONE"],
                    f"{which} {_fmt(p)} is in no-fly zone {zone!r} (grown by the margin)",
                )
        return None

    # --- the query -----------------------------------------------------------------------

    def plan(self, request: PlanRequest) -> PlanResult:
        """Answer one query; never raises on bad input."""
        t0 = time.perf_counter()
        bad = self._validate(request)
        if bad is not None:
            return _timed(bad, t0, request.planner)
        checker = ConstraintChecker(self.gis, request.constraints, request.speed)
        bad = self._check_ends(request, checker)
        if bad is not None:
            return _timed(bad, t0, request.planner)
        deadline = t0 + request.timeout
        start, goal = np.array(request.start, float), np.array(request.goal, float)
        try:
            found = self._search(request, checker, start, goal, deadline)
        except Deadline:
            return _timed(_timeout(request), t0, request.planner)
        if found is None:
            reason = "no path found"
            if request.planner is PlannerKind.PRM:
                reason = "start and goal are not connected in the roadmap under the constraints"
            elif time.perf_counter() >= deadline:
                return _timed(_timeout(request), t0, request.planner)
            return _timed(PlanResult(PlanStatus.NO_PATH, reason), t0, request.planner)
        waypoints, reconnected = found
        direction = _start_direction(request)
        checks = self._checks(checker)
        smoothed = multilevel(waypoints, checks, request.speed, self.limits, direction)
        if smoothed is None and direction is not None:
            try:
                joined = self._join_by_search(request, checker, checks, direction, deadline)
            except Deadline:
                return _timed(_timeout(request), t0, request.planner)
            if joined is not None:
                smoothed, reconnected = joined
        if smoothed is None:
            steps = ", ".join(f"{v:g}" for v in JOIN_STEPS)
            reason = (
                f"the start direction {_fmt(request.start_direction or ())} cannot be joined: "
                f"no cubic from the start along it is clear, nor a path on from a waypoint {steps}"
                " m along it"
            )
            return _timed(PlanResult(PlanStatus.NO_PATH, reason), t0, request.planner)
        return _timed(self._result(smoothed, reconnected), t0, request.planner)

    def _join_by_search(
        self,
        request: PlanRequest,
        checker: ConstraintChecker,
        checks: Checks,
        direction: NDArray[np.float64],
        deadline: float,
    ) -> tuple[Smoothed, bool] | None:
        """The path found cannot be joined: search on from a waypoint along the direction."""
        start, goal = np.array(request.start, float), np.array(request.goal, float)
        unit = direction / float(np.linalg.norm(direction))
        for step in JOIN_STEPS:
            q = start + step * unit
            point = (float(q[0]), float(q[1]), float(q[2]))
            if not (
                self.gis.inside_bounds(point) and checker.point_ok(point) and checks.line(start, q)
            ):
                continue
            found = self._search(request, checker, q, goal, deadline)
            if found is None:
                continue
            waypoints = np.vstack([start, found[0]])
            smoothed = multilevel(waypoints, checks, request.speed, self.limits, direction)
            if smoothed is not None:
                return smoothed, found[1]
        return None

    def _checks(self, checker: ConstraintChecker) -> Checks:
        gis = self.gis

        def line(a: Point3, b: Point3) -> bool:
            return checker.polyline_ok(np.array([a, b], float)) and gis.segment_free(a, b)

        def curve(points: NDArray[np.float64]) -> bool:
            return checker.polyline_ok(points) and gis.polyline_free(points)

        return Checks(line, curve)

    def _search(
        self,
        request: PlanRequest,
        checker: ConstraintChecker,
        start: NDArray[np.float64],
        goal: NDArray[np.float64],
        deadline: float,
    ) -> tuple[NDArray[np.float64], bool] | None:
        checks = self._checks(checker)
        if request.planner is PlannerKind.RRT:
            path = rrt_connect(self._space(checker), [start], [goal], deadline)
            return None if path is None else (path, False)
        roadmap, _ = self.roadmap()
        gis = self.gis
        nodes, edges = roadmap.nodes, roadmap.edges
        a, b = nodes[edges[:, 0]], nodes[edges[:, 1]]
        node_valid = checker.points_ok(nodes)
        boxes = gis.runtime_boxes()
        if len(boxes):
            # an edge (and its end nodes) near a runtime obstacle is tested with FCL lazily
            m = gis.margin
            lo, hi = np.minimum(a, b) - m, np.maximum(a, b) + m
            suspect = np.zeros(len(edges), dtype=bool)
            for box in boxes:
                suspect |= np.all(lo <= box[3:], axis=1) & np.all(hi >= box[:3], axis=1)
        else:
            suspect = np.zeros(len(edges), dtype=bool)
        query = Query(
            roadmap, start, goal, node_valid,
            checker.edges_ok(a, b, roadmap.lines, self._zone_cache.setdefault(roadmap.key, {})),
            suspect,
            lambda p, q: gis.segment_free(p, q, static=False), checks.line,
            request.criterion, request.speed, self.model, deadline,
            self._costs(roadmap, request.criterion, request.speed),
        )  # fmt: skip
        ids = query.astar(query.start_id, query.goal_id)
        if ids is not None:
            return np.array([query.point(i) for i in ids]), False
        if request.planner is PlannerKind.PRM:
            return None
        return self._reconnect(query, checker, deadline)

    def _costs(
        self, roadmap: Roadmap, criterion: Criterion, speed: float
    ) -> tuple[list[float], list[float]]:
        key = (roadmap.key, criterion, 0.0 if criterion is Criterion.LENGTH else speed)
        costs = self._cost_cache.get(key)
        if costs is None:
            if len(self._cost_cache) >= 16:
                self._cost_cache.clear()
            costs = self._cost_cache[key] = edge_costs(roadmap, self.model, criterion, speed)
        return costs

    def _space(self, checker: ConstraintChecker) -> OmplSpace:
        return OmplSpace(
            self.gis,
            point_ok=checker.point_ok,
            segment_ok=lambda a, b: checker.polyline_ok(np.array([a, b], float)),
        )

    def _reconnect(
        self, query: Query, checker: ConstraintChecker, deadline: float
    ) -> tuple[NDArray[np.float64], bool] | None:
        """§7.1.2: an RRT bridges the start's and the goal's roadmap components."""
        from_start = sorted(query.component(query.start_id))
        to_goal = sorted(query.component(query.goal_id, reverse=True))
        s_pts = np.array([query.point(i) for i in from_start])
        g_pts = np.array([query.point(i) for i in to_goal])
        d_s, _ = cKDTree(g_pts).query(s_pts)
        d_g, _ = cKDTree(s_pts).query(g_pts)
        s_ids = [from_start[i] for i in np.argsort(d_s)[:_BRIDGE_ENDS]]
        g_ids = [to_goal[i] for i in np.argsort(d_g)[:_BRIDGE_ENDS]]
        bridge = rrt_connect(
            self._space(checker),
            [query.point(i) for i in s_ids],
            [query.point(i) for i in g_ids],
            deadline,
        )
        if bridge is None:
            return None
        s_id = min(s_ids, key=lambda i: float(np.linalg.norm(query.point(i) - bridge[0])))
        g_id = min(g_ids, key=lambda i: float(np.linalg.norm(query.point(i) - bridge[-1])))
        head = query.astar(query.start_id, s_id)
        tail = query.astar(g_id, query.goal_id)
        if head is None or tail is None:
            return None
        pts = [query.point(i) for i in head] + list(bridge[1:-1])
        pts += [query.point(i) for i in tail]
        return np.array(pts), True

    def _result(self, smoothed: Smoothed, reconnected: bool) -> PlanResult:
        duration = 0.0
        energy = 0.0
        decel = self.limits.braking_decel
        previous_end = 0.0
        for seg, length in zip(smoothed.segments, smoothed.lengths, strict=True):
            v = max(seg.target_velocity, 0.1)
            duration += length / v
            duration += max(0.0, v - previous_end) / (2.0 * decel)  # accelerating
            duration += max(0.0, v - seg.end_velocity) / (2.0 * decel)  # braking
            previous_end = seg.end_velocity
            pts = sample(seg)
            energy += self.model.polyline_cost(Criterion.ENERGY, pts, v)
        return PlanResult(
            PlanStatus.SOLVED,
            f"{len(smoothed.segments)} segments, {smoothed.corners} hover stops",
            tuple(smoothed.segments),
            float(sum(smoothed.lengths)),
            duration,
            energy,
            reconnected=reconnected,
            hover_stops=smoothed.corners,
        )


def _timeout(request: PlanRequest) -> PlanResult:
    return PlanResult(PlanStatus.TIMEOUT, f"no path within {request.timeout} s")


def _timed(result: PlanResult, t0: float, planner: PlannerKind) -> PlanResult:
    return PlanResult(
        result.status,
        result.reason,
        result.segments,
        result.length,
        result.duration,
        result.energy,
        time.perf_counter() - t0,
        planner,
        result.reconnected,
        result.hover_stops,
    )


def _start_direction(request: PlanRequest) -> NDArray[np.float64] | None:
    """The validated start direction as a vector; None when free (absent or zero)."""
    if request.start_direction is None:
        return None
    direction = np.array(request.start_direction, float)
    return None if float(np.linalg.norm(direction)) < 1e-9 else direction


def _fmt(p: Sequence[float]) -> str:
    return "(" + ", ".join(f"{v:.1f}" for v in p) + ")"
