"""Book-keeping of the navigation filter's aiding sources (chapter §5.4 "Sensor Fusion").

What :class:`~hdrc3_control.state_estimator.StateEstimator` needs beside its two Kalman steps
to fuse vision fixes: which source corrected the solution and when (:class:`AidingLog`, so the
filter can say which sources it used), the filter's own recent positions to carry a fix taken
at an image's time over to the filter's time (:class:`PositionHistory`: images arrive late,
after rendering and pose estimation), and the test that a run of rejected fixes agrees with
itself, which means the filter is off rather than the fixes (:func:`consistent`).
"""

from __future__ import annotations

import enum
import math
from collections import deque
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


class AidingSource(enum.Enum):
    """What corrected the inertial solution."""

    GPS = "gps"  # GPS position and velocity
    GPS_VELOCITY = "gps_velocity"  # GPS velocity only: vision has the position
    VISION = "vision"  # the landing pad fix
    BARO = "baro"
    GROUND = "ground"  # on the skids: zero velocity and the ground height


class Verdict(enum.Enum):
    """What happened to one measurement."""

    ACCEPTED = "accepted"
    REJECTED = "rejected"  # outside the innovation gate
    STALE = "stale"  # older than the filter's memory of its own positions
    INVALID = "invalid"  # non-finite values or a non-positive sigma


@dataclass
class SourceStats:
    """Counts per verdict and the last accepted time of one source."""

    counts: dict[Verdict, int]
    last_accepted: float = -math.inf
    last_noted: float = -math.inf
    """Time of the last measurement, whatever its verdict."""
    last_innovation: float = math.nan
    """Norm of the last innovation (measurement minus prediction), m."""


class AidingLog:
    """Per source: verdict counts, last accepted time; which sources are in use."""

    def __init__(self) -> None:
        self.stats: dict[AidingSource, SourceStats] = {}

    def note(
        self, source: AidingSource, verdict: Verdict, time: float, innovation: float = math.nan
    ) -> None:
        """Count one measurement of ``source``."""
        stats = self.stats.setdefault(source, SourceStats({v: 0 for v in Verdict}))
        stats.counts[verdict] += 1
        stats.last_noted = max(stats.last_noted, time)
        if math.isfinite(innovation):
            stats.last_innovation = innovation
        if verdict is Verdict.ACCEPTED:
            stats.last_accepted = max(stats.last_accepted, time)

    def used(self, now: float, within: float) -> tuple[AidingSource, ...]:
        """Sources accepted within ``within`` seconds before ``now`` (enum order)."""
        return tuple(
            s
            for s in AidingSource
            if s in self.stats and now - self.stats[s].last_accepted <= within
        )

    def age(self, source: AidingSource, now: float) -> float:
        """Seconds from the last accepted measurement of ``source`` to ``now`` (inf: none)."""
        stats = self.stats.get(source)
        return math.inf if stats is None else now - stats.last_accepted

    def seen_age(self, source: AidingSource, now: float) -> float:
        """Seconds from the last measurement of ``source``, accepted or not, to ``now`` (inf)."""
        stats = self.stats.get(source)
        return math.inf if stats is None else now - stats.last_noted

    def count(self, source: AidingSource, verdict: Verdict) -> int:
        """How many measurements of ``source`` got ``verdict``."""
        stats = self.stats.get(source)
        return 0 if stats is None else stats.counts[verdict]

    def report(self, now: float, within: float) -> dict[str, object]:
        """JSON-ready summary: the sources in use and every source's counts."""
        return {
            "used": [s.value for s in self.used(now, within)],
            "sources": {
                s.value: {
                    **{v.value: n for v, n in st.counts.items()},
                    "age_s": round(now - st.last_accepted, 3)
                    if math.isfinite(st.last_accepted)
                    else None,
                    "innovation_m": None
                    if math.isnan(st.last_innovation)
                    else round(st.last_innovation, 4),
                }
                for s, st in self.stats.items()
            },
        }


class PositionHistory:
    """The filter's recent travel (predicted motion summed), to move a delayed fix to its time."""

    def __init__(self, span: float) -> None:
        self.span = span
        self._items: deque[tuple[float, NDArray[np.float64]]] = deque()

    def clear(self) -> None:
        """Forget everything (the filter was reset)."""
        self._items.clear()

    def add(self, time: float, position: NDArray[np.float64]) -> None:
        """Remember the filter's position at ``time`` (times increase)."""
        self._items.append((time, np.array(position, copy=True)))
        while self._items and time - self._items[0][0] > self.span:
            self._items.popleft()

    def at(self, time: float) -> NDArray[np.float64] | None:
        """Position at ``time`` (linear between entries); None if older than the memory."""
        items = self._items
        if not items or time < items[0][0]:
            return None
        if time >= items[-1][0]:
            return items[-1][1]
        for (t0, p0), (t1, p1) in zip(reversed(items), list(reversed(items))[1:], strict=False):
            # walking back: (t0, p0) is the later entry, (t1, p1) the earlier one
            if t1 <= time <= t0:
                w = 0.0 if t0 == t1 else (time - t1) / (t0 - t1)
                moved: NDArray[np.float64] = p1 + w * (p0 - p1)
                return moved
        return None


def consistent(innovations: list[NDArray[np.float64]], spread: float) -> bool:
    """True when the innovations agree with each other to ``spread`` (m, RMS about the mean)."""
    if not innovations:
        return False
    stack = np.array(innovations)
    deviation = stack - stack.mean(axis=0)
    return float(np.sqrt(np.mean(np.sum(deviation**2, axis=1)))) <= spread
