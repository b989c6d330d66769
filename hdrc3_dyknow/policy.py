"""Declarative stream policies and the filter that enforces them (sections 8.2-8.3).

A :class:`Policy` states requirements on a stream's content: ordered by valid time, change-only,
a sample period, a maximum delay, and advice on how to handle late and missing values. A
:class:`PolicyFilter` enforces one policy on one stream with a reset()/update(sample) interface
and counts what it drops, so bad input is visible instead of fatal. Times are in ms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

from hdrc3_dyknow.sample import Sample, StreamError, Value, is_number

# A gap longer than this many sample periods is not filled point by point: the filter jumps
# ahead, so one wild timestamp cannot make it emit millions of samples.
MAX_FILL = 1000


class MissingHandling(StrEnum):
    """What to emit at a sample time for which no sample exists."""

    DROP = "drop"
    LAST_VALUE = "last_value"
    EXTRAPOLATE = "extrapolate"


class LateHandling(StrEnum):
    """What to do with a sample whose delay exceeds the policy's maximum delay."""

    DROP = "drop"
    KEEP = "keep"


@dataclass(frozen=True, slots=True)
class Policy:
    """A declarative specification of the desired properties of a stream.

    Attributes:
        ordered: Samples must be ordered by valid time; older samples are dropped.
        change_only: Only samples that differ from the previous one by more than
            ``change_threshold`` pass.
        change_threshold: Significance threshold for ``change_only`` (absolute, per element).
        sample_period_ms: Resample onto the grid ``k * sample_period_ms`` (0: no resampling).
        max_delay_ms: Maximum permitted delay (available minus valid time); 0: unlimited.
        late: How to handle samples exceeding ``max_delay_ms``.
        missing: How to fill sample times without a sample when resampling.

    """

    ordered: bool = True
    change_only: bool = False
    change_threshold: float = 0.0
    sample_period_ms: int = 0
    max_delay_ms: int = 0
    late: LateHandling = LateHandling.DROP
    missing: MissingHandling = MissingHandling.LAST_VALUE

    def __post_init__(self) -> None:
        if self.sample_period_ms < 0 or self.max_delay_ms < 0:
            raise StreamError(
                f"policy periods must be >= 0 ms, got sample_period_ms={self.sample_period_ms},"
                f" max_delay_ms={self.max_delay_ms}"
            )
        if not math.isfinite(self.change_threshold) or self.change_threshold < 0:
            raise StreamError(f"change_threshold must be finite and >= 0: {self.change_threshold}")


@dataclass(slots=True)
class PolicyStats:
    """What a policy filter has seen and done (all counts since the last reset)."""

    samples_in: int = 0
    samples_out: int = 0
    out_of_order: int = 0
    duplicates: int = 0
    late: int = 0
    unchanged: int = 0
    filled: int = 0


def changed(old: Value, new: Value, threshold: float) -> bool:
    """Whether ``new`` is a significant change relative to ``old``."""
    if is_number(old) and is_number(new):
        return abs(float(new) - float(old)) > threshold  # type: ignore[arg-type]
    if isinstance(old, tuple) and isinstance(new, tuple) and len(old) == len(new):
        return any(changed(a, b, threshold) for a, b in zip(old, new, strict=True))
    return old != new


def _linear(v0: Value, v1: Value, fraction: float) -> Value | None:
    if is_number(v0) and is_number(v1):
        return float(v1) + (float(v1) - float(v0)) * fraction  # type: ignore[arg-type]
    if isinstance(v0, tuple) and isinstance(v1, tuple) and len(v0) == len(v1):
        parts = [_linear(a, b, fraction) for a, b in zip(v0, v1, strict=True)]
        return None if any(p is None for p in parts) else tuple(p for p in parts if p is not None)
    return None


