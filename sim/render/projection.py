"""OpenGL matrices from the simulator's pinhole camera (``sim.sensors.camera_model``).

The clip transform is built so that a world point lands on exactly the pixel that
:func:`sim.sensors.camera_model.project` gives: u = fx x/z + cx, v = fy y/z + cy in the optical
frame (z forward, x right, y down), with (0, 0) the top-left corner of the image. Normalised
device y is +1 at the *bottom* of the image (v = height), so the framebuffer's first row read
back is the image's top row and no flip is needed.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from sim.sensors.camera_model import CameraPose, Intrinsics

NEAR_M = 0.5
FAR_M = 3000.0


def view_matrix(pose: CameraPose) -> NDArray[np.float64]:
    """4x4 world ENU -> optical frame."""
    rotation = pose.matrix()
    view = np.eye(4)
    view[:3, :3] = rotation.T
    view[:3, 3] = -rotation.T @ np.asarray(pose.position)
    return view


def projection_matrix(
    intrinsics: Intrinsics, near: float = NEAR_M, far: float = FAR_M
) -> NDArray[np.float64]:
    """4x4 optical frame -> clip space for an image of the intrinsics' size."""
    w, h = intrinsics.width, intrinsics.height
    proj = np.zeros((4, 4))
    proj[0, 0] = 2.0 * intrinsics.fx / w
    proj[0, 2] = 2.0 * intrinsics.cx / w - 1.0
    proj[1, 1] = 2.0 * intrinsics.fy / h
    proj[1, 2] = 2.0 * intrinsics.cy / h - 1.0
    proj[2, 2] = (far + near) / (far - near)
    proj[2, 3] = -2.0 * far * near / (far - near)
    proj[3, 2] = 1.0
    return proj


def clip_matrix(pose: CameraPose, intrinsics: Intrinsics) -> NDArray[np.float64]:
    """4x4 world ENU -> clip space (projection @ view)."""
    clip: NDArray[np.float64] = projection_matrix(intrinsics) @ view_matrix(pose)
    return clip


def gl_bytes(matrix: NDArray[np.float64]) -> bytes:
    """A 4x4 matrix as the column-major float32 bytes a GLSL ``mat4`` uniform takes."""
    return np.ascontiguousarray(matrix.T, dtype=np.float32).tobytes()


def look_at(eye: tuple[float, float, float], target: tuple[float, float, float]) -> CameraPose:
    """Pose of a camera at ``eye`` looking at ``target``, horizon level.

    Looking straight down, the image top points north.
    """
    position = np.asarray(eye, dtype=np.float64)
    z = np.asarray(target, dtype=np.float64) - position
    z /= np.linalg.norm(z)
    up = np.array([0.0, 0.0, 1.0]) if abs(z[2]) < 0.999 else np.array([0.0, 1.0, 0.0])
    x = np.cross(z, up)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return CameraPose.of(position, np.column_stack([x, y, z]))
