import math

import pytest

from sim.truth_state import TruthState
from sim.velocity_hold import VelocityHold


def state(heading: float, velocity: tuple[float, float, float]) -> TruthState:
    return TruthState(
        time=0.0,
        position_enu=(0.0, 0.0, 10.0),
        velocity_enu=velocity,
        roll=0.0,
        pitch=0.0,
        heading=heading,
        body_rates=(0.0, 0.0, 0.0),
        specific_force_body=(0.0, 0.0, -9.81),
        rotor_rpm=850.0,
        engine_running=True,
        on_ground=False,
        height_above_ground=9.5,
        mass=80.0,
    )


@pytest.mark.parametrize(
    ("heading", "want_en", "pitch_sign", "roll_sign"),
    [
        (0.0, (0.0, 5.0), -1, 0),  # faces north, wants north: nose down
        (0.0, (5.0, 0.0), 0, 1),  # faces north, wants east: roll right
        (math.pi / 2, (0.0, 5.0), 0, -1),  # faces east, wants north: roll left
        (math.pi, (0.0, 5.0), 1, 0),  # faces south, wants north: nose up
    ],
)
def test_tilts_towards_the_wanted_velocity(
    heading: float, want_en: tuple[float, float], pitch_sign: int, roll_sign: int
) -> None:
    cmd = VelocityHold().update(state(heading, (0.0, 0.0, 0.0)), 0.02, want_en, 0.5, heading)
    for value, sign in ((cmd.pitch, pitch_sign), (cmd.roll, roll_sign)):
        if sign == 0:
            assert abs(value) < 1e-9
        else:
            assert math.copysign(1.0, value) == sign
    assert cmd.vertical == 0.5
    assert cmd.yaw_rate == pytest.approx(0.0, abs=1e-12)


def test_turns_the_short_way_to_the_heading() -> None:
    cmd = VelocityHold().update(state(0.1, (0.0, 0.0, 0.0)), 0.02, (0.0, 0.0), 0.0, 6.2)
    assert cmd.yaw_rate < 0.0
