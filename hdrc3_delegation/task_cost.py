"""What a TST's elementary actions cost one agent: time, energy and where it ends (§9.2, §10).

A contractor's bid rests on motion-plan information (Figure 27): flights are asked of the path
planner through :class:`MotionCost` (:class:`PlannerMotion` is the real PRM/RRT planner of
``hdrc3_navigation``; the fake beside this module flies straight lines), a scan's coverage
pattern comes from ``hdrc3_navigation.coverage`` exactly as the scan executor flies it, and
actions with a duration parameter take that long. What no planner answers (take-off, landing,
the hook's cycles, turning the PTU) is budgeted by :data:`BUDGET_S`, deliberately generous.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Protocol

import numpy as np

from hdrc3_control.takeoff import TakeoffConfig
from hdrc3_navigation.cost import FlightModel
from hdrc3_navigation.coverage import CoverageStatus, Platform, pair_footprint_width, plan_part
from hdrc3_navigation.planner import MIN_FLIGHT_M, PathPlanner, PlanRequest
from hdrc3_tst.actions import ACTIONS, ParamType
from hdrc3_tst.model import Node
from hdrc3_tst.resolver import ResolvedTst

Vec3 = tuple[float, float, float]

TAKEOFF = TakeoffConfig()
TAKEOFF_S = TAKEOFF.spool_timeout + TAKEOFF.height / TAKEOFF.climb_rate
"""Longest take-off: the engine's spool-up allowance and the climb (the take-off mode's)."""
BUDGET_S: dict[str, float] = {
    "take-off": TAKEOFF_S,
    "land": 60.0,
    "look-at": 5.0,
    "ptu-turn-to": 5.0,
    "camera-zoom": 2.0,
    "pick-up-box": 90.0,
    "drop-box": 90.0,
    "put-on-carrier": 90.0,
    "take-from-carrier": 90.0,
    "attach-carrier": 90.0,
    "detach-carrier": 90.0,
}
"""Seconds budgeted for actions no planner prices (the hook's lower-attach-raise cycle is
about a minute in the simulator; the rest are upper bounds of the control modes)."""
FLIGHTS = frozenset({"fly-to", "fly-path", "scan-area"})
"""Actions whose executors take off first when the aircraft stands on the ground."""
DEFAULT_SPEED = 8.0
"""Speed when a node leaves its speed open (the registry's preferred speed)."""


@dataclass(frozen=True)
class MotionInfo:
    """A flight's feasibility, length (m), duration (s) and energy (J)."""

    feasible: bool
    length: float = 0.0
    duration: float = 0.0
    energy: float = 0.0
    reason: str = ""


class MotionCost(Protocol):
    """Motion-plan information for one flight (the path planner's ``motion_plan_info``)."""

    def motion(self, start: Vec3, goal: Vec3, speed: float) -> MotionInfo:
        """Whether and at what cost the agent can fly from ``start`` to ``goal``."""


class PlannerMotion:
    """:class:`MotionCost` from the PRM/RRT path planner in this process (real OMPL queries)."""

    def __init__(self, planner: PathPlanner, timeout: float = 2.0) -> None:
        self.planner = planner
        self.timeout = timeout

    def motion(self, start: Vec3, goal: Vec3, speed: float) -> MotionInfo:
        """Plan the flight and report its figures."""
        result = self.planner.plan(PlanRequest(start, goal, speed, timeout=self.timeout))
        if not result.ok:
            return MotionInfo(False, reason=result.reason)
        return MotionInfo(True, result.length, result.duration, result.energy)


@dataclass(frozen=True)
class ActionCost:
    """One action as one agent would fly it from a given position."""

    node_id: str
    feasible: bool
    duration: float = 0.0
    energy: float = 0.0
    end: Vec3 = (0.0, 0.0, 0.0)
    reason: str = ""


@dataclass
class TaskCoster:
    """Prices the elementary actions of a resolved TST for one agent."""

    motion: MotionCost
    ground_up: Callable[[float, float], float] = lambda east, north: 0.0
    model: FlightModel = field(default_factory=FlightModel)

    def cost(self, tst: ResolvedTst, node: Node, start: Vec3) -> ActionCost:
        """Time, energy and end position of action ``node`` flown from ``start``."""
        spec = ACTIONS[node.action]
        speed = _number(tst, node, "speed", DEFAULT_SPEED)
        if node.action in FLIGHTS and self._on_ground(start):
            lifted = self._airborne(start)
            flight = self.cost(tst, node, lifted)
            return replace(
                flight,
                duration=flight.duration + TAKEOFF_S,
                energy=flight.energy + self.model.cruise_power * TAKEOFF_S,
            )
        if node.action == "fly-to":
            return self._flights(node, start, _points(tst, node, "destination"), speed)
        if node.action == "fly-path":
            return self._flights(node, start, _points(tst, node, "path"), speed)
        if node.action == "scan-area":
            return self._scan(tst, node, start, speed)
        if spec.duration is not None:
            return self._still(node, start, _number(tst, node, spec.duration, 0.0))
        end = start
        if node.action == "take-off":
            end = (start[0], start[1], self.ground_up(start[0], start[1]) + TAKEOFF.height)
        elif node.action == "land":
            end = (start[0], start[1], self.ground_up(start[0], start[1]))
        return self._still(node, end, BUDGET_S[node.action])

    def _on_ground(self, at: Vec3) -> bool:
        """Below half the take-off height: a flight starts with a take-off (as executors do)."""
        return at[2] < self.ground_up(at[0], at[1]) + TAKEOFF.height / 2

    def _airborne(self, at: Vec3) -> Vec3:
        return (at[0], at[1], self.ground_up(at[0], at[1]) + TAKEOFF.height)

    def _still(self, node: Node, at: Vec3, seconds: float) -> ActionCost:
        return ActionCost(node.node_id, True, seconds, self.model.cruise_power * seconds, at)

    def _flights(self, node: Node, start: Vec3, points: list[Vec3], speed: float) -> ActionCost:
        duration = energy = 0.0
        here = start
        for point in points:
            if math.dist(here, point) < MIN_FLIGHT_M:  # already there
                continue
            info = self.motion.motion(here, point, speed)
            if not info.feasible:
                return ActionCost(
                    node.node_id, False, reason=f"no flight to {point}: {info.reason}"
                )
            duration += info.duration
            energy += info.energy
            here = point
        return ActionCost(node.node_id, True, duration, energy, here)

    def _scan(self, tst: ResolvedTst, node: Node, start: Vec3, speed: float) -> ActionCost:
        corners = _place(tst, node, "area")
        altitude = _number(tst, node, "altitude", 30.0)
        part = int(_number(tst, node, "part", 1.0))
        parts = int(_number(tst, node, "parts", 1.0))
        ground = max(self.ground_up(c[0], c[1]) for c in corners)
        me = Platform("bidder", pair_footprint_width(altitude), speed, (start[0], start[1]))
        plan = plan_part([c[:2] for c in corners], part, parts, me, ground + altitude)
        if plan.status is not CoverageStatus.PLANNED:
            return ActionCost(node.node_id, False, reason=plan.reason)
        assignment = plan.assignments[0]
        end = assignment.segments[-1].end
        climb = max(0.0, ground + altitude - start[2])
        duration = assignment.duration + climb / self.model.climb_rate
        energy = self.model.cruise_power * duration
        return ActionCost(node.node_id, True, duration, energy, (end[0], end[1], end[2]))


def _value(tst: ResolvedTst, node: Node, param: str) -> float | str | None:
    var = node.params.get(param)
    return None if var is None else tst.network.values.get(var)


def _number(tst: ResolvedTst, node: Node, param: str, default: float) -> float:
    value = _value(tst, node, param)
    if isinstance(value, float | int) and math.isfinite(value):
        return float(value)
    spec = ACTIONS[node.action].param(param)
    if spec is not None and spec.preferred is not None:
        return spec.preferred
    if spec is not None and spec.default is not None:
        return spec.default
    return default


def _place(tst: ResolvedTst, node: Node, param: str) -> list[Vec3]:
    name = _value(tst, node, param)
    place = tst.places.get(str(name))
    if place is None:
        return []
    return [(c[0], c[1], c[2] if len(c) > 2 else 0.0) for c in place.coords]


def _points(tst: ResolvedTst, node: Node, param: str) -> list[Vec3]:
    spec = ACTIONS[node.action].param(param)
    assert spec is not None and spec.type in (ParamType.POINT, ParamType.PATH)
    return _place(tst, node, param)


def straight_line(model: FlightModel, start: Vec3, goal: Vec3, speed: float) -> MotionInfo:
    """Figures of the straight flight (no obstacles): the model's time and energy."""
    a, b = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    length = float(np.linalg.norm(b - a))
    return MotionInfo(
        True, length, float(model.piece_time(a, b, speed)), float(model.piece_energy(a, b, speed))
    )
