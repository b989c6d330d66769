import pytest

from hdrc3_dyknow.policy import (
    LateHandling,
    MissingHandling,
    Policy,
    PolicyFilter,
    estimate,
)
from hdrc3_dyknow.sample import Sample, StreamError


def run(
    policy: Policy, samples: list[tuple[int, int, object]]
) -> tuple[list[tuple[int, object]], PolicyFilter]:
    flt = PolicyFilter(policy)
    out = []
    for valid, available, value in samples:
        out += [(s.valid_time, s.value) for s in flt.update(Sample(valid, available, value))]  # type: ignore[arg-type]
    return out, flt


@pytest.mark.parametrize(
    ("policy", "samples", "expected", "counts"),
    [
        # ordered: older samples dropped and counted; duplicates dropped and counted
        (
            Policy(),
            [(0, 0, 1), (20, 20, 2), (10, 25, 3), (20, 26, 4), (30, 30, 5)],
            [(0, 1), (20, 2), (30, 5)],
            {"out_of_order": 1, "duplicates": 1},
        ),
        # unordered: out-of-order samples pass (but are still counted)
        (
            Policy(ordered=False),
            [(0, 0, 1), (20, 20, 2), (10, 25, 3)],
            [(0, 1), (20, 2), (10, 3)],
            {"out_of_order": 1},
        ),
        # change-only with threshold
        (
            Policy(change_only=True, change_threshold=0.5),
            [(0, 0, 1.0), (10, 10, 1.2), (20, 20, 1.6), (30, 30, 1.7)],
            [(0, 1.0), (20, 1.6)],
            {"unchanged": 2},
        ),
        # change-only over tuples and strings
        (
            Policy(change_only=True),
            [(0, 0, (1, 2)), (10, 10, (1, 2)), (20, 20, "a"), (30, 30, "a")],
            [(0, (1, 2)), (20, "a")],
            {"unchanged": 2},
        ),
        # max delay, late samples dropped
        (
            Policy(max_delay_ms=50),
            [(0, 10, 1), (10, 100, 2), (20, 60, 3)],
            [(0, 1), (20, 3)],
            {"late": 1},
        ),
        # max delay, late samples kept
        (
            Policy(max_delay_ms=50, late=LateHandling.KEEP),
            [(0, 10, 1), (10, 100, 2)],
            [(0, 1), (10, 2)],
            {"late": 1},
        ),
        # resampling with last value: a gap is filled with the held value
        (
            Policy(sample_period_ms=10),
            [(0, 0, 1.0), (10, 10, 2.0), (35, 35, 5.0), (40, 40, 6.0)],
            [(0, 1.0), (10, 2.0), (20, 2.0), (30, 2.0), (40, 6.0)],
            {"filled": 2},
        ),
        # resampling with extrapolation
        (
            Policy(sample_period_ms=10, missing=MissingHandling.EXTRAPOLATE),
            [(0, 0, 1.0), (10, 10, 2.0), (35, 35, 5.0)],
            [(0, 1.0), (10, 2.0), (20, 3.0), (30, 4.0)],
            {"filled": 2},
        ),
        # resampling with drop: no value invented
        (
            Policy(sample_period_ms=10, missing=MissingHandling.DROP),
            [(0, 0, 1.0), (10, 10, 2.0), (35, 35, 5.0), (40, 40, 6.0)],
            [(0, 1.0), (10, 2.0), (40, 6.0)],
            {"filled": 0},
        ),
        # resampling: sample within the period is used at the next grid point
        (
            Policy(sample_period_ms=10),
            [(3, 3, 1.0), (7, 7, 2.0), (12, 12, 3.0), (21, 21, 4.0)],
            [(10, 2.0), (20, 3.0)],
            {},
        ),
    ],
)
def test_policy_filter(
    policy: Policy, samples: list, expected: list, counts: dict[str, int]
) -> None:
    out, flt = run(policy, samples)
    assert out == expected
    for name, value in counts.items():
        assert getattr(flt.stats, name) == value, name
    assert flt.stats.samples_in == len(samples)


def test_advance_emits_grid_points_after_max_delay() -> None:
    flt = PolicyFilter(Policy(sample_period_ms=10, max_delay_ms=5))
    assert [s.valid_time for s in flt.update(Sample(0, 0, 1.0))] == [0]
    assert flt.advance(14) == []
    assert [(s.valid_time, s.value, s.available_time) for s in flt.advance(15)] == [(10, 1.0, 15)]


def test_huge_gap_is_bounded() -> None:
    flt = PolicyFilter(Policy(sample_period_ms=1))
    flt.update(Sample(0, 0, 1.0))
    assert len(flt.update(Sample(10**9, 10**9, 2.0))) <= 1001


def test_reset_forgets_everything() -> None:
    flt = PolicyFilter(Policy())
    flt.update(Sample(10, 10, 1))
    flt.reset()
    assert flt.stats.samples_in == 0
    assert [s.valid_time for s in flt.update(Sample(5, 5, 1))] == [5]


@pytest.mark.parametrize(
    "kwargs",
    [{"sample_period_ms": -1}, {"max_delay_ms": -5}, {"change_threshold": float("nan")}],
)
def test_invalid_policy(kwargs: dict[str, float]) -> None:
    with pytest.raises(StreamError):
        Policy(**kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("previous", "latest", "time", "missing", "expected"),
    [
        (Sample(0, 0, 0.0), Sample(10, 10, 1.0), 20, MissingHandling.EXTRAPOLATE, 2.0),
        (
            Sample(0, 0, (0.0, 10.0)),
            Sample(10, 10, (1.0, 10.0)),
            30,
            MissingHandling.EXTRAPOLATE,
            (3.0, 10.0),
        ),
        (Sample(0, 0, "a"), Sample(10, 10, "b"), 20, MissingHandling.EXTRAPOLATE, "b"),
        (None, Sample(10, 10, 1.0), 20, MissingHandling.EXTRAPOLATE, 1.0),
        (Sample(0, 0, 0.0), Sample(10, 10, 1.0), 20, MissingHandling.LAST_VALUE, 1.0),
        (Sample(0, 0, 0.0), Sample(10, 10, 1.0), 20, MissingHandling.DROP, None),
        (Sample(0, 0, 0.0), Sample(10, 10, 1.0), 10, MissingHandling.DROP, 1.0),
    ],
)
def test_estimate(
    previous: Sample | None, latest: Sample, time: int, missing: MissingHandling, expected: object
) -> None:
    assert estimate(previous, latest, time, missing) == expected
