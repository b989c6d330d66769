"""Pairing of camera metadata and exposure poses; frozen frames repeat; CameraInfo rows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim.render.camera_feed import (
    MAX_PENDING,
    CameraFeed,
    CameraMeta,
    ExposurePairs,
    FrameAction,
    FrameRequest,
    pose_from_ros,
    pose_to_ros,
    projection_rows,
)
from sim.render.projection import look_at
from sim.sensors.camera import COLOR_CAMERA, CameraId, camera_intrinsics

POSE_A = look_at((0.0, 0.0, 40.0), (5.0, 3.0, 0.0))
POSE_B = look_at((1.0, 0.0, 40.0), (5.0, 3.0, 0.0))
META = CameraMeta(0.1, 1.2, 0.25)


@pytest.mark.parametrize("pose_first", [True, False])
def test_a_frame_needs_both_halves_in_either_order(pose_first: bool) -> None:
    feed = CameraFeed(CameraId.COLOR)
    if pose_first:
        assert feed.on_pose(40, POSE_A) is None
        request = feed.on_meta(40, META)
    else:
        assert feed.on_meta(40, META) is None
        request = feed.on_pose(40, POSE_A)
    assert request is not None
    assert request.stamp_ns == 40 and request.pose == POSE_A and request.meta == META
    assert request.action is FrameAction.RENDER
    assert request.intrinsics == camera_intrinsics(COLOR_CAMERA, 0.25)


def test_unchanged_metadata_repeats_the_last_image() -> None:
    feed = CameraFeed(CameraId.THERMAL)
    actions = []
    for stamp, pose in ((40, POSE_A), (80, POSE_A), (120, POSE_B), (160, POSE_B)):
        feed.on_pose(stamp, pose)
        request = feed.on_meta(stamp, META)
        assert request is not None
        actions.append(request.action)
    assert actions == [FrameAction.RENDER, FrameAction.REPEAT, FrameAction.RENDER,
                       FrameAction.REPEAT]  # fmt: skip
    feed.reset()
    feed.on_pose(0, POSE_B)
    request = feed.on_meta(0, META)
    assert request is not None and request.action is FrameAction.RENDER


def test_unpaired_halves_are_bounded_and_older_ones_dropped() -> None:
    feed = CameraFeed(CameraId.COLOR)
    for stamp in range(3 * MAX_PENDING):
        assert feed.on_pose(stamp, POSE_A) is None
    assert feed.on_meta(0, META) is None  # forgotten: the renderer fell behind
    request = feed.on_meta(3 * MAX_PENDING - 1, META)
    assert request is not None
    assert feed.on_meta(3 * MAX_PENDING - 2, META) is None  # older than a completed pair


def test_pose_round_trip_through_a_quaternion() -> None:
    position, quat = pose_to_ros(POSE_A)
    assert math.isclose(float(np.linalg.norm(quat)), 1.0)
    back = pose_from_ros(position, quat)  # type: ignore[arg-type]
    assert back is not None
    assert np.allclose(back.matrix(), POSE_A.matrix(), atol=1e-12)
    assert back.position == POSE_A.position


@pytest.mark.parametrize(
    ("position", "quat"),
    [
        ((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
        ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0)),
        ((0.0, 0.0, 0.0), (0.0, 0.0, math.inf, 1.0)),
        ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0, 1.0)),
    ],
)
def test_bad_poses_are_refused(position: tuple[float, ...], quat: tuple[float, ...]) -> None:
    assert pose_from_ros(position, quat) is None  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "meta",
    [
        CameraMeta(math.nan, 0.0, 0.0),
        CameraMeta(0.0, math.inf, 0.0),
        CameraMeta(0.0, 0.0, 1.5),
        CameraMeta(0.0, 0.0, math.nan),
    ],
)
def test_bad_metadata_makes_no_frame(meta: CameraMeta) -> None:
    feed = CameraFeed(CameraId.COLOR)
    feed.on_pose(40, POSE_A)
    assert feed.on_meta(40, meta) is None


def test_camera_info_rows() -> None:
    k = camera_intrinsics(COLOR_CAMERA, 0.0)
    rows, p = projection_rows(k)
    assert np.allclose(np.reshape(rows, (3, 3)), k.matrix())
    assert np.allclose(np.reshape(p, (3, 4))[:, :3], k.matrix())
    assert p[3] == p[7] == p[11] == 0.0


def request(camera: CameraId, stamp: int) -> FrameRequest:
    intrinsics = camera_intrinsics(COLOR_CAMERA, 0.0)
    return FrameRequest(stamp, camera, POSE_A, intrinsics, META, FrameAction.RENDER)


C, T = CameraId.COLOR, CameraId.THERMAL


@pytest.mark.parametrize(
    ("offers", "released", "dropped"),
    [
        # (camera, stamp) offered in order -> the (camera, stamp) rendered, in order
        ([(C, 40), (T, 40)], [(C, 40), (T, 40)], 0),
        ([(T, 40), (C, 40)], [(C, 40), (T, 40)], 0),
        # the renderer fell behind: thermal 40 was skipped, colour 40 is not rendered alone
        ([(C, 40), (C, 80), (T, 80)], [(C, 80), (T, 80)], 1),
        ([(C, 40), (T, 80), (C, 80)], [(C, 80), (T, 80)], 1),
        ([(C, 40), (T, 80), (C, 120), (T, 120)], [(C, 120), (T, 120)], 2),
    ],
)
def test_both_cameras_wanted_render_in_pairs_of_one_stamp(
    offers: list[tuple[CameraId, int]], released: list[tuple[CameraId, int]], dropped: int
) -> None:
    pairs = ExposurePairs()
    out = [r for camera, stamp in offers for r in pairs.offer(request(camera, stamp), True)]
    assert [(r.camera, r.stamp_ns) for r in out] == released
    assert pairs.dropped == dropped


def test_one_camera_wanted_renders_every_request() -> None:
    pairs = ExposurePairs()
    assert pairs.offer(request(C, 40), True) == []  # held while both were wanted
    out = [r.stamp_ns for s in (80, 120) for r in pairs.offer(request(C, s), False)]
    assert out == [80, 120]
    assert pairs.offer(request(T, 80), True) == []  # the colour one held before is gone
