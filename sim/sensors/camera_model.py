"""Pinhole camera geometry: intrinsics, camera pose from aircraft pose and PTU angles, projection.

Optical frame: z along the optical axis, x to the image right, y to the image bottom; pixel
coordinates are continuous with (0, 0) at the top-left corner of the image.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.frames import body_to_enu, rot_y, rot_z
from sim.truth_state import TruthState

# Columns: optical x, y, z axes expressed in the PTU frame (x boresight, y right, z down).
_PTU_TO_OPTICAL: NDArray[np.float64] = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


@dataclass(frozen=True, slots=True)
class Intrinsics:
    """Pinhole intrinsics with square pixels."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    @staticmethod
    def from_fov(width: int, height: int, hfov: float) -> Intrinsics:
        """Intrinsics of an image ``width`` x ``height`` with horizontal field of view ``hfov``."""
        f = (width / 2.0) / math.tan(hfov / 2.0)
        return Intrinsics(width, height, f, f, width / 2.0, height / 2.0)

    @property
    def hfov(self) -> float:
        """Horizontal field of view, rad."""
        return 2.0 * math.atan(self.width / (2.0 * self.fx))

    @property
    def vfov(self) -> float:
        """Vertical field of view, rad."""
        return 2.0 * math.atan(self.height / (2.0 * self.fy))

    def matrix(self) -> NDArray[np.float64]:
        """Return the 3x3 camera matrix K."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])


@dataclass(frozen=True, slots=True)
class CameraPose:
    """Camera position (ENU, m) and rotation taking optical-frame vectors to ENU (row-major)."""

    position: tuple[float, float, float]
    rotation: tuple[tuple[float, float, float], ...]

    @staticmethod
    def of(position: NDArray[np.float64], rotation: NDArray[np.float64]) -> CameraPose:
        """Build from numpy arrays (kept as tuples so poses compare and hash by value)."""
        rows = tuple((float(r[0]), float(r[1]), float(r[2])) for r in rotation)
        return CameraPose((float(position[0]), float(position[1]), float(position[2])), rows)

    def matrix(self) -> NDArray[np.float64]:
        """Return the 3x3 rotation optical -> ENU."""
        return np.asarray(self.rotation, dtype=np.float64)

    @property
    def optical_axis(self) -> NDArray[np.float64]:
        """Unit viewing direction in ENU."""
        axis: NDArray[np.float64] = self.matrix()[:, 2].copy()
        return axis


def camera_pose(
    truth: TruthState, pan: float, tilt: float, mount_offset: tuple[float, float, float]
) -> CameraPose:
    """Pose of a camera on the PTU: aircraft pose, then mount point (body FRD), then pan/tilt."""
    body = body_to_enu(truth.roll, truth.pitch, truth.heading)
    position = np.asarray(truth.position_enu) + body @ np.asarray(mount_offset)
    ptu = rot_z(pan) @ rot_y(-tilt)  # positive tilt looks down (towards body +z)
    return CameraPose.of(position, body @ ptu @ _PTU_TO_OPTICAL)


def project(
    pose: CameraPose, intrinsics: Intrinsics, point: tuple[float, float, float]
) -> tuple[float, float] | None:
    """Pixel (u, v) of an ENU point, or None if it is behind the camera or outside the image."""
    local = pose.matrix().T @ (np.asarray(point) - np.asarray(pose.position))
    if local[2] <= 1e-9:
        return None
    u = intrinsics.fx * local[0] / local[2] + intrinsics.cx
    v = intrinsics.fy * local[1] / local[2] + intrinsics.cy
    if not (0.0 <= u <= intrinsics.width and 0.0 <= v <= intrinsics.height):
        return None
    return float(u), float(v)


def pixel_ray(pose: CameraPose, intrinsics: Intrinsics, u: float, v: float) -> NDArray[np.float64]:
    """Return the unit ENU direction of the ray through pixel (u, v)."""
    local = np.array(
        [(u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy, 1.0]
    )
    direction: NDArray[np.float64] = pose.matrix() @ (local / np.linalg.norm(local))
    return direction


def ground_point(
    pose: CameraPose, intrinsics: Intrinsics, u: float, v: float, ground_up: float
) -> tuple[float, float, float] | None:
    """Flat-world geolocation (section 11.1.1): where the pixel's ray meets up = ``ground_up``."""
    direction = pixel_ray(pose, intrinsics, u, v)
    if direction[2] >= -1e-9:
        return None
    t = (ground_up - pose.position[2]) / direction[2]
    if t <= 0.0:
        return None
    hit = np.asarray(pose.position) + t * direction
    return float(hit[0]), float(hit[1]), float(hit[2])