def estimate(
    previous: Sample | None, latest: Sample, time: int, missing: MissingHandling
) -> Value | None:
    """Estimate a value at ``time`` from the two latest samples at or before it.

    Args:
        previous: The sample before ``latest`` (for extrapolation), if any.
        latest: The latest sample with valid time <= ``time``.
        time: The time to estimate at (ms).
        missing: Handling when ``latest`` is not exactly at ``time``.

    Returns:
        The estimate, or None when ``missing`` is DROP and there is no sample at ``time``.

    """
    if latest.valid_time == time or missing is MissingHandling.LAST_VALUE:
        return latest.value
    if missing is MissingHandling.DROP:
        return None
    if previous is None or previous.valid_time >= latest.valid_time:
        return latest.value
    fraction = (time - latest.valid_time) / (latest.valid_time - previous.valid_time)
    extrapolated = _linear(previous.value, latest.value, fraction)
    return latest.value if extrapolated is None else extrapolated


@dataclass(slots=True)
class PolicyFilter:
    """Enforce a :class:`Policy` on one stream: update(sample) returns the samples to deliver."""

    policy: Policy
    stats: PolicyStats = field(default_factory=PolicyStats)
    _last_time: int | None = None
    _last_value: Value | None = None
    _previous: Sample | None = None
    _held: Sample | None = None
    _next_grid: int | None = None

    def reset(self) -> None:
        """Forget all samples and counts."""
        self.stats = PolicyStats()
        self._last_time = self._last_value = self._previous = self._held = None
        self._next_grid = None

    def update(self, sample: Sample) -> list[Sample]:
        """Offer one sample; return the samples the policy lets through (possibly none)."""
        self.stats.samples_in += 1
        policy = self.policy
        if policy.max_delay_ms and sample.delay > policy.max_delay_ms:
            self.stats.late += 1
            if policy.late is LateHandling.DROP:
                return []
        if self._last_time is not None:
            if sample.valid_time == self._last_time:
                self.stats.duplicates += 1
                return []
            if sample.valid_time < self._last_time:
                self.stats.out_of_order += 1
                if policy.ordered or policy.sample_period_ms:
                    return []
        self._last_time = max(sample.valid_time, self._last_time or sample.valid_time)
        if (
            policy.change_only
            and self._last_value is not None
            and not changed(self._last_value, sample.value, policy.change_threshold)
        ):
            self.stats.unchanged += 1
            return []
        self._last_value = sample.value
        out = self._resample(sample) if policy.sample_period_ms else [sample]
        self.stats.samples_out += len(out)
        return out

    def advance(self, now: int) -> list[Sample]:
        """Emit grid samples that can no longer receive input in time (resampling only).

        A grid time ``t`` is complete once ``now >= t + max_delay_ms``.
        """
        if not self.policy.sample_period_ms or self._held is None or self._next_grid is None:
            return []
        out = self._fill_until(now - self.policy.max_delay_ms + 1, now)
        self.stats.samples_out += len(out)
        return out

    def _resample(self, sample: Sample) -> list[Sample]:
        period = self.policy.sample_period_ms
        if self._next_grid is None:
            self._next_grid = -(-sample.valid_time // period) * period
        out = self._fill_until(sample.valid_time, sample.available_time)
        self._previous, self._held = self._held, sample
        if sample.valid_time == self._next_grid:
            out.append(Sample(sample.valid_time, sample.available_time, sample.value))
            self._next_grid += period
        return out

    def _fill_until(self, end: int, available: int) -> list[Sample]:
        """Emit grid points strictly before ``end`` from the held samples."""
        assert self._next_grid is not None
        period = self.policy.sample_period_ms
        out: list[Sample] = []
        held = self._held
        if held is None:
            if self._next_grid < end:
                self._next_grid = -(-end // period) * period
            return out
        if (end - self._next_grid) // period > MAX_FILL:
            self._next_grid = -(-(end - MAX_FILL * period) // period) * period
        while self._next_grid < end:
            grid = self._next_grid
            self._next_grid += period
            if held.valid_time > grid - period:
                out.append(Sample(grid, available, held.value))
                continue
            value = estimate(self._previous, held, grid, self.policy.missing)
            if value is not None:
                self.stats.filled += 1
                out.append(Sample(grid, available, value))
        return out
