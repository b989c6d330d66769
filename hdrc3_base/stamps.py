"""Seconds and nanoseconds in ``builtin_interfaces/Time`` stamps, converted in one place.

Duck-typed (anything with ``sec`` and ``nanosec``), so that pure cores and tests can use it
without rclpy. Negative times are written as 0: ROS times are unsigned here.
"""

from __future__ import annotations

from typing import Any

NS_PER_S = 1_000_000_000


def stamp_ns(stamp: Any) -> int:
    """Integer nanoseconds of a stamp."""
    return int(stamp.sec) * NS_PER_S + int(stamp.nanosec)


def stamp_s(stamp: Any) -> float:
    """Seconds of a stamp."""
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def ns_to_s(ns: int) -> float:
    """Seconds of integer nanoseconds, exactly as :func:`stamp_s` of the stamp holding them."""
    sec, nanosec = divmod(ns, NS_PER_S)
    return float(sec) + 1e-9 * float(nanosec)


def set_stamp_ns(stamp: Any, ns: int) -> None:
    """Write integer nanoseconds (negative: 0) into a stamp."""
    ns = max(0, ns)
    stamp.sec, stamp.nanosec = ns // NS_PER_S, ns % NS_PER_S


def set_stamp_s(stamp: Any, seconds: float) -> None:
    """Write seconds, rounded to the nanosecond (negative: 0), into a stamp."""
    set_stamp_ns(stamp, round(seconds * 1e9))
