import pytest
from hypothesis import given
from hypothesis import strategies as st

from hdrc3_dyknow.policy import MissingHandling
from hdrc3_dyknow.sample import Sample, StreamError
from hdrc3_dyknow.state_sync import StateSynchronizer

Event = tuple[str, int, int, float]  # key, valid, available, value


def run(
    sync: StateSynchronizer, events: list[Event | int]
) -> list[tuple[int, int, dict[str, object]]]:
    """Feed samples; an int in the event list advances the clock to that time."""
    out = []
    for event in events:
        if isinstance(event, int):
            out += [(s.time, s.available_time, dict(s.values)) for s in sync.advance(event)]
        else:
            key, valid, available, value = event
            sync.update(key, Sample(valid, available, value))
    return out


@pytest.mark.parametrize(
    ("missing", "events", "expected"),
    [
        # Both streams reached t=0 and t=100: states are complete, emitted before any deadline.
        (
            MissingHandling.LAST_VALUE,
            [
                ("a", 0, 0, 1.0),
                ("b", 0, 5, 10.0),
                5,
                ("a", 100, 101, 2.0),
                ("b", 100, 102, 20.0),
                102,
            ],
            [(0, 5, {"a": 1.0, "b": 10.0}), (100, 102, {"a": 2.0, "b": 20.0})],
        ),
        # b is slow (every 200 ms): state at 100 waits for it until 100 + max_delay (150) = 250.
        (
            MissingHandling.LAST_VALUE,
            [
                ("a", 0, 0, 1.0),
                ("b", 0, 0, 10.0),
                0,
                ("a", 100, 100, 2.0),
                ("a", 200, 200, 3.0),
                249,
                250,
                ("b", 200, 260, 30.0),
                260,
            ],
            [
                (0, 0, {"a": 1.0, "b": 10.0}),
                (100, 250, {"a": 2.0, "b": 10.0}),
                (200, 260, {"a": 3.0, "b": 30.0}),
            ],
        ),
        # Extrapolation of a delayed stream.
        (
            MissingHandling.EXTRAPOLATE,
            [
                ("a", 0, 0, 0.0),
                ("b", 0, 0, 0.0),
                ("a", 100, 100, 1.0),
                ("b", 100, 100, 10.0),
                ("a", 200, 200, 2.0),
                350,
            ],
            [
                (0, 350, {"a": 0.0, "b": 0.0}),
                (100, 350, {"a": 1.0, "b": 10.0}),
                (200, 350, {"a": 2.0, "b": 20.0}),
            ],
        ),
        # Drop: no sample within the period means no state (counted as incomplete).
        (
            MissingHandling.DROP,
            [
                ("a", 0, 0, 0.0),
                ("b", 0, 0, 0.0),
                ("a", 100, 100, 1.0),
                ("a", 200, 200, 2.0),
                ("b", 200, 200, 5.0),
                400,
            ],
            [(0, 400, {"a": 0.0, "b": 0.0}), (200, 400, {"a": 2.0, "b": 5.0})],
        ),
        # A sample within the period before the grid time is used (sample-and-hold).
        (
            MissingHandling.DROP,
            [("a", 3, 3, 1.0), ("b", 95, 95, 2.0), ("a", 130, 130, 3.0), ("b", 120, 120, 4.0), 130],
            [(100, 130, {"a": 1.0, "b": 2.0})],
        ),
    ],
)
def test_state_generation(
    missing: MissingHandling, events: list[Event | int], expected: list
) -> None:
    sync = StateSynchronizer(["a", "b"], period_ms=100, max_delay_ms=150, missing=missing)
    assert run(sync, events) == expected


def test_incomplete_until_every_stream_has_a_value() -> None:
    sync = StateSynchronizer(["a", "b"], period_ms=10, max_delay_ms=0)
    out = run(sync, [("a", 0, 0, 1.0), 20, ("b", 25, 25, 2.0), 30])
    assert [t for t, _, _ in out] == [30]
    assert sync.stats.incomplete == 3


def test_out_of_order_and_late_samples_are_counted() -> None:
    sync = StateSynchronizer(["a"], period_ms=10, max_delay_ms=0)
    run(sync, [("a", 0, 0, 1.0), ("a", 50, 50, 2.0), ("a", 40, 41, 9.0), ("a", 50, 51, 9.0), 50])
    assert sync.stats.out_of_order == 2
    sync.update("a", Sample(55, 56, 3.0))
    assert sync.stats.late == 0
    sync2 = StateSynchronizer(["a", "b"], period_ms=10, max_delay_ms=0)
    run(sync2, [("a", 0, 0, 1.0), ("b", 0, 0, 1.0), 100, ("b", 30, 101, 2.0)])
    assert sync2.stats.late == 1


def test_max_age_marks_stale_values_missing() -> None:
    sync = StateSynchronizer(["a"], period_ms=10, max_delay_ms=0, max_age_ms=15)
    out = run(sync, [("a", 0, 0, 1.0), 40])
    assert [t for t, _, _ in out] == [0, 10]


def test_per_key_missing_handling_and_reset() -> None:
    sync = StateSynchronizer(
        ["a", "b"],
        10,
        0,
        missing={"a": MissingHandling.EXTRAPOLATE, "b": MissingHandling.LAST_VALUE},
    )
    out = run(
        sync, [("a", 0, 0, 0.0), ("a", 10, 10, 1.0), ("b", 0, 0, 5.0), ("b", 10, 10, 6.0), 30]
    )
    assert out[-1] == (30, 30, {"a": 3.0, "b": 6.0})
    sync.reset()
    assert sync.next_time is None and sync.stats.states == 0


def test_clock_jump_is_bounded() -> None:
    sync = StateSynchronizer(["a"], period_ms=1, max_delay_ms=0)
    sync.update("a", Sample(0, 0, 1.0))
    assert len(sync.advance(10**9)) <= 1001
    assert sync.stats.skipped > 0


@pytest.mark.parametrize(
    ("keys", "period", "delay"), [([], 10, 0), (["a", "a"], 10, 0), (["a"], 0, 0), (["a"], 10, -1)]
)
def test_bad_synchroniser(keys: list[str], period: int, delay: int) -> None:
    with pytest.raises(StreamError):
        StateSynchronizer(keys, period, delay)


def test_unknown_key() -> None:
    with pytest.raises(StreamError, match="unknown state key"):
        StateSynchronizer(["a"], 10, 0).update("zz", Sample(0, 0, 1.0))


@given(
    st.lists(
        st.tuples(st.sampled_from(["a", "b", "c"]), st.integers(0, 2000), st.integers(0, 300)),
        min_size=1,
        max_size=80,
    ),
    st.integers(1, 200),
    st.integers(0, 300),
)
def test_states_are_on_the_grid_in_order_and_use_real_samples(
    samples: list[tuple[str, int, int]], period: int, delay: int
) -> None:
    sync = StateSynchronizer(["a", "b", "c"], period, delay)
    arrivals = sorted((valid + lag, key, valid) for key, valid, lag in samples)
    states = []
    for available, key, valid in arrivals:
        states += sync.advance(available)
        sync.update(key, Sample(valid, available, float(valid)))
    states += sync.advance(10_000)
    times = [s.time for s in states]
    assert times == sorted(set(times))
    assert all(t % period == 0 for t in times)
    for state in states:
        for key, value in state.values.items():
            assert value in {float(v) for k, v, _ in samples if k == key}
            assert value <= state.time  # never a value from the future
