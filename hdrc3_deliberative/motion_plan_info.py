"""Motion-plan-info hook (§9.2, Figure 27): is a flight feasible, how long, how costly.

The task planner asks this interface while grounding flight operators. The straight-line
implementation is used until the path planner's motion-plan-info service is wired in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

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
