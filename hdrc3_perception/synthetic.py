"""Synthetic colour + thermal pairs for tests and the benchmark (not a renderer).

Known ground shapes are projected with known camera poses through :mod:`hdrc3_perception.camera`
and filled with OpenCV: a warm ellipse per body in the thermal image, a person-like silhouette
(head, torso, arms, legs lying on the ground) in the colour image, over a noisy background. The
geometry is exact, so geolocation can be checked against the shapes' ground truth. The simulator's
renderer (``sim/render``) makes the real frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from hdrc3_perception.camera import MOUNT_OFFSET, CameraPose, Intrinsics, NavPose
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.pipeline import COLOR_ENCODING, THERMAL_ENCODING, CameraImage, FramePair
from hdrc3_perception.thermal import CENTI_KELVIN

COLOR_K = Intrinsics.from_fov(720, 576, math.radians(48.0))
THERMAL_K = Intrinsics.from_fov(160, 120, math.radians(25.0))

# Silhouette of a person lying on the ground, metres: x from the feet to the head, y across.
_PARTS: tuple[tuple[tuple[float, float], ...], ...] = (
    ((0.0, -0.22), (0.85, -0.2), (0.85, -0.04), (0.0, -0.08)),  # left leg
    ((0.0, 0.08), (0.85, 0.04), (0.85, 0.2), (0.0, 0.22)),  # right leg
    ((0.82, -0.2), (1.45, -0.22), (1.45, 0.22), (0.82, 0.2)),  # torso
    ((0.85, -0.31), (1.42, -0.3), (1.42, -0.22), (0.85, -0.23)),  # left arm
    ((0.85, 0.23), (1.42, 0.22), (1.42, 0.3), (0.85, 0.31)),  # right arm
    ((1.45, -0.05), (1.5, -0.05), (1.5, 0.05), (1.45, 0.05)),  # neck
)
_HEAD = (1.6, 0.0, 0.11)
_GRASS = (84, 116, 58)


@dataclass(frozen=True, slots=True)
class Body:
    """A body lying on the ground: feet-to-head axis along ``heading`` (rad from east)."""

    east: float
    north: float
    heading: float = 0.0
    kelvin: float = 306.0
    length: float = 1.7
    width: float = 0.55
    """Of the warm ellipse, m."""


def _ground_points(body: Body, local: NDArray[np.float64], ground: Ground) -> NDArray[np.float64]:
    c, s = math.cos(body.heading), math.sin(body.heading)
    x = local[:, 0] - body.length / 2.0  # centred on the body's middle
    east = body.east + c * x - s * local[:, 1]
    north = body.north + s * x + c * local[:, 1]
    up = np.array([ground.up(e, n) for e, n in zip(east, north, strict=True)])
    return np.stack([east, north, up], axis=1)


def _fill(
    image: NDArray[np.uint8] | NDArray[np.float64],
    pose: CameraPose,
    k: Intrinsics,
    points: NDArray[np.float64],
    value: float | tuple[int, ...],
) -> None:
    px = pose.project(k, points)
    if np.isnan(px).any():
        return
    cv2.fillPoly(image, [np.round(px * 16).astype(np.int32)], value, cv2.LINE_AA, shift=4)


def ellipse_outline(body: Body, samples: int = 36) -> NDArray[np.float64]:
    """Body-local outline (x from the feet, y across) of the body's warm ellipse."""
    a = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    return np.stack([body.length / 2.0 * (1 + np.cos(a)), body.width / 2.0 * np.sin(a)], axis=1)


def render_pair(
    time: float,
    nav: NavPose,
    pan: float,
    tilt: float,
    bodies: list[Body],
    ground: Ground,
    rng: np.random.Generator,
    background_kelvin: float = 291.0,
) -> FramePair:
    """A colour and a thermal image of ``bodies`` seen from ``nav`` with the PTU at pan/tilt."""
    pose = CameraPose.of(nav, pan, tilt, MOUNT_OFFSET)
    thermal = rng.normal(
        background_kelvin * CENTI_KELVIN, 40.0, (THERMAL_K.height, THERMAL_K.width)
    )
    # grass: a random 72x90 tile repeated (cheap enough for the benchmark's frame stream)
    tile = rng.integers(0, 25, (COLOR_K.height // 8, COLOR_K.width // 8, 3), dtype=np.uint8)
    color = np.ascontiguousarray(np.tile(tile + np.array(_GRASS, np.uint8), (8, 8, 1)))
    for body in bodies:
        outline = _ground_points(body, ellipse_outline(body), ground)
        _fill(thermal, pose, THERMAL_K, outline, body.kelvin * CENTI_KELVIN)
        for part in _PARTS:
            _fill(color, pose, COLOR_K, _ground_points(body, np.array(part), ground), (40, 40, 60))
        a = np.linspace(0.0, 2.0 * math.pi, 16, endpoint=False)
        head = np.stack([_HEAD[0] + _HEAD[2] * np.cos(a), _HEAD[2] * np.sin(a)], axis=1)
        _fill(color, pose, COLOR_K, _ground_points(body, head, ground), (200, 160, 130))
    return FramePair(
        time,
        CameraImage(color, COLOR_ENCODING, COLOR_K),
        CameraImage(np.clip(thermal, 0, 65535).astype(np.uint16), THERMAL_ENCODING, THERMAL_K),
        nav,
        pan,
        tilt,
    )
