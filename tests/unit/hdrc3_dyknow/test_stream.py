import pytest

from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.sample import Sample, StreamError
from hdrc3_dyknow.stream import RateEstimator, Stream, StreamGenerator


def test_publish_is_delivered_only_on_flush() -> None:
    gen = StreamGenerator("uav0/altitude", Policy(), "Altitude[uav0]")
    a = gen.subscribe(Policy())
    b = gen.subscribe(Policy(change_only=True))
    for t, v in [(0, 1.0), (10, 1.0), (20, 2.0)]:
        gen.publish(Sample(t, t, v))
    assert a.drain() == [] and gen.pending
    assert gen.flush() == 3
    assert [s.value for s in a.drain()] == [1.0, 1.0, 2.0]
    assert [s.value for s in b.drain()] == [1.0, 2.0]
    assert a.drain() == []


def test_generator_policy_counts_bad_samples_and_status() -> None:
    gen = StreamGenerator("x", Policy(max_delay_ms=100), "X[a]")
    for valid, available in [(0, 0), (40, 40), (40, 41), (20, 50), (80, 300), (120, 120)]:
        gen.publish(Sample(valid, available, 1.0))
    status = gen.status()
    assert (status.stats.duplicates, status.stats.out_of_order, status.stats.late) == (1, 1, 1)
    assert status.stats.samples_out == 3
    assert status.last_valid_time == 120
    assert status.rate_hz == pytest.approx(1000 * 2 / 120)
    assert status.annotation == "X[a]" and status.subscribers == 0


def test_unsubscribe_stops_delivery() -> None:
    gen = StreamGenerator("x", Policy())
    stream = gen.subscribe(Policy())
    gen.unsubscribe(stream)
    gen.publish(Sample(0, 0, 1))
    gen.flush()
    assert stream.drain() == []


def test_bounded_inbox_counts_overflow() -> None:
    stream = Stream("x", Policy(), capacity=2)
    for t in range(5):
        stream.offer(Sample(t, t, t))
    assert [s.value for s in stream.drain()] == [3, 4]
    assert stream.overflow == 3


@pytest.mark.parametrize(
    ("times", "rate"), [([], 0.0), ([5], 0.0), ([0, 0], 0.0), ([0, 40, 80], 25.0)]
)
def test_rate_estimator(times: list[int], rate: float) -> None:
    est = RateEstimator()
    for t in times:
        est.update(Sample(t, t, 0))
    assert est.rate_hz == pytest.approx(rate)


@pytest.mark.parametrize(("label", "capacity"), [("", 10), ("x", 0)])
def test_bad_construction(label: str, capacity: int) -> None:
    with pytest.raises(StreamError):
        if label:
            Stream(label, Policy(), capacity)
        else:
            StreamGenerator(label, Policy())
