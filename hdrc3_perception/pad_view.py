"""The landing pad as a pinhole camera sees it, drawn exactly: the pose estimator's test images.

:func:`render` intersects each (supersampled) pixel's ray with the pad's plane and looks the
point up in the printed pattern (:func:`sim.landing_pattern.is_black`), so the ellipses in the
image are exact to the sampling: the reference against which ``pad_pose`` is tested and
benchmarked. The simulator's renderer draws the same pattern on the world's pads (a triangle
mesh, with lighting and noise); tests run the estimator on both.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from hdrc3_perception.camera import Intrinsics
from sim.landing_pattern import PAD_HALF_WIDTH_M, is_black

WHITE = 235
BLACK = 25


def render(
    intrinsics: Intrinsics,
    rotation: NDArray[np.float64],
    translation: NDArray[np.float64],
    background: int = 110,
    supersample: int = 2,
) -> NDArray[np.uint8]:
    """The pad as a camera sees it: 8-bit grey image, ``height`` x ``width``.

    Args:
        intrinsics: The camera's pinhole model (no distortion).
        rotation: Pad frame -> camera frame (x right, y down, z forward).
        translation: The pad's origin in the camera frame (metres).
        background: Grey level of the ground around the pad.
        supersample: Samples per pixel side (anti-aliasing).
    """
    n = supersample
    offsets = (np.arange(n) + 0.5) / n - 0.5
    u = (np.arange(intrinsics.width)[:, None] + offsets[None, :]).reshape(-1)
    v = (np.arange(intrinsics.height)[:, None] + offsets[None, :]).reshape(-1)
    uu, vv = np.meshgrid(u, v)
    rays = np.stack(
        [
            (uu - intrinsics.cx) / intrinsics.fx,
            (vv - intrinsics.cy) / intrinsics.fy,
            np.ones_like(uu),
        ]
    )
    centre = -rotation.T @ translation  # the camera in the pad frame
    directions = np.tensordot(rotation.T, rays, axes=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        reach = -centre[2] / directions[2]
    x = centre[0] + reach * directions[0]
    y = centre[1] + reach * directions[1]
    on_pad = (reach > 0) & (np.abs(x) <= PAD_HALF_WIDTH_M) & (np.abs(y) <= PAD_HALF_WIDTH_M)
    grey = np.full(on_pad.shape, float(background))
    grey[on_pad] = np.where(is_black(x[on_pad], y[on_pad]), BLACK, WHITE)
    pixels = grey.reshape(intrinsics.height, n, intrinsics.width, n).mean(axis=(1, 3))
    out: NDArray[np.uint8] = np.round(pixels).astype(np.uint8)
    return out


def look_at(
    camera: tuple[float, float, float], roll: float = 0.0
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotation and translation of a camera at ``camera`` (pad frame) aimed at the pad's centre.

    ``roll`` turns the camera about its optical axis. Returns (pad -> camera rotation, the pad's
    origin in the camera frame), as :func:`render` takes them.
    """
    eye = np.asarray(camera, dtype=np.float64)
    forward = -eye / np.linalg.norm(eye)
    helper = np.array([0.0, 1.0, 0.0]) if abs(forward[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(forward, helper)
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    c, s = math.cos(roll), math.sin(roll)
    right, down = c * right + s * down, -s * right + c * down
    rotation = np.stack([right, down, forward])
    return rotation, -rotation @ eye
