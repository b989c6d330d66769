"""Rotations between the body frame (FRD), NED and the world's local ENU frame."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

NED_TO_ENU: NDArray[np.float64] = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
"""Maps NED coordinates to ENU (it is its own inverse)."""


def rot_x(angle: float) -> NDArray[np.float64]:
    """Rotation about x by ``angle`` (right-handed)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle: float) -> NDArray[np.float64]:
    """Rotation about y by ``angle`` (right-handed)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle: float) -> NDArray[np.float64]:
    """Rotation about z by ``angle`` (right-handed)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def body_to_enu(roll: float, pitch: float, heading: float) -> NDArray[np.float64]:
    """Matrix taking body FRD vectors to ENU, from Euler 3-2-1 angles (heading from north)."""
    body_to_ned = rot_z(heading) @ rot_y(pitch) @ rot_x(roll)
    result: NDArray[np.float64] = NED_TO_ENU @ body_to_ned
    return result
