"""Motion-plan-info hook (§9.2, Figure 27): is a flight feasible, how long, how costly.

The task planner asks this interface while grounding flight operators. Two implementations:
straight lines at constant speed (no world needed) and the real path planner of
:mod:`hdrc3_navigation` (PRM+RRT with the world's obstacles and no-fly zones).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

from hdrc3_navigation.planner import PathPlanner, PlanRequest

Point = tuple[float, float, float]


@dataclass(frozen=True)
class FlightInfo:
    """Answer to one query: feasibility, duration (s) and cost (path length, m)."""

    feasible: bool
    duration: float
    cost: float


class MotionPlanInfo(Protocol):
    """Answers flight queries between two positions for one agent."""

    def query(self, agent: str, start: Point, goal: Point) -> FlightInfo:
        """Return feasibility, duration and cost of flying ``agent`` from start to goal."""
        ...


@dataclass(frozen=True)
class StraightLineMotionPlanInfo:
    """Straight-line flights at constant speed plus a fixed overhead per flight.

    Attributes:
        speed: Cruise speed in m/s.
        overhead: Seconds added to every flight (acceleration, braking, hover-in).
        max_range: Flights longer than this (m) are infeasible.

    """

    speed: float = 10.0
    overhead: float = 5.0
    max_range: float = math.inf

    def query(self, agent: str, start: Point, goal: Point) -> FlightInfo:
        """Distance / speed + overhead; infeasible beyond ``max_range``."""
        del agent  # every agent flies the same model here
        distance = math.dist(start, goal)
        feasible = distance <= self.max_range
        return FlightInfo(feasible, distance / self.speed + self.overhead, distance)


@dataclass
class PlannedMotionPlanInfo:
    """Flights answered by the path planner (chapter 9.2, Figure 27): PRM+RRT on the world.

    Task positions are usually on the ground: a flight climbs vertically to ``cruise_agl``
    above the terrain, flies the planned path at that height and descends at the goal. Answers
    are memoised per (start, goal).

    Attributes:
        planner: The path planner of the agent's world.
        speed: Cruise speed in m/s.
        cruise_agl: Height above the terrain of the planned part, m.
        timeout: Planning time budget per query, s.

    """

    planner: PathPlanner
    speed: float = 10.0
    cruise_agl: float = 20.0
    timeout: float = 2.0
    _memo: dict[tuple[Point, Point], FlightInfo] = field(default_factory=dict, repr=False)

    def _lift(self, p: Point) -> Point:
        ground = self.planner.gis.world.terrain.height(p[0], p[1])
        return (p[0], p[1], max(p[2], ground + self.cruise_agl))

    def query(self, agent: str, start: Point, goal: Point) -> FlightInfo:
        """Feasibility, duration (s) and cost (flown length, m) of one flight."""
        del agent  # one planner per agent's world
        key = (tuple(start), tuple(goal))
        known = self._memo.get(key)  # type: ignore[arg-type]
        if known is not None:
            return known
        a, b = self._lift(start), self._lift(goal)
        climb, descent = a[2] - start[2], b[2] - goal[2]
        model = self.planner.model
        vertical_time = climb / model.climb_rate + descent / model.descent_rate
        if math.dist(a, b) < 0.5:
            info = FlightInfo(True, vertical_time, climb + descent)
        else:
            result = self.planner.plan(PlanRequest(a, b, self.speed, timeout=self.timeout))
            info = FlightInfo(
                result.ok, result.duration + vertical_time, result.length + climb + descent
            )
        self._memo[key] = info  # type: ignore[index]
        return info
