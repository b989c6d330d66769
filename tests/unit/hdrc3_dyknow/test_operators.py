import pytest

from hdrc3_dyknow.operators import (
    Aggregate,
    AggregateOp,
    Chain,
    FilterOp,
    MapOp,
    MergeOp,
    SampleOp,
    StreamOperator,
    WindowOp,
    aggregate,
)
from hdrc3_dyknow.policy import MissingHandling
from hdrc3_dyknow.sample import Sample, StreamError


def feed(op: StreamOperator, samples: list[tuple[int, object]]) -> list[tuple[int, object]]:
    out = []
    for t, v in samples:
        out += [(s.valid_time, s.value) for s in op.update(Sample(t, t, v))]  # type: ignore[arg-type]
    return out


def close(a: object, b: object) -> bool:
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b, strict=True))
    return bool(a == pytest.approx(b))


SERIES = [(0, 1.0), (10, 3.0), (20, -2.0), (30, 4.0)]


@pytest.mark.parametrize(
    ("op", "expected"),
    [
        (MapOp(lambda v: v * 2), [(0, 2.0), (10, 6.0), (20, -4.0), (30, 8.0)]),  # type: ignore[operator]
        (FilterOp(lambda v: v > 0), [(0, 1.0), (10, 3.0), (30, 4.0)]),  # type: ignore[operator]
        (WindowOp(20), [(0, (1.0,)), (10, (1.0, 3.0)), (20, (3.0, -2.0)), (30, (-2.0, 4.0))]),
        (AggregateOp(Aggregate.MAX, 20), [(0, 1.0), (10, 3.0), (20, 3.0), (30, 4.0)]),
        (AggregateOp(Aggregate.MEAN, 30), [(0, 1.0), (10, 2.0), (20, 2 / 3), (30, 5 / 3)]),
        (AggregateOp(Aggregate.COUNT, 15), [(0, 1), (10, 2), (20, 2), (30, 2)]),
        (SampleOp(20), [(0, 1.0), (20, -2.0)]),
        (Chain([MapOp(lambda v: v + 1), FilterOp(lambda v: v > 2)]), [(10, 4.0), (30, 5.0)]),  # type: ignore[operator]
    ],
)
def test_single_input_operators(op: StreamOperator, expected: list[tuple[int, object]]) -> None:
    for _ in range(2):  # the second round checks reset()
        got = feed(op, SERIES)
        assert [t for t, _ in got] == [t for t, _ in expected]
        assert all(close(v, w) for (_, v), (_, w) in zip(got, expected, strict=True))
        op.reset()


def test_sample_op_advance_fills_after_delay() -> None:
    op = SampleOp(10, MissingHandling.LAST_VALUE, max_delay_ms=5)
    op.update(Sample(0, 0, 7.0))
    assert op.advance(24) == [Sample(10, 24, 7.0)]
    assert [s.valid_time for s in op.advance(25)] == [20]


def test_chain_advance_pushes_through_later_operators() -> None:
    chain = Chain([SampleOp(10), MapOp(lambda v: v * 10)])  # type: ignore[operator]
    chain.update(Sample(0, 0, 1.0))
    assert [(s.valid_time, s.value) for s in chain.advance(20)] == [(10, 10.0), (20, 10.0)]


def test_merge_orders_by_valid_time_using_watermark() -> None:
    merge = MergeOp(2, max_delay_ms=100)
    assert merge.update_input(0, Sample(10, 10, "a10")) == []
    assert merge.update_input(0, Sample(30, 30, "a30")) == []
    assert [s.value for s in merge.update_input(1, Sample(20, 21, "b20"))] == ["a10", "b20"]
    assert [s.value for s in merge.update_input(1, Sample(40, 41, "b40"))] == ["a30"]
    assert merge.update_input(0, Sample(25, 50, "late")) == []
    assert merge.late == 1
    assert [s.value for s in merge.advance(140)] == ["b40"]


def test_merge_releases_silent_input_after_delay() -> None:
    merge = MergeOp(3, max_delay_ms=50)
    merge.update_input(0, Sample(0, 0, 1))
    assert merge.advance(49) == []
    assert [s.value for s in merge.advance(50)] == [1]


@pytest.mark.parametrize(
    "make",
    [
        lambda: WindowOp(0),
        lambda: SampleOp(0),
        lambda: MergeOp(0, 1),
        lambda: MergeOp(1, 0).update_input(3, Sample(0, 0, 0)),
    ],
)
def test_operator_misuse_raises(make: object) -> None:
    with pytest.raises(StreamError):
        make()  # type: ignore[operator]


def test_aggregate_without_numbers_raises() -> None:
    with pytest.raises(StreamError, match="no numbers"):
        aggregate(Aggregate.MEAN, ["a"])
