"""Sensor measurements the state estimator takes, in the local ENU frame.

The node converts ROS messages and the closed-loop tests convert ``sim.sensors`` samples; the core
depends on neither.
"""

from __future__ import annotations

from dataclasses import dataclass

from hdrc3_control.commands import Vec3


@dataclass(frozen=True, slots=True)
class GpsMeasurement:
    """One GPS fix converted to the local frame."""

    time: float
    position: Vec3
    """m, ENU."""
    velocity: Vec3
    """m/s, ENU."""


@dataclass(frozen=True, slots=True)
class ImuMeasurement:
    """Specific force and body rates (FRD)."""

    time: float
    specific_force: Vec3
    """m/s^2, body FRD (hover: about (0, 0, -9.81))."""
    angular_rate: Vec3
    """p, q, r, rad/s."""


@dataclass(frozen=True, slots=True)
class BaroMeasurement:
    """Barometric height above the local frame's origin altitude."""

    time: float
    height: float
    """m, same axis as ENU up (biased by weather drift)."""


@dataclass(frozen=True, slots=True)
class AttitudeMeasurement:
    """Attitude and heading from the attitude sensor (Euler 3-2-1)."""

    time: float
    roll: float
    pitch: float
    heading: float
    """rad clockwise from north."""


@dataclass(frozen=True, slots=True)
class GroundContactMeasurement:
    """Skid switch plus the ground height under the aircraft (from the world model)."""

    time: float
    on_ground: bool
    ground_height: float
    """Terrain height (ENU up) under the aircraft, m."""


@dataclass(frozen=True, slots=True)
class VisionPoseMeasurement:
    """Position from the vision system (landing pad pose), already converted to ENU."""

    time: float
    position: Vec3
    sigma: float = 0.05
    """1-sigma per axis, m (the chapter: cm accuracy)."""
