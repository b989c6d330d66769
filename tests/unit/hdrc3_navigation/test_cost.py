from __future__ import annotations

import numpy as np
import pytest

from hdrc3_navigation.cost import Criterion, FlightModel

MODEL = FlightModel()


@pytest.mark.parametrize(
    ("a", "b", "speed", "seconds"),
    [
        ((0, 0, 0), (100, 0, 0), 10.0, 10.0),
        ((0, 0, 0), (0, 0, 30), 10.0, 10.0),  # vertical: 30 m at 3 m/s
        ((0, 0, 30), (0, 0, 0), 10.0, 15.0),  # 30 m down at 2 m/s
        ((0, 0, 0), (100, 0, 6), 10.0, np.hypot(100, 6) / 10.0),
    ],
)
def test_piece_time(a, b, speed: float, seconds: float) -> None:  # type: ignore[no-untyped-def]
    assert float(MODEL.piece_time(np.array(a, float), np.array(b, float), speed)) == pytest.approx(
        seconds
    )


@pytest.mark.parametrize("criterion", list(Criterion))
def test_heuristic_is_a_lower_bound_and_costs_vectorise(criterion: Criterion) -> None:
    rng = np.random.default_rng(1)
    pts = rng.uniform(-100, 100, (50, 3))
    goal = np.array([10.0, 20.0, 30.0])
    for p in pts:
        path = np.array([p, (p + goal) / 2 + rng.normal(0, 10, 3), goal])
        assert (
            MODEL.heuristic(criterion, p, goal, 8.0)
            <= MODEL.polyline_cost(criterion, path, 8.0) + 1e-9
        )
    vec = MODEL.cost(criterion, pts[:-1], pts[1:], 8.0)
    one = [float(MODEL.cost(criterion, pts[i], pts[i + 1], 8.0)) for i in range(len(pts) - 1)]
    assert np.allclose(vec, one)


def test_climbing_costs_energy_descending_does_not_pay_it_back() -> None:
    a, b = np.array([0.0, 0, 0]), np.array([100.0, 0, 20])
    assert MODEL.cost(Criterion.ENERGY, a, b, 10.0) > MODEL.cost(Criterion.ENERGY, b, a, 10.0)
