"""Velocity profile along a segment: curvature compatibility, acceleration and braking limits.

The maximum speed where the path has curvature radius R is V = sqrt(|phi_max g R|) (chapter
5.3); the profile is the target speed capped by that limit, then made reachable with the braking
deceleration towards the end speed (backward pass). Braking distance d(v) = v^2 / (2 a).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import G
from hdrc3_control.path_segment import PathSegment


@dataclass(frozen=True, slots=True)
class ProfileLimits:
    """Platform limits the profile respects."""

    max_roll: float = math.radians(15.0)
    """phi_max of the compatibility check, rad."""
    braking_decel: float = 1.2
    """Deceleration the profile plans with, m/s^2."""
    max_speed: float = 15.0

    def __post_init__(self) -> None:
        """Reject non-positive limits."""
        if not all(v > 0.0 and math.isfinite(v) for v in (self.max_roll, self.braking_decel)):
            raise ConfigError("profile limits must be > 0")


def compatible_speed(curvature: float, max_roll: float) -> float:
    """V = sqrt(|phi_max g R|) with R = 1/curvature (inf on a straight line)."""
    if curvature <= 1e-9:
        return math.inf
    return math.sqrt(abs(max_roll * G / curvature))


def braking_distance(speed: float, decel: float) -> float:
    """Distance to stop from ``speed`` at constant ``decel``, m."""
    return speed * speed / (2.0 * decel)


@dataclass(frozen=True, slots=True)
class VelocityProfile:
    """Speed limits sampled along one segment."""

    params: NDArray[np.float64]
    """Segment parameter s of each sample."""
    distance: NDArray[np.float64]
    """Arc length from the segment start, m."""
    limit: NDArray[np.float64]
    """Curvature-compatible speed (capped at max_speed), m/s."""
    speed: NDArray[np.float64]
    """Planned speed: min(target, limit), reachable with the braking deceleration, m/s."""

    @property
    def length(self) -> float:
        """Segment length, m."""
        return float(self.distance[-1])

    def speed_at(self, s: float) -> float:
        """Planned speed at parameter s (linear interpolation)."""
        return float(np.interp(s, self.params, self.speed))

    def min_speed_ahead(self, s: float, ahead: float) -> float:
        """Lowest planned speed between s and ``ahead`` metres further along the segment."""
        d0 = self.distance_at(s)
        d1 = min(d0 + max(0.0, ahead), self.length)
        inside = self.speed[(self.distance >= d0) & (self.distance <= d1)]
        ends = np.interp([d0, d1], self.distance, self.speed)
        return float(min(float(ends.min()), float(inside.min()) if len(inside) else math.inf))

    def limit_at(self, s: float) -> float:
        """Compatible speed at parameter s."""
        return float(np.interp(s, self.params, self.limit))

    def distance_at(self, s: float) -> float:
        """Arc length from the start to s, m."""
        return float(np.interp(s, self.params, self.distance))


def build_profile(
    segment: PathSegment,
    end_speed: float,
    limits: ProfileLimits | None = None,
    samples: int = 101,
    max_end_speed: float | None = None,
) -> VelocityProfile:
    """Profile of ``segment`` that reaches ``end_speed`` at its end (0: stop at the end).

    ``max_end_speed`` caps the speed entering the next segment (its own profile's start value).
    """
    lim = limits or ProfileLimits()
    params = np.linspace(0.0, 1.0, samples)
    pts = np.array([segment.position(float(s)) for s in params])
    steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    distance = np.concatenate([[0.0], np.cumsum(steps)])
    curv = np.array([segment.curvature(float(s)) for s in params])
    limit = np.array([min(lim.max_speed, compatible_speed(float(k), lim.max_roll)) for k in curv])
    speed = np.minimum(limit, segment.target_velocity)
    end = min(end_speed, float(speed[-1]))
    if max_end_speed is not None:
        end = min(end, max_end_speed)
    speed[-1] = end
    for i in range(samples - 2, -1, -1):
        reach = math.sqrt(float(speed[i + 1]) ** 2 + 2.0 * lim.braking_decel * float(steps[i]))
        speed[i] = min(float(speed[i]), reach)
    return VelocityProfile(params, distance, limit, speed)
