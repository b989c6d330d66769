"""Search criteria (chapter section 7.1.1: "shortest path, minimal fuel usage, etc.").

Edge costs and admissible A* heuristics for path length, flight time and energy. Time and
energy use a simple flight model written here (no library models a helicopter's flight cost):
a piece takes the longer of its length at the cruise speed and its climb at the climb rate;
energy is cruise power times time plus the potential energy of every climb over an efficiency.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hdrc3_control.commands import G


class Criterion(enum.Enum):
    """What the roadmap search minimises."""

    LENGTH = "length"
    TIME = "time"
    ENERGY = "energy"


@dataclass(frozen=True, slots=True)
class FlightModel:
    """Cost model of one aircraft (defaults: an RMAX-class helicopter)."""

    mass: float = 95.0
    """kg."""
    cruise_power: float = 12_000.0
    """Shaft power in level flight, W."""
    climb_efficiency: float = 0.5
    """Fraction of extra power that becomes height."""
    climb_rate: float = 3.0
    """Vertical speed that bounds a steep climb, m/s."""
    descent_rate: float = 2.0
    """Vertical speed that bounds a steep descent, m/s."""

    def piece_time(self, a: NDArray[np.float64], b: NDArray[np.float64], speed: float) -> Any:
        """Seconds to fly straight pieces a-b at ``speed`` (points or (m, 3) arrays)."""
        d = np.asarray(b) - np.asarray(a)
        length = np.linalg.norm(d, axis=-1)
        dz = d[..., 2]
        vertical = np.where(dz > 0, dz / self.climb_rate, -dz / self.descent_rate)
        return np.maximum(length / speed, vertical)

    def piece_energy(self, a: NDArray[np.float64], b: NDArray[np.float64], speed: float) -> Any:
        """Joules to fly straight pieces a-b at ``speed`` (points or (m, 3) arrays)."""
        climb = np.maximum(0.0, np.asarray(b)[..., 2] - np.asarray(a)[..., 2])
        return self.cruise_power * self.piece_time(a, b, speed) + (
            self.mass * G * climb / self.climb_efficiency
        )

    def cost(
        self, criterion: Criterion, a: NDArray[np.float64], b: NDArray[np.float64], speed: float
    ) -> Any:
        """Edge costs under a criterion (a float for points, an array for (m, 3) arrays)."""
        if criterion is Criterion.LENGTH:
            return np.linalg.norm(np.asarray(b) - np.asarray(a), axis=-1)
        if criterion is Criterion.TIME:
            return self.piece_time(a, b, speed)
        return self.piece_energy(a, b, speed)

    def heuristic(
        self, criterion: Criterion, a: NDArray[np.float64], goal: NDArray[np.float64], speed: float
    ) -> Any:
        """Lower bounds of the cost from points a to the goal (admissible for A*)."""
        dist = np.linalg.norm(np.asarray(goal) - np.asarray(a), axis=-1)
        if criterion is Criterion.LENGTH:
            return dist
        if criterion is Criterion.TIME:
            return dist / speed
        climb = np.maximum(0.0, goal[2] - np.asarray(a)[..., 2])
        return self.cruise_power * dist / speed + self.mass * G * climb / self.climb_efficiency

    def polyline_cost(
        self, criterion: Criterion, points: NDArray[np.float64], speed: float
    ) -> float:
        """Cost of a polyline."""
        return float(np.sum(self.cost(criterion, points[:-1], points[1:], speed)))
