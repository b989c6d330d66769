"""Stamps <-> seconds and nanoseconds."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from hdrc3_base.stamps import nanoseconds, seconds, set_stamp_ns, set_stamp_s, stamp_ns, stamp_s


@dataclass
class Stamp:
    """A builtin_interfaces/Time stand-in (the helpers are duck-typed)."""

    sec: int = 0
    nanosec: int = 0


@pytest.mark.parametrize(
    ("seconds", "sec", "nanosec"),
    [
        (0.0, 0, 0),
        (1.5, 1, 500_000_000),
        (123.000000001, 123, 1),
        (-2.0, 0, 0),  # ROS times are unsigned here
        (1e-10, 0, 0),  # rounded to the nanosecond
    ],
)
def test_seconds_round_trip(seconds: float, sec: int, nanosec: int) -> None:
    stamp = Stamp()
    set_stamp_s(stamp, seconds)
    assert (stamp.sec, stamp.nanosec) == (sec, nanosec)
    assert stamp_ns(stamp) == sec * 1_000_000_000 + nanosec
    assert stamp_s(stamp) == pytest.approx(max(seconds, 0.0), abs=1e-9)


@pytest.mark.parametrize("ns", [0, 1, 999_999_999, 1_000_000_000, 86_400_123_456_789])
def test_nanoseconds_round_trip(ns: int) -> None:
    stamp = Stamp()
    set_stamp_ns(stamp, ns)
    assert stamp_ns(stamp) == ns and 0 <= stamp.nanosec < 1_000_000_000


@pytest.mark.parametrize(
    "ns", [0, 1, 999_999_999, 1_000_000_000, 254_980_000_000, 86_400_123_456_789]
)
def test_the_fields_give_what_the_stamp_gives(ns: int) -> None:
    stamp = Stamp()
    set_stamp_ns(stamp, ns)
    # bit for bit: the raw readers' (sec, nanosec) feed the kernel the same floats
    assert seconds(stamp.sec, stamp.nanosec) == stamp_s(stamp)
    assert nanoseconds(stamp.sec, stamp.nanosec) == stamp_ns(stamp) == ns
