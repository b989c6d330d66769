"""The helicopter's fix from the pad's pose: exact geometry, the simulator's renderer, refusals."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import cv2
import numpy as np
import pytest
from numpy.typing import NDArray

from hdrc3_base.errors import ConfigError
from hdrc3_control.ppc_modes import Pose, look_at_angles
from hdrc3_perception.camera import CameraPose, NavPose
from hdrc3_perception.pad_fix import (
    FixStatus,
    PadPlacement,
    fix_sigma,
    helicopter_fix,
)
from hdrc3_perception.pad_pose import PoseStatus, estimate
from hdrc3_perception.synthetic import COLOR_K
from sim.geodesy import GeodeticOrigin
from sim.landing_pattern import PRINT_HEIGHT_M
from sim.terrain import Terrain
from sim.world import LandingPad, World
from sim.world_loader import load_world

PAD = LandingPad("L9", 10.0, 20.0, 3.0, math.radians(23.0), pattern=True)
WORLD = World(
    name="pad",
    origin=GeodeticOrigin(55.7, 13.47, 95.0),
    terrain=Terrain.flat(-100.0, -100.0, 100.0, 100.0),
    pads=(PAD, LandingPad("H9", 40.0, 20.0, 3.0, 0.0)),
)
PLACEMENT = PadPlacement.of_world(WORLD)


def pad_in_camera(
    camera: CameraPose, placement: PadPlacement
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The exact pad pose in the optical frame: rotation pad -> camera, pad origin in camera."""
    rotation = camera.rotation.T @ placement.axes
    translation = camera.rotation.T @ (placement.origin - camera.position)
    return rotation, translation


def turn(a: float, b: float) -> float:
    """``a - b`` wrapped to [-pi, pi)."""
    return (a - b + math.pi) % math.tau - math.pi


def aimed(position: tuple[float, float, float], roll: float, pitch: float, heading: float) -> Any:
    """The navigation pose and PTU angles that look at the pad's centre from ``position``."""
    nav = NavPose(position, roll, pitch, heading)
    pan, tilt = look_at_angles(Pose(position, roll, pitch, heading), tuple(PLACEMENT.origin))
    return nav, pan, tilt


@pytest.mark.parametrize(
    ("position", "roll", "pitch", "heading"),
    [
        ((10.5, 20.3, 12.0), 0.0, 0.0, 0.0),  # hovering over the pad, looking down
        ((25.0, 8.0, 15.0), 0.05, -0.08, 1.2),
        ((-3.0, 30.0, 6.0), -0.1, 0.04, 3.5),
        ((12.0, 40.0, 19.0), 0.02, 0.1, 6.2),  # heading just short of north
    ],
)
def test_exact_poses_give_back_the_helicopter(
    position: tuple[float, float, float], roll: float, pitch: float, heading: float
) -> None:
    nav, pan, tilt = aimed(position, roll, pitch, heading)
    rotation, translation = pad_in_camera(CameraPose.of(nav, pan, tilt), PLACEMENT)
    fix = helicopter_fix(3.0, rotation, translation, (pan, tilt), PLACEMENT)
    assert fix.status is FixStatus.OK
    assert np.allclose(fix.position, position, atol=1e-9)
    assert (fix.roll, fix.pitch) == pytest.approx((roll, pitch), abs=1e-9)
    assert abs(turn(fix.heading, heading)) < 1e-9 and 0.0 <= fix.heading < math.tau
    assert fix.range_m == pytest.approx(float(np.linalg.norm(translation)))
    assert fix.sigma == pytest.approx(fix_sigma(fix.range_m))


def test_a_wrong_pan_turns_the_heading_and_swings_the_mount() -> None:
    nav, pan, tilt = aimed((10.5, 20.3, 12.0), 0.0, 0.0, 0.0)
    rotation, translation = pad_in_camera(CameraPose.of(nav, pan, tilt), PLACEMENT)
    fix = helicopter_fix(0.0, rotation, translation, (pan + 0.1, tilt), PLACEMENT)
    assert turn(fix.heading, -0.1) == pytest.approx(0.0, abs=1e-9)
    # the camera stays where it is; only the CG moves around it by the 0.54 m mount offset
    assert 0.0 < math.dist(fix.position, nav.position) < 0.1


