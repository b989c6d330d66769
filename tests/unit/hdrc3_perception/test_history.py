"""NavHistory (nearest state) and PtuHistory (interpolated read-out) at an image's time."""

from __future__ import annotations

import math

import pytest

from hdrc3_perception.camera import NavPose
from hdrc3_perception.history import NavHistory, PtuHistory


def test_nav_history_gives_the_nearest_state_within_the_gap() -> None:
    history = NavHistory(size=3, max_gap=0.1)
    poses = [NavPose((float(i), 0.0, 30.0), 0.0, 0.0, 0.0) for i in range(5)]
    for i, pose in enumerate(poses):
        history.add(0.04 * i, pose)
    history.add(math.nan, poses[0])
    assert history.at(0.13) is poses[3]
    assert history.at(0.17) is poses[4]
    assert history.at(0.3) is None  # 0.14 s after the last
    assert history.at(0.0) is poses[2]  # 0.0 itself is forgotten (size 3)
    assert history.at(-0.03) is None
    assert history.at(math.nan) is None


@pytest.mark.parametrize(
    ("samples", "time", "expected"),
    [
        ([(0.0, 0.1, 1.0), (0.04, 0.3, 1.2)], 0.02, (0.2, 1.1)),  # interpolated
        ([(0.0, 0.1, 1.0), (0.04, 0.3, 1.2)], 0.04, (0.3, 1.2)),
        ([(0.0, 0.1, 1.0)], 0.05, (0.1, 1.0)),  # the nearest within the gap
        ([(0.0, 0.1, 1.0)], 0.5, None),  # too old
        ([], 0.0, None),
        ([(0.0, 0.1, 1.0), (0.0, 0.9, 0.9), (math.nan, 0.0, 0.0)], 0.0, (0.1, 1.0)),
    ],
)
def test_ptu_history(
    samples: list[tuple[float, float, float]],
    time: float,
    expected: tuple[float, float] | None,
) -> None:
    history = PtuHistory()
    for sample in samples:
        history.add(*sample)
    got = history.at(time)
    assert got == (None if expected is None else pytest.approx(expected))
