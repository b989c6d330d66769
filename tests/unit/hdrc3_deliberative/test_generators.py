from __future__ import annotations

import pytest

from hdrc3_deliberative.generators import LogisticsSize, UavSize, logistics_problem, uav_problem


def test_logistics_generator_is_deterministic_and_sized() -> None:
    size = LogisticsSize(42, 14, 4)
    text = logistics_problem(size, 7)
    assert text == logistics_problem(size, 7) != logistics_problem(size, 8)
    assert text.count("(at obj") == 2 * 42  # initial + goal
    assert "apt14 - airport" not in text or "apt14" in text
    assert text.count("(in-city") == 14 * 2


def test_uav_generator() -> None:
    text = uav_problem(UavSize(3, 4, 8, 2), 1)
    assert text.count("goal at(") == 8
    assert "object carrier1, carrier2: carrier" in text
    assert text == uav_problem(UavSize(3, 4, 8, 2), 1)


def test_generator_rejects_empty_sizes() -> None:
    with pytest.raises(ValueError, match="positive"):
        logistics_problem(LogisticsSize(0, 1, 1), 1)
