import math

import numpy as np
import pytest

from sim.odometry import enu_to_flu, flu_odometry, flu_quaternion
from sim.sensors.fake_truth import make_truth
from sim.sensors.frames import body_to_enu

FRD_TO_FLU = np.diag([1.0, -1.0, -1.0])


def _matrix(q: tuple[float, float, float, float]) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


ANGLES = [(0.0, 0.0, 0.0), (0.1, -0.2, 1.0), (-0.4, 0.3, 4.0), (0.0, 0.0, math.pi / 2)]


@pytest.mark.parametrize(("roll", "pitch", "heading"), ANGLES)
def test_quaternion_is_the_flu_body_attitude_in_enu(
    roll: float, pitch: float, heading: float
) -> None:
    flu_to_enu = body_to_enu(roll, pitch, heading) @ FRD_TO_FLU
    assert _matrix(flu_quaternion(roll, pitch, heading)) == pytest.approx(flu_to_enu, abs=1e-12)


@pytest.mark.parametrize(("roll", "pitch", "heading"), ANGLES)
def test_enu_to_flu_inverts_the_attitude(roll: float, pitch: float, heading: float) -> None:
    v = (1.0, -2.0, 0.5)
    flu_to_enu = body_to_enu(roll, pitch, heading) @ FRD_TO_FLU
    assert np.array(enu_to_flu(v, roll, pitch, heading)) == pytest.approx(flu_to_enu.T @ v)


def test_heading_north_means_yaw_90_degrees_and_forward_is_north() -> None:
    odo = flu_odometry(make_truth(velocity_enu=(0.0, 3.0, 0.0), body_rates=(0.1, 0.2, 0.3)))
    s = math.sqrt(0.5)
    assert odo.orientation == pytest.approx((0.0, 0.0, s, s))
    assert odo.linear == pytest.approx((3.0, 0.0, 0.0))
    assert odo.angular == (0.1, -0.2, -0.3)
