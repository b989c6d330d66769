"""Time-stamped samples of fluent streams (HDRC3 chapter section 8.3).

Time is explicit and integral: every time in ``hdrc3_dyknow`` stream processing is an ``int`` in
**milliseconds** (the unit the chapter's monitor formulas use, e.g. ``◇[0,5000]``). Integers keep
sampling grids exact; callers convert ROS time (ns) with :func:`ms_from_ns`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypeAlias

from hdrc3_base.errors import Hdrc3Error

Value: TypeAlias = bool | int | float | str | tuple["Value", ...]
"""A sample value: a scalar or a (possibly nested) tuple such as a (lat, lon, alt) position."""


class StreamError(Hdrc3Error):
    """Misuse of the DyKnow stream API (unknown label, bad policy, bad sample)."""


@dataclass(frozen=True, slots=True)
class Sample:
    """One sample of a fluent stream.

    Attributes:
        valid_time: When the value holds in the world (ms).
        available_time: When the sample became available in the stream (ms); never before
            ``valid_time`` for observations, although clocks of different computers may disagree.
        value: The sampled value.

    """

    valid_time: int
    available_time: int
    value: Value

    @property
    def delay(self) -> int:
        """Propagation delay: available time minus valid time (ms)."""
        return self.available_time - self.valid_time


@dataclass(frozen=True, slots=True)
class FeatureTerm:
    """A feature applied to objects, e.g. ``XYDist[uav1, av1]`` (section 8.3).

    Attributes:
        feature: Feature name as in the ontology, e.g. ``"XYDist"``.
        args: Object names, in order.

    """

    feature: str
    args: tuple[str, ...] = ()

    def __str__(self) -> str:
        return f"{self.feature}[{', '.join(self.args)}]"


def ms_from_ns(nanoseconds: int) -> int:
    """Convert ROS time (ns) to stream time (ms), rounding down."""
    return nanoseconds // 1_000_000


def is_number(value: Value) -> bool:
    """Whether ``value`` is a finite real number (bools are not numbers here)."""
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def check_value(value: Value) -> Value:
    """Reject non-finite floats anywhere in ``value`` (NaN never enters a stream).

    Raises:
        StreamError: If a float in ``value`` is NaN or infinite.

    """
    if isinstance(value, float) and not math.isfinite(value):
        raise StreamError(f"non-finite value {value!r}")
    if isinstance(value, tuple):
        for item in value:
            check_value(item)
    return value