@pytest.mark.parametrize(
    ("rotation", "translation", "ptu", "status"),
    [
        (np.eye(3), np.array([0.0, 0.0, 5.0]), None, FixStatus.NO_PTU),
        (np.eye(3), np.array([0.0, math.nan, 5.0]), (0.0, 1.5), FixStatus.BAD_POSE),
        (np.eye(3), np.array([0.0, 0.0, 5.0]), (math.inf, 1.5), FixStatus.BAD_POSE),
        (2.0 * np.eye(3), np.array([0.0, 0.0, 5.0]), (0.0, 1.5), FixStatus.BAD_POSE),
        (np.eye(3), np.zeros(3), (0.0, 1.5), FixStatus.BAD_POSE),
    ],
)
def test_refusals(
    rotation: NDArray[np.float64],
    translation: NDArray[np.float64],
    ptu: tuple[float, float] | None,
    status: FixStatus,
) -> None:
    fix = helicopter_fix(1.0, rotation, translation, ptu, PLACEMENT)
    assert fix.status is status and fix.reason and math.isnan(fix.position[0])


@pytest.mark.parametrize(
    ("world", "name", "found"),
    [
        (WORLD, "", "L9"),
        (WORLD, "L9", "L9"),
        (WORLD, "H9", None),  # a pad without the pattern
        (WORLD, "nope", None),
        (World("bare", WORLD.origin, WORLD.terrain), "", None),
    ],
)
def test_the_pad_comes_from_the_world(world: World, name: str, found: str | None) -> None:
    if found is None:
        with pytest.raises(ConfigError, match="no patterned pad"):
            PadPlacement.of_world(world, name)
        return
    placement = PadPlacement.of_world(world, name)
    assert placement.name == found
    assert np.allclose(placement.origin, (PAD.east, PAD.north, PRINT_HEIGHT_M))


def test_revinge_s_vision_pad() -> None:
    world = load_world("revinge")
    placement = PadPlacement.of_world(world)
    assert placement.name == "L1"
    assert placement.origin[:2] == pytest.approx((-215.0, -162.0))
    # pad x axis is east turned 30 deg clockwise
    assert placement.axes[:, 0] == pytest.approx((math.cos(math.radians(30)), -0.5, 0.0))


@pytest.fixture(scope="module")
def renderer() -> Iterator[Any]:
    """The simulator's renderer on the flat world with the patterned pad."""
    from sim.render.renderer import Renderer

    r = Renderer(WORLD)
    yield r
    r.release()


@pytest.mark.parametrize(
    ("position", "roll", "pitch", "heading"),
    [
        ((10.8, 19.7, 5.0), 0.02, -0.03, 0.4),
        ((14.0, 24.0, 10.0), -0.04, 0.05, 2.0),
        ((6.0, 14.0, 12.5), 0.0, 0.0, 4.0),
        ((17.0, 28.0, 15.0), 0.06, 0.02, 5.5),
    ],
)
def test_fixes_on_the_simulators_renderer(
    renderer: Any,
    position: tuple[float, float, float],
    roll: float,
    pitch: float,
    heading: float,
) -> None:
    from sim.sensors.camera import COLOR_CAMERA
    from sim.sensors.camera_model import Intrinsics as SimIntrinsics
    from sim.sensors.camera_model import camera_pose
    from sim.truth_state import TruthState

    _, pan, tilt = aimed(position, roll, pitch, heading)
    truth = TruthState(0.0, position, (0.0, 0.0, 0.0), roll, pitch, heading, (0.0, 0.0, 0.0),
                       (0.0, 0.0, -9.81), 1500.0, True, False, position[2], 80.0)  # fmt: skip
    k = COLOR_K
    sim_k = SimIntrinsics(k.width, k.height, k.fx, k.fy, k.cx, k.cy)
    rgb = renderer.render_color(camera_pose(truth, pan, tilt, COLOR_CAMERA.mount_offset), sim_k)
    pose = estimate(cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2GRAY), k)
    assert pose.status is PoseStatus.OK, pose.reason
    assert pose.rotation is not None and pose.translation is not None
    fix = helicopter_fix(0.0, pose.rotation, pose.translation, (pan, tilt), PLACEMENT)
    assert fix.status is FixStatus.OK
    error = math.dist(fix.position, position)
    assert error <= 3.0 * fix.sigma, (error, fix.sigma, fix.range_m)
    assert abs(turn(fix.heading, heading)) < math.radians(1.0)
    assert abs(fix.roll - roll) < math.radians(1.5) and abs(fix.pitch - pitch) < math.radians(1.5)
