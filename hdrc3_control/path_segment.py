"""Cubic path segments p(s) = A s^3 + B s^2 + C s + D, s in [0, 1] (chapter 5.3, 7.1.2).

A segment is built from its boundary conditions (start/end points and directions) as a cubic
Hermite curve whose end tangents have the chord length as magnitude; a straight segment (Traj3D
Flyto) is the case where both directions point along the chord.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import Vec3

# 8-point Gauss-Legendre nodes/weights on [0, 1] for arc lengths
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_X = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W


def _unit(v: NDArray[np.float64], what: str) -> NDArray[np.float64]:
    n = float(np.linalg.norm(v))
    if not math.isfinite(n) or n < 1e-9:
        raise ConfigError(f"{what} must be a non-zero finite vector, got {v.tolist()}")
    out: NDArray[np.float64] = v / n
    return out


@dataclass(frozen=True, slots=True)
class PathSegment:
    """One segment as the path planner sends it (Traj3D-EV): geometry plus velocities."""

    start: Vec3
    end: Vec3
    start_direction: Vec3
    end_direction: Vec3
    target_velocity: float
    """Desired cruise speed on the segment, m/s."""
    end_velocity: float = 0.0
    """Speed at the end point, m/s; 0 marks the last (or a single) segment."""
    segment_id: int = 0
    coefficients: tuple[Vec3, Vec3, Vec3, Vec3] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Validate and compute A, B, C, D."""
        values = (*self.start, *self.end, self.target_velocity, self.end_velocity)
        if not all(math.isfinite(v) for v in values):
            raise ConfigError(f"segment {self.segment_id}: non-finite values {values}")
        if self.target_velocity < 0.0 or self.end_velocity < 0.0:
            raise ConfigError(f"segment {self.segment_id}: velocities must be >= 0")
        p0, p1 = np.array(self.start, float), np.array(self.end, float)
        chord = float(np.linalg.norm(p1 - p0))
        if chord < 0.1:
            raise ConfigError(f"segment {self.segment_id}: start and end closer than 0.1 m")
        m0 = _unit(np.array(self.start_direction, float), "start direction") * chord
        m1 = _unit(np.array(self.end_direction, float), "end direction") * chord
        a = 2.0 * (p0 - p1) + m0 + m1
        b = 3.0 * (p1 - p0) - 2.0 * m0 - m1
        coeffs = tuple((float(v[0]), float(v[1]), float(v[2])) for v in (a, b, m0, p0))
        object.__setattr__(self, "coefficients", coeffs)

    @staticmethod
    def straight(
        start: Vec3,
        end: Vec3,
        target_velocity: float,
        end_velocity: float = 0.0,
        segment_id: int = 0,
    ) -> PathSegment:
        """A straight line (Traj3D Flyto, climb, braking)."""
        d = (end[0] - start[0], end[1] - start[1], end[2] - start[2])
        return PathSegment(start, end, d, d, target_velocity, end_velocity, segment_id)

    def _abcd(self) -> NDArray[np.float64]:
        return np.array(self.coefficients)

    def position(self, s: float) -> NDArray[np.float64]:
        """p(s)."""
        a, b, c, d = self._abcd()
        out: NDArray[np.float64] = ((a * s + b) * s + c) * s + d
        return out

    def derivative(self, s: float) -> NDArray[np.float64]:
        """dp/ds (tangent, not normalised)."""
        a, b, c, _ = self._abcd()
        out: NDArray[np.float64] = (3.0 * a * s + 2.0 * b) * s + c
        return out

    def second_derivative(self, s: float) -> NDArray[np.float64]:
        """d2p/ds2."""
        a, b, _, _ = self._abcd()
        out: NDArray[np.float64] = 6.0 * a * s + 2.0 * b
        return out

    def tangent(self, s: float) -> NDArray[np.float64]:
        """Unit tangent at s."""
        return _unit(self.derivative(s), "tangent")

    def curvature(self, s: float) -> float:
        """|p' x p''| / |p'|^3, 1/m (0 on a straight line)."""
        d1, d2 = self.derivative(s), self.second_derivative(s)
        n = float(np.linalg.norm(d1))
        return float(np.linalg.norm(np.cross(d1, d2))) / n**3 if n > 1e-9 else 0.0

    def curvature_vector(self, s: float) -> NDArray[np.float64]:
        """Curvature times the unit normal (towards the centre of the turn), 1/m."""
        d1, d2 = self.derivative(s), self.second_derivative(s)
        n2 = float(d1 @ d1)
        if n2 < 1e-18:
            return np.zeros(3)
        out: NDArray[np.float64] = (d2 - d1 * float(d1 @ d2) / n2) / n2
        return out

    def arc_length(self, s0: float = 0.0, s1: float = 1.0) -> float:
        """Length of the curve between parameters s0 and s1, m."""
        ss = s0 + (s1 - s0) * _GL_X
        return float(
            (s1 - s0)
            * sum(w * np.linalg.norm(self.derivative(s)) for s, w in zip(ss, _GL_W, strict=True))
        )

    def closest_parameter(self, point: Vec3, guess: float | None = None) -> float:
        """Parameter of the closest point to ``point`` (grid search + Newton), in [0, 1]."""
        x = np.array(point, float)
        if guess is None:
            grid = np.linspace(0.0, 1.0, 33)
            guess = float(
                grid[int(np.argmin([np.linalg.norm(self.position(s) - x) for s in grid]))]
            )
        s = guess
        for _ in range(8):
            r = self.position(s) - x
            d1 = self.derivative(s)
            f1 = float(r @ d1)
            f2 = float(d1 @ d1 + r @ self.second_derivative(s))
            if f2 <= 1e-12:
                break
            step = f1 / f2
            s = min(1.0, max(0.0, s - step))
            if abs(step) < 1e-10:
                break
        return s
