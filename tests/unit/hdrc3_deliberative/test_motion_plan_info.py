from __future__ import annotations

import pytest

from hdrc3_deliberative.motion_plan_info import StraightLineMotionPlanInfo


@pytest.mark.parametrize(
    ("start", "goal", "duration", "cost", "feasible"),
    [
        ((0, 0, 0), (30, 40, 0), 5.0 + 5.0, 50.0, True),
        ((0, 0, 0), (0, 0, 0), 5.0, 0.0, True),
        ((0, 0, 0), (300, 400, 0), 55.0, 500.0, False),
    ],
)
def test_straight_line(
    start: tuple[float, float, float],
    goal: tuple[float, float, float],
    duration: float,
    cost: float,
    feasible: bool,
) -> None:
    info = StraightLineMotionPlanInfo(speed=10.0, overhead=5.0, max_range=100.0).query(
        "h", start, goal
    )
    assert info.duration == pytest.approx(duration)
    assert info.cost == pytest.approx(cost)
    assert info.feasible is feasible
