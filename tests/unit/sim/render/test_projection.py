"""The GL clip transform puts world points on the pixels camera_model.project gives."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.render.projection import clip_matrix, gl_bytes
from sim.sensors.camera_model import CameraPose, Intrinsics, camera_pose, pixel_ray, project
from sim.sensors.fake_truth import make_truth
from sim.truth_state import TruthState

INTRINSICS = (
    Intrinsics.from_fov(640, 480, math.radians(48.0)),
    Intrinsics(200, 150, 180.0, 181.5, 90.3, 80.7),
    Intrinsics.from_fov(160, 120, math.radians(25.0)),
)


def _truth(heading: float, roll: float, pitch: float) -> TruthState:
    return make_truth(position_enu=(10.0, -20.0, 45.0), heading=heading, roll=roll, pitch=pitch)


POSES = (
    camera_pose(_truth(0.3, 0.05, -0.02), 0.0, math.radians(90.0), (0.3, 0.0, 0.45)),
    camera_pose(_truth(2.0, -0.1, 0.08), 0.4, math.radians(40.0), (0.3, 0.0, 0.45)),
    camera_pose(_truth(5.5, 0.0, 0.0), -1.2, math.radians(15.0), (0.3, 0.0, 0.45)),
)


def _pixel(clip: np.ndarray, k: Intrinsics, point: np.ndarray) -> tuple[float, float]:
    c = clip @ np.append(point, 1.0)
    ndc = c[:3] / c[3]
    return (ndc[0] + 1.0) / 2.0 * k.width, (ndc[1] + 1.0) / 2.0 * k.height


@pytest.mark.parametrize("intrinsics", INTRINSICS)
@pytest.mark.parametrize("pose", POSES)
def test_clip_matrix_matches_project(pose: CameraPose, intrinsics: Intrinsics) -> None:
    rng = np.random.default_rng(1)
    clip = clip_matrix(pose, intrinsics)
    # float32 as the GPU sees it
    clip32 = np.frombuffer(gl_bytes(clip), dtype=np.float32).reshape(4, 4).T.astype(np.float64)
    for _ in range(200):
        u, v = rng.uniform(0.0, intrinsics.width), rng.uniform(0.0, intrinsics.height)
        distance = rng.uniform(1.0, 500.0)
        point = np.asarray(pose.position) + distance * pixel_ray(pose, intrinsics, u, v)
        expected = project(pose, intrinsics, tuple(point))
        assert expected == pytest.approx((u, v), abs=1e-6)
        assert _pixel(clip, intrinsics, point) == pytest.approx(expected, abs=1e-6)
        assert _pixel(clip32, intrinsics, point) == pytest.approx(expected, abs=2e-3)
        depth = (clip @ np.append(point, 1.0))[2] / (clip @ np.append(point, 1.0))[3]
        assert -1.0 < depth < 1.0
