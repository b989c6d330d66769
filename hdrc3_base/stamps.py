"""Seconds and nanoseconds in ``builtin_interfaces/Time`` stamps, converted in one place.

Duck-typed (anything with ``sec`` and ``nanosec``), so that pure cores and tests can use it
without rclpy. Negative times are written as 0: ROS times are unsigned here.
"""

from __future__ import annotations

from typing import Any

NS_PER_S = 1_000_000_000


def nanoseconds(sec: int, nanosec: int) -> int:
    """Integer nanoseconds of a stamp's two fields (as a raw reader gives them)."""
    return int(sec) * NS_PER_S + int(nanosec)


def seconds(sec: int, nanosec: int) -> float:
    """Seconds of a stamp's two fields (as a raw reader gives them)."""
    return float(sec) + 1e-9 * float(nanosec)


def stamp_ns(stamp: Any) -> int:
    """Integer nanoseconds of a stamp."""
    return nanoseconds(stamp.sec, stamp.nanosec)


def stamp_s(stamp: Any) -> float:
    """Seconds of a stamp."""
    return seconds(stamp.sec, stamp.nanosec)


def set_stamp_ns(stamp: Any, ns: int) -> None:
    """Write integer nanoseconds (negative: 0) into a stamp."""
    ns = max(0, ns)
    stamp.sec, stamp.nanosec = ns // NS_PER_S, ns % NS_PER_S


def set_stamp_s(stamp: Any, seconds: float) -> None:
    """Write seconds, rounded to the nanosecond (negative: 0), into a stamp."""
    set_stamp_ns(stamp, round(seconds * 1e9))
