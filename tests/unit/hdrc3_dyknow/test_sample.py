import math

import pytest

from hdrc3_dyknow.sample import FeatureTerm, Sample, StreamError, check_value, is_number, ms_from_ns


@pytest.mark.parametrize(
    ("value", "expected"),
    [(1, True), (2.5, True), (True, False), ("x", False), (math.nan, False), ((1.0,), False)],
)
def test_is_number(value: object, expected: bool) -> None:
    assert is_number(value) is expected  # type: ignore[arg-type]


@pytest.mark.parametrize("value", [math.nan, math.inf, (1.0, (2.0, -math.inf))])
def test_check_value_rejects_non_finite(value: object) -> None:
    with pytest.raises(StreamError, match="non-finite"):
        check_value(value)  # type: ignore[arg-type]


def test_check_value_returns_finite_value() -> None:
    assert check_value((1.0, ("a", True))) == (1.0, ("a", True))


def test_delay_and_time_conversion() -> None:
    assert Sample(100, 130, 1.0).delay == 30
    assert ms_from_ns(1_999_999) == 1
    assert str(FeatureTerm("XYDist", ("uav1", "av1"))) == "XYDist[uav1, av1]"
