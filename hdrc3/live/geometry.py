"""Small geometry helpers of the live view: poses in the ``world`` ENU frame, times, colours.

The world frame of every live channel is the local ENU frame of the world's geodetic origin
(x east, y north, z up), as in ``sim/world.py``; an aircraft's frame is its body frame with x
forward, y left, z up (the FLU convention of ROS REP 103).
"""

from __future__ import annotations

import math

from foxglove.messages import Color, Point3, Pose, Quaternion, Timestamp, Vector3

WORLD_FRAME = "world"


def timestamp(ns: int) -> Timestamp:
    """A Foxglove timestamp of integer nanoseconds."""
    return Timestamp(sec=ns // 1_000_000_000, nsec=ns % 1_000_000_000)


def attitude_quaternion(roll: float, pitch: float, heading: float) -> tuple[float, ...]:
    """(x, y, z, w) of a body (FLU) in ENU from aeronautical roll, pitch and heading.

    Heading is clockwise from north, pitch positive nose up, roll positive right wing down (FRD
    Euler angles): the ENU yaw is ``pi/2 - heading`` and the FLU pitch is ``-pitch``.
    """
    yaw = math.pi / 2 - heading
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(-pitch / 2), math.sin(-pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def quaternion(xyzw: tuple[float, ...]) -> Quaternion:
    """A Foxglove quaternion of (x, y, z, w)."""
    x, y, z, w = xyzw
    return Quaternion(x=x, y=y, z=z, w=w)


def pose(east: float = 0.0, north: float = 0.0, up: float = 0.0, heading: float = 0.0) -> Pose:
    """A pose at (east, north, up) turned to ``heading`` (rad, clockwise from north)."""
    return Pose(
        position=Vector3(x=east, y=north, z=up),
        orientation=quaternion(attitude_quaternion(0.0, 0.0, heading)),
    )


def point(x: float, y: float, z: float) -> Point3:
    """A Foxglove point."""
    return Point3(x=x, y=y, z=z)


def color(r: float, g: float, b: float, a: float = 1.0) -> Color:
    """A Foxglove colour (components 0..1)."""
    return Color(r=r, g=g, b=b, a=a)


def height_color(height: float, low: float, high: float) -> Color:
    """Terrain colour: green in the lows to brown in the highs."""
    t = 0.0 if high <= low else min(1.0, max(0.0, (height - low) / (high - low)))
    return color(0.35 + 0.3 * t, 0.55 - 0.15 * t, 0.25 + 0.05 * t)
