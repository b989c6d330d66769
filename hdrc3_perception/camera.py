"""Camera geometry on the PPC side: intrinsics, camera pose from the navigation solution + PTU.

The perception core sits beside the control kernel (layer 2) and must not use the simulator's
sensor models, so this module writes the pinhole model out itself. It follows the image contract
of the simulator's renderer (``sensor_msgs/CameraInfo`` K; optical frame z forward, x right,
y down; camera = aircraft pose, then the PTU mount point in body FRD, then pan about body z and
tilt about the PTU's y with positive tilt looking down). The pose is built from the aircraft's
OWN navigation solution and PTU readings; the tests check it against the simulator's model.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from hdrc3_platform_server.geo_frame import WorldFrame
from sim.airframe import PTU_MOUNT_FRD

Vec3 = tuple[float, float, float]

_NED_TO_ENU: NDArray[np.float64] = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
# Columns: optical x, y, z axes in the PTU frame (x boresight, y right, z down).
_PTU_TO_OPTICAL: NDArray[np.float64] = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])

MOUNT_OFFSET: Vec3 = PTU_MOUNT_FRD
"""PTU centre relative to the centre of gravity, body FRD, m: the payload's mounting calibration
(``sim.airframe``, data the simulated platform is built to)."""


def _rot_x(a: float) -> NDArray[np.float64]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_y(a: float) -> NDArray[np.float64]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rot_z(a: float) -> NDArray[np.float64]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def body_to_enu(roll: float, pitch: float, heading: float) -> NDArray[np.float64]:
    """Rotation taking body-FRD vectors to ENU (Euler 3-2-1, heading clockwise from north)."""
    rotation: NDArray[np.float64] = _NED_TO_ENU @ _rot_z(heading) @ _rot_y(pitch) @ _rot_x(roll)
    return rotation


def euler_of(body: NDArray[np.float64]) -> tuple[float, float, float]:
    """Roll, pitch and heading (rad, heading in [0, 2 pi)) of a body-FRD -> ENU rotation."""
    ned = _NED_TO_ENU.T @ body
    pitch = -math.asin(max(-1.0, min(1.0, float(ned[2, 0]))))
    roll = math.atan2(float(ned[2, 1]), float(ned[2, 2]))
    heading = math.atan2(float(ned[1, 0]), float(ned[0, 0])) % math.tau
    return roll, pitch, 0.0 if heading >= math.tau else heading


def optical_to_body(pan: float, tilt: float) -> NDArray[np.float64]:
    """Rotation taking the camera's optical-frame vectors to body FRD at these PTU angles."""
    rotation: NDArray[np.float64] = _rot_z(pan) @ _rot_y(-tilt) @ _PTU_TO_OPTICAL
    return rotation


@dataclass(frozen=True, slots=True)
class Intrinsics:
    """Pinhole intrinsics of one image (pixels; (0, 0) is the top-left corner)."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @staticmethod
    def from_k(width: int, height: int, k: Sequence[float]) -> Intrinsics | None:
        """From a row-major 3x3 K (``CameraInfo.k``); None if it is not a usable calibration."""
        if len(k) != 9 or width <= 0 or height <= 0:
            return None
        values = [float(v) for v in k]
        if not all(math.isfinite(v) for v in values) or values[0] <= 0.0 or values[4] <= 0.0:
            return None
        return Intrinsics(width, height, values[0], values[4], values[2], values[5])

    @staticmethod
    def from_fov(width: int, height: int, hfov: float) -> Intrinsics:
        """Square pixels, principal point at the centre, horizontal field of view ``hfov``."""
        f = (width / 2.0) / math.tan(hfov / 2.0)
        return Intrinsics(width, height, f, f, width / 2.0, height / 2.0)

    def k(self) -> tuple[float, ...]:
        """Row-major K as ``CameraInfo.k`` carries it."""
        return (self.fx, 0.0, self.cx, 0.0, self.fy, self.cy, 0.0, 0.0, 1.0)

    def direction(self, u: float, v: float) -> NDArray[np.float64]:
        """Unit vector through pixel (u, v) in the optical frame (x right, y down, z forward)."""
        local = np.array([(u - self.cx) / self.fx, (v - self.cy) / self.fy, 1.0])
        unit: NDArray[np.float64] = local / np.linalg.norm(local)
        return unit


@dataclass(frozen=True, slots=True)
class NavPose:
    """The aircraft's navigation solution: ENU position (m) and Euler 3-2-1 angles (rad)."""

    position: Vec3
    roll: float
    pitch: float
    heading: float
    """Clockwise from north."""

    def is_finite(self) -> bool:
        """True if every number is finite."""
        return all(math.isfinite(v) for v in (*self.position, self.roll, self.pitch, self.heading))

    @staticmethod
    def of_state(frame: WorldFrame, state: Any) -> NavPose:
        """The pose a Data Interface ``HelicopterState`` (WGS84, Euler angles) gives in ENU.

        Non-finite input gives a non-finite pose (:meth:`is_finite` says so).
        """
        east, north, up = frame.to_enu(state.longitude, state.latitude, state.altitude)
        return NavPose(
            (east, north, up), float(state.roll), float(state.pitch), float(state.heading)
        )


@dataclass(frozen=True, slots=True)
class CameraPose:
    """Camera centre (ENU, m) and rotation taking optical-frame vectors to ENU."""

    position: NDArray[np.float64]
    rotation: NDArray[np.float64]

    @staticmethod
    def of(nav: NavPose, pan: float, tilt: float, mount: Vec3 = MOUNT_OFFSET) -> CameraPose:
        """Pose of a camera on the PTU: body attitude, mount point, then pan and tilt."""
        body = body_to_enu(nav.roll, nav.pitch, nav.heading)
        position = np.asarray(nav.position, dtype=np.float64) + body @ np.asarray(mount)
        return CameraPose(position, body @ optical_to_body(pan, tilt))

    def project(self, intrinsics: Intrinsics, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Pixels (N, 2) of ENU points (N, 3); NaN rows for points behind the camera."""
        local = (np.atleast_2d(points) - self.position) @ self.rotation
        with np.errstate(divide="ignore", invalid="ignore"):
            u = intrinsics.fx * local[:, 0] / local[:, 2] + intrinsics.cx
            v = intrinsics.fy * local[:, 1] / local[:, 2] + intrinsics.cy
        pixels = np.stack([u, v], axis=1)
        pixels[local[:, 2] <= 1e-9] = np.nan
        return pixels

    def sees(
        self, intrinsics: Intrinsics, points: NDArray[np.float64], margin_m: float = 0.0
    ) -> NDArray[np.bool_]:
        """Mask of the ENU points (N, 3) that project inside the image.

        Args:
            intrinsics: The camera's calibration.
            points: ENU points (N, 3).
            margin_m: Ground distance a point must keep from the image border: the border
                margin in pixels is ``margin_m`` x focal length / range, per point.
        """
        pts = np.atleast_2d(points)
        px = self.project(intrinsics, pts)
        distance = np.linalg.norm(pts - self.position, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            m = margin_m * (intrinsics.fx + intrinsics.fy) / 2.0 / distance
            inside: NDArray[np.bool_] = (
                (px[:, 0] >= m)
                & (px[:, 0] <= intrinsics.width - m)
                & (px[:, 1] >= m)
                & (px[:, 1] <= intrinsics.height - m)
            )
        return inside

    def ray(self, intrinsics: Intrinsics, u: float, v: float) -> NDArray[np.float64]:
        """Unit ENU direction of the ray through pixel (u, v)."""
        direction: NDArray[np.float64] = self.rotation @ intrinsics.direction(u, v)
        return direction
