"""Ground truth in ROS conventions (REP 103): FLU body frame in the world's ENU frame.

The simulator works with aerospace angles (Euler 3-2-1, heading clockwise from north, body
x forward / y right / z down); ``nav_msgs/Odometry`` wants the orientation of a body frame with
x forward / y left / z up relative to ENU, and the twist in that body frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.truth_state import TruthState

Vec3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class FluOdometry:
    """Orientation (x, y, z, w) of the FLU body in ENU, and body-frame FLU velocities."""

    orientation: tuple[float, float, float, float]
    linear: Vec3
    """m/s, FLU body frame."""
    angular: Vec3
    """rad/s, FLU body frame."""


def flu_quaternion(roll: float, pitch: float, heading: float) -> tuple[float, float, float, float]:
    """Quaternion (x, y, z, w) of the FLU body frame in ENU from aerospace Euler angles.

    In ENU/FLU terms the yaw is measured counter-clockwise from east (pi/2 - heading), pitch is
    nose-down positive (-pitch) and roll keeps its sign; the rotation is yaw * pitch * roll.
    """
    yaw = 0.5 * math.pi - heading
    cy, sy = math.cos(0.5 * yaw), math.sin(0.5 * yaw)
    cp, sp = math.cos(-0.5 * pitch), math.sin(-0.5 * pitch)
    cr, sr = math.cos(0.5 * roll), math.sin(0.5 * roll)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def enu_to_flu(vector: Vec3, roll: float, pitch: float, heading: float) -> Vec3:
    """Express an ENU vector in the FLU body frame."""
    e, n, u = vector
    # ENU -> NED -> body FRD (transpose of the 3-2-1 rotation), then FRD -> FLU
    ch, sh = math.cos(heading), math.sin(heading)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cr, sr = math.cos(roll), math.sin(roll)
    north, east, down = n, e, -u
    x1 = ch * north + sh * east
    y1 = -sh * north + ch * east
    z1 = down
    x2 = cp * x1 - sp * z1
    z2 = sp * x1 + cp * z1
    y3 = cr * y1 + sr * z2
    z3 = -sr * y1 + cr * z2
    return (x2, -y3, -z3)


def flu_odometry(truth: TruthState) -> FluOdometry:
    """Orientation and body-frame twist of ``truth`` in ROS conventions."""
    r, p, h = truth.roll, truth.pitch, truth.heading
    rates = truth.body_rates
    return FluOdometry(
        flu_quaternion(r, p, h),
        enu_to_flu(truth.velocity_enu, r, p, h),
        (rates[0], -rates[1], -rates[2]),
    )
