"""Pan-tilt control modes: look-at geometry, clamping, on-target, mode switching."""

from __future__ import annotations

import math

import pytest

from hdrc3_control.ppc_hardware import COLOR, THERMAL, PtuLimits
from hdrc3_control.ppc_modes import (
    ImageProcessing,
    PadVision,
    Pose,
    PtuController,
    PtuMode,
    clamp,
    look_at_angles,
    on_target,
    pad_vision,
)

LEVEL = Pose((0.0, 0.0, 50.0), 0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("pose", "target", "pan_deg", "tilt_deg"),
    [
        (LEVEL, (0.0, 100.0, 50.0), 0.0, 0.0),  # ahead (north) at the same height
        (LEVEL, (100.0, 0.0, 50.0), 90.0, 0.0),  # east = right of a north-facing aircraft
        (LEVEL, (-100.0, 0.0, 50.0), -90.0, 0.0),
        (LEVEL, (0.0, 50.0, 0.0), 0.0, 45.0),  # ahead and below
        (LEVEL, (0.0, 0.0, 0.0), 0.0, 90.0),  # straight down
        (
            Pose((0.0, 0.0, 50.0), 0.0, 0.0, math.pi / 2),
            (100.0, 0.0, 50.0),
            0.0,
            0.0,
        ),  # facing east
        (Pose((0.0, 0.0, 50.0), 0.0, math.radians(10.0), 0.0), (0.0, 100.0, 50.0), 0.0, 10.0),
        (Pose((0.0, 0.0, 50.0), math.radians(20.0), 0.0, 0.0), (0.0, 0.0, 0.0), 90.0, 70.0),
    ],
)
def test_look_at_angles(
    pose: Pose, target: tuple[float, float, float], pan_deg: float, tilt_deg: float
) -> None:
    pan, tilt = look_at_angles(pose, target, mount=(0.0, 0.0, 0.0))
    assert math.degrees(tilt) == pytest.approx(tilt_deg, abs=1e-6)
    if abs(tilt_deg) < 89.0:
        assert math.degrees(pan) == pytest.approx(pan_deg, abs=1e-6)


def test_mount_offset_shifts_the_angles_slightly() -> None:
    with_mount = look_at_angles(LEVEL, (0.0, 50.0, 0.0))
    without = look_at_angles(LEVEL, (0.0, 50.0, 0.0), mount=(0.0, 0.0, 0.0))
    assert 0.0 < abs(with_mount[1] - without[1]) < math.radians(2.0)


def test_clamp_and_on_target() -> None:
    limits = PtuLimits()
    assert clamp(limits, math.radians(200), math.radians(-30)) == (limits.max_pan, limits.min_tilt)
    assert on_target((0.1, 0.2), (0.1 + math.radians(0.5), 0.2))
    assert not on_target((0.1, 0.2), (0.1 + math.radians(2.0), 0.2))


def test_controller_modes() -> None:
    ptu = PtuController()
    assert ptu.update(LEVEL) is None and ptu.mode is PtuMode.IDLE
    ptu.turn_to(0.5, 1.0)
    assert ptu.update(None) == (0.5, 1.0) and ptu.mode is PtuMode.TURN_TO
    ptu.look_at((0.0, 0.0, 0.0))
    assert ptu.update(None) == (0.5, 1.0)  # no pose yet: keeps the last set-point
    sp = ptu.update(LEVEL)
    assert sp is not None and sp[1] == pytest.approx(math.pi / 2, abs=0.02)
    ptu.look_at((0.0, -100.0, 50.0))  # behind: pan beyond the limits
    ptu.update(LEVEL)
    assert not ptu.reachable
    ptu.reset()
    assert ptu.update(LEVEL) is None and ptu.mode is PtuMode.IDLE


@pytest.mark.parametrize("spec", [COLOR, THERMAL])
def test_camera_focal_and_fov(spec: object) -> None:
    from hdrc3_control.ppc_hardware import CameraSpec

    assert isinstance(spec, CameraSpec)
    assert spec.hfov(0.0) == pytest.approx(spec.hfov_wide)
    assert spec.hfov(1.0) == pytest.approx(spec.hfov_tele)
    assert spec.focal(2.0) == spec.focal(1.0)


IP = ImageProcessing


@pytest.mark.parametrize(
    ("camera", "pipeline", "function", "image_age", "state"),
    [
        (False, False, IP.IDLE, math.inf, PadVision.NONE),  # hdrc3 demo --basic: nothing
        (False, True, IP.STATE_ESTIMATION, 0.1, PadVision.NONE),  # no camera: nothing to see
        (True, False, IP.IDLE, math.inf, PadVision.NONE),  # camera, but no pad pose node
        (True, True, IP.IDLE, math.inf, PadVision.READY),
        (True, True, IP.SALIENCY, math.inf, PadVision.BUSY),
        (True, True, IP.COLOR_TRACKER, 0.1, PadVision.BUSY),
        (True, True, IP.STATE_ESTIMATION, math.inf, PadVision.ENGAGED),  # just engaged
        (True, True, IP.STATE_ESTIMATION, 2.5, PadVision.ENGAGED),  # images stopped
        (True, True, IP.STATE_ESTIMATION, 1.9, PadVision.RUNNING),
    ],
)
def test_pad_vision_says_what_the_ppc_can_do_for_a_vision_landing(
    camera: bool, pipeline: bool, function: ImageProcessing, image_age: float, state: PadVision
) -> None:
    assert pad_vision(camera, pipeline, function, image_age, 2.0) is state
    assert state.describe()
