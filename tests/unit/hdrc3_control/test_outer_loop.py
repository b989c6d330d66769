"""The shared translational loop: acceleration -> attitude and the sign of each axis."""

from __future__ import annotations

import math

import pytest

from hdrc3_control.commands import EstimatedState
from hdrc3_control.outer_loop import OuterLoop, Reference, accel_to_attitude

MAX = math.radians(22.0)


@pytest.mark.parametrize(
    ("accel", "heading", "roll_sign", "pitch_sign"),
    [
        ((0.0, 1.0), 0.0, 0, -1),  # north, facing north: nose down
        ((1.0, 0.0), 0.0, 1, 0),  # east, facing north: roll right
        ((1.0, 0.0), math.pi / 2, 0, -1),  # east, facing east: nose down
        ((0.0, 1.0), math.pi / 2, -1, 0),  # north, facing east: roll left
        ((0.0, -1.0), 0.0, 0, 1),  # south, facing north: nose up
    ],
)
def test_accel_to_attitude_signs(
    accel: tuple[float, float], heading: float, roll_sign: int, pitch_sign: int
) -> None:
    roll, pitch = accel_to_attitude(accel[0], accel[1], heading, MAX)
    assert (round(roll, 9) > 0) - (round(roll, 9) < 0) == roll_sign
    assert (round(pitch, 9) > 0) - (round(pitch, 9) < 0) == pitch_sign
    assert math.hypot(roll, pitch) == pytest.approx(math.atan(1.0 / 9.80665))


def test_tilt_is_limited() -> None:
    roll, pitch = accel_to_attitude(30.0, -30.0, 0.3, MAX)
    assert abs(roll) == pytest.approx(MAX) and abs(pitch) == pytest.approx(MAX)


def test_loop_drives_towards_the_reference_and_integrates_only_in_the_air() -> None:
    state = EstimatedState(0.0, (0.0, 0.0, 10.0), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0)
    loop = OuterLoop()
    cmd = loop.update(state, Reference(position=(0.0, 5.0, 12.0), heading=0.2), 0.02)
    assert cmd.pitch < 0.0 and cmd.vertical > 0.0 and cmd.yaw_rate > 0.0
    assert loop.integral[1] > 0.0
    ground = EstimatedState(0.0, (0.0, 0.0, 0.45), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0, on_ground=True)
    loop.reset()
    loop.update(ground, Reference(position=(0.0, 5.0, 0.45), heading=0.0), 0.02)
    assert loop.integral == (0.0, 0.0)
