"""Pad pose from rendered views: the chapter's ellipse-reprojection estimate, and its refusals."""

from __future__ import annotations

import math
from collections.abc import Iterator
from functools import cache
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

from hdrc3_perception.camera import Intrinsics
from hdrc3_perception.pad_pose import PoseStatus, estimate
from hdrc3_perception.pad_view import look_at, render
from hdrc3_perception.synthetic import COLOR_K


@cache
def view(
    eye: tuple[float, float, float], roll: float = 0.0
) -> tuple[NDArray[np.uint8], NDArray[np.float64]]:
    """The pad seen from ``eye`` (pad frame), and the pad's true position in the camera frame."""
    rotation, translation = look_at(eye, roll)
    return render(COLOR_K, rotation, translation), translation


@pytest.mark.parametrize(
    ("eye", "roll", "triplets"),
    [
        ((0.3, 0.2, 1.5), 0.0, {0, 1, 2, 3}),  # close: the small triplets
        ((1.0, 2.0, 5.0), 0.3, {1, 2, 3, 4}),
        ((3.0, -4.0, 8.0), -1.0, {2, 3, 4}),
        ((6.0, 6.0, 10.0), 2.0, {3, 4}),  # 45 degrees off nadir
        ((-10.0, 3.0, 15.0), 0.5, {3, 4}),
        ((0.0, 0.1, 18.0), 3.0, {3, 4}),  # 18 m: the two largest triplets
    ],
)
def test_the_pose_is_found_within_a_percent_of_the_range(
    eye: tuple[float, float, float], roll: float, triplets: set[int]
) -> None:
    image, truth = view(eye, roll)
    pose = estimate(image, COLOR_K)
    assert pose.status is PoseStatus.OK, pose.reason
    assert set(pose.triplets) == triplets
    distance = math.dist(eye, (0.0, 0.0, 0.0))
    assert pose.translation is not None
    assert np.linalg.norm(pose.translation - truth) <= 0.01 * distance
    # the camera on the pad: the attitude error (tenths of a degree) times the range adds up
    assert np.linalg.norm(pose.camera_in_pad - np.asarray(eye)) <= 0.03 * distance
    assert pose.rms_px < 0.5


def test_a_pad_half_out_of_the_image_uses_the_triplets_still_seen() -> None:
    rotation, translation = look_at((0.5, 0.5, 4.0))
    shifted = np.array([0.45, 0.0, 0.0])  # the pad's centre moves to the image's right edge
    image = render(COLOR_K, rotation, translation + shifted)
    pose = estimate(image, COLOR_K)
    assert pose.status is PoseStatus.OK, pose.reason
    assert pose.translation is not None
    assert np.linalg.norm(pose.translation - (translation + shifted)) <= 0.04


def test_image_noise_is_tolerated() -> None:
    image, truth = view((2.0, 1.0, 6.0), 0.7)
    noisy = np.clip(image + np.random.default_rng(0).normal(0.0, 6.0, image.shape), 0, 255)
    pose = estimate(noisy.astype(np.uint8), COLOR_K)
    assert pose.status is PoseStatus.OK, pose.reason
    assert pose.translation is not None
    assert np.linalg.norm(pose.translation - truth) <= 0.01 * 6.4


@pytest.mark.parametrize(
    ("image", "intrinsics", "status"),
    [
        (view((1.0, 2.0, 5.0), 0.3)[0][:, ::-1].copy(), COLOR_K, PoseStatus.MIRRORED),
        (np.full((576, 720), 110, np.uint8), COLOR_K, PoseStatus.NO_PATTERN),
        (view((0.0, 0.1, 60.0))[0], COLOR_K, PoseStatus.NO_PATTERN),  # too far to tell
        (np.zeros((576, 720, 3), np.uint8), COLOR_K, PoseStatus.BAD_IMAGE),  # colour, not grey
        (np.zeros((576, 720), np.float32), COLOR_K, PoseStatus.BAD_IMAGE),
        (np.zeros((4, 4), np.uint8), COLOR_K, PoseStatus.BAD_IMAGE),
        (view((1.0, 2.0, 5.0), 0.3)[0], None, PoseStatus.BAD_IMAGE),  # no calibration
    ],
)
def test_refusals_name_their_reason(
    image: NDArray[np.generic], intrinsics: Intrinsics | None, status: PoseStatus
) -> None:
    pose = estimate(image, intrinsics)
    assert pose.status is status
    assert pose.reason and pose.rotation is None


@pytest.fixture(scope="module")
def pad_world_renderer() -> Iterator[Any]:
    """The simulator's renderer on a flat world with one patterned pad (turned 23 deg)."""
    from sim.geodesy import GeodeticOrigin
    from sim.render.renderer import Renderer
    from sim.terrain import Terrain
    from sim.world import LandingPad, World

    pad = LandingPad("L1", 10.0, 20.0, 3.0, math.radians(23.0), pattern=True)
    world = World(
        name="pad",
        origin=GeodeticOrigin(55.7, 13.47, 95.0),
        terrain=Terrain.flat(-100.0, -100.0, 100.0, 100.0),
        pads=(pad,),
    )
    renderer = Renderer(world)
    yield renderer, pad
    renderer.release()


@pytest.mark.parametrize("offset", [(0.3, -0.4, 5.0), (-4.0, 6.0, 9.0), (8.0, 3.0, 14.0)])
def test_the_pose_is_found_on_the_simulators_renderer(
    pad_world_renderer: tuple[Any, Any], offset: tuple[float, float, float]
) -> None:
    import cv2

    from sim.landing_pattern import PRINT_HEIGHT_M
    from sim.render.projection import look_at as sim_look_at
    from sim.sensors.camera_model import Intrinsics as SimIntrinsics

    renderer, pad = pad_world_renderer
    plane = PRINT_HEIGHT_M  # the black rings' height above the flat ground
    centre = (pad.east, pad.north, plane)
    eye = (pad.east + offset[0], pad.north + offset[1], plane + offset[2])
    k = COLOR_K
    sim_k = SimIntrinsics(k.width, k.height, k.fx, k.fy, k.cx, k.cy)
    rgb = renderer.render_color(sim_look_at(eye, centre), sim_k)
    pose = estimate(cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2GRAY), k)
    assert pose.status is PoseStatus.OK, pose.reason
    s, c = math.sin(pad.heading), math.cos(pad.heading)
    east, north, up = offset  # ENU from the pad's centre -> the pad frame (turned clockwise)
    truth = np.array([c * east - s * north, s * east + c * north, up])
    assert np.linalg.norm(pose.camera_in_pad - truth) <= 0.03 * float(np.linalg.norm(truth))
