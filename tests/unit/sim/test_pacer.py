import math

import pytest

from hdrc3_base.errors import ConfigError
from sim.pacer import Pacer


@pytest.mark.parametrize(
    ("speed", "sim_time", "now", "wait"),
    [
        (1.0, 0.5, 100.2, 0.3),
        (2.0, 1.0, 100.0, 0.5),
        (10.0, 1.0, 100.15, 0.0),
        (0.0, 50.0, 100.0, 0.0),
    ],
)
def test_wait_time_follows_the_factor(
    speed: float, sim_time: float, now: float, wait: float
) -> None:
    pacer = Pacer(speed)
    assert pacer.wait_time(0.0, 100.0) == 0.0  # anchors sim 0 at wall 100
    assert pacer.wait_time(sim_time, now) == pytest.approx(wait)


def test_falling_far_behind_re_anchors_instead_of_racing() -> None:
    pacer = Pacer(1.0)
    pacer.wait_time(0.0, 0.0)
    assert pacer.wait_time(1.0, 5.0) == 0.0  # 4 s late: new anchor (sim 1 at wall 5)
    assert pacer.wait_time(1.5, 5.0) == pytest.approx(0.5)


def test_restart_moves_the_anchor() -> None:
    pacer = Pacer(1.0)
    pacer.wait_time(0.0, 0.0)
    pacer.restart()
    assert pacer.wait_time(10.0, 50.0) == 0.0
    assert pacer.wait_time(10.5, 50.0) == pytest.approx(0.5)


@pytest.mark.parametrize("speed", [-1.0, math.nan, math.inf])
def test_bad_speed_is_misuse(speed: float) -> None:
    with pytest.raises(ConfigError, match="speed"):
        Pacer(speed)
