"""Stream operators: map, filter, window, aggregate, sample and merge (section 8.1).

Each operator is a small object with ``reset()`` and ``update(sample) -> list[Sample]`` (and
``advance(now)`` for time-driven ones) over bounded buffers, so operators chain into
computational units (see :class:`hdrc3_dyknow.knowledge_process.OperatorUnit`). Times in ms.
"""

from __future__ import annotations

import heapq
import statistics
from collections import deque
from collections.abc import Callable, Sequence
from enum import StrEnum
from typing import Protocol

from hdrc3_dyknow.policy import LateHandling, MissingHandling, Policy, PolicyFilter
from hdrc3_dyknow.sample import Sample, StreamError, Value, is_number


class StreamOperator(Protocol):
    """A single-input stream operator."""

    def reset(self) -> None:
        """Forget all state."""

    def update(self, sample: Sample) -> list[Sample]:
        """Consume one sample; return the samples produced."""

    def advance(self, now: int) -> list[Sample]:
        """Let time pass; return samples that became due."""


class MapOp:
    """Apply a function to every value."""

    def __init__(self, function: Callable[[Value], Value]) -> None:
        self._function = function

    def reset(self) -> None:
        """Stateless."""

    def update(self, sample: Sample) -> list[Sample]:
        """Map the sample's value."""
        return [Sample(sample.valid_time, sample.available_time, self._function(sample.value))]

    def advance(self, now: int) -> list[Sample]:
        """Stateless: nothing becomes due."""
        return []


class FilterOp:
    """Keep samples whose value satisfies a predicate."""

    def __init__(self, predicate: Callable[[Value], bool]) -> None:
        self._predicate = predicate

    def reset(self) -> None:
        """Stateless."""

    def update(self, sample: Sample) -> list[Sample]:
        """Pass the sample if the predicate holds."""
        return [sample] if self._predicate(sample.value) else []

    def advance(self, now: int) -> list[Sample]:
        """Stateless: nothing becomes due."""
        return []


class WindowOp:
    """Sliding time window: emit the tuple of values with valid time in (t - width, t]."""

    def __init__(self, width_ms: int, capacity: int = 1024) -> None:
        if width_ms <= 0 or capacity <= 0:
            raise StreamError(f"window width and capacity must be > 0: {width_ms}, {capacity}")
        self._width = width_ms
        self._buffer: deque[Sample] = deque(maxlen=capacity)

    def reset(self) -> None:
        """Empty the window."""
        self._buffer.clear()

    def update(self, sample: Sample) -> list[Sample]:
        """Add the sample and emit the current window contents."""
        self._buffer.append(sample)
        while self._buffer[0].valid_time <= sample.valid_time - self._width:
            self._buffer.popleft()
        values = tuple(s.value for s in self._buffer)
        return [Sample(sample.valid_time, sample.available_time, values)]

    def advance(self, now: int) -> list[Sample]:
        """Emit nothing: windows emit on input only."""
        return []


class Aggregate(StrEnum):
    """Aggregation functions over a window of numbers."""

    MEAN = "mean"
    MIN = "min"
    MAX = "max"
    SUM = "sum"
    COUNT = "count"


def aggregate(function: Aggregate, values: Sequence[Value]) -> Value:
    """Aggregate the numeric ``values`` (non-numbers are ignored; COUNT counts all)."""
    if function is Aggregate.COUNT:
        return len(values)
    numbers = [float(v) for v in values if is_number(v)]  # type: ignore[arg-type]
    if not numbers:
        raise StreamError(f"cannot aggregate {function} over no numbers")
    reducers: dict[Aggregate, Callable[[list[float]], float]] = {
        Aggregate.MEAN: statistics.fmean,
        Aggregate.MIN: min,
        Aggregate.MAX: max,
        Aggregate.SUM: sum,
    }
    return reducers[function](numbers)


class AggregateOp:
    """Aggregate a sliding time window into one value per input sample."""

    def __init__(self, function: Aggregate, width_ms: int, capacity: int = 1024) -> None:
        self._function = function
        self._window = WindowOp(width_ms, capacity)

    def reset(self) -> None:
        """Empty the window."""
        self._window.reset()

    def update(self, sample: Sample) -> list[Sample]:
        """Add the sample and emit the aggregate of the window."""
        out = []
        for window in self._window.update(sample):
            assert isinstance(window.value, tuple)
            if self._function is Aggregate.COUNT or any(is_number(v) for v in window.value):
                value = aggregate(self._function, window.value)
                out.append(Sample(window.valid_time, window.available_time, value))
        return out

    def advance(self, now: int) -> list[Sample]:
        """Emit nothing: aggregates emit on input only."""
        return []


class SampleOp:
    """Resample onto a fixed period, filling gaps per ``missing`` (a resampling policy)."""

    def __init__(
        self,
        period_ms: int,
        missing: MissingHandling = MissingHandling.LAST_VALUE,
        max_delay_ms: int = 0,
    ) -> None:
        if period_ms <= 0:
            raise StreamError(f"sample period must be > 0 ms, got {period_ms}")
        # Late samples are kept: here the maximum delay only bounds how long a grid point waits.
        self._filter = PolicyFilter(
            Policy(
                sample_period_ms=period_ms,
                missing=missing,
                max_delay_ms=max_delay_ms,
                late=LateHandling.KEEP,
            )
        )

    def reset(self) -> None:
        """Forget the held samples."""
        self._filter.reset()

    def update(self, sample: Sample) -> list[Sample]:
        """Consume one sample; emit completed grid points."""
        return self._filter.update(sample)

    def advance(self, now: int) -> list[Sample]:
        """Emit grid points older than ``now - max_delay_ms``."""
        return self._filter.advance(now)


class Chain:
    """Several single-input operators applied in sequence."""

    def __init__(self, operators: Sequence[StreamOperator]) -> None:
        self._operators = list(operators)

    def reset(self) -> None:
        """Reset every operator."""
        for operator in self._operators:
            operator.reset()

    def update(self, sample: Sample) -> list[Sample]:
        """Push one sample through the whole chain."""
        return self._through(0, [sample])

    def advance(self, now: int) -> list[Sample]:
        """Advance every operator, pushing what each emits through the rest of the chain."""
        out: list[Sample] = []
        for index, operator in enumerate(self._operators):
            out.extend(self._through(index + 1, operator.advance(now)))
        return out

    def _through(self, start: int, samples: list[Sample]) -> list[Sample]:
        for operator in self._operators[start:]:
            samples = [produced for s in samples for produced in operator.update(s)]
        return samples


class MergeOp:
    """Merge several input streams into one ordered by valid time.

    A sample is released once every input has reached its valid time (the watermark) or once
    ``max_delay_ms`` has passed since it, so a silent input cannot stall the merge forever.
    Samples older than the last released one are counted as late and dropped.
    """

    def __init__(self, inputs: int, max_delay_ms: int, capacity: int = 4096) -> None:
        if inputs < 1 or max_delay_ms < 0 or capacity < 1:
            raise StreamError(f"bad merge: inputs={inputs} max_delay_ms={max_delay_ms}")
        self._inputs = inputs
        self._max_delay = max_delay_ms
        self._capacity = capacity
        self._heap: list[tuple[int, int, int, Sample]] = []
        self._seen: list[int | None] = [None] * inputs
        self._released: int | None = None
        self._sequence = 0
        self.late = 0
        self.overflow = 0

    def reset(self) -> None:
        """Forget buffered samples and watermarks."""
        self._heap.clear()
        self._seen = [None] * self._inputs
        self._released = None
        self.late = self.overflow = 0

    def update_input(self, index: int, sample: Sample) -> list[Sample]:
        """Consume one sample from input ``index``; return the samples released."""
        if not 0 <= index < self._inputs:
            raise StreamError(f"merge input {index} out of range 0..{self._inputs - 1}")
        if self._released is not None and sample.valid_time < self._released:
            self.late += 1
            return []
        seen = self._seen[index]
        self._seen[index] = sample.valid_time if seen is None else max(seen, sample.valid_time)
        self._sequence += 1
        heapq.heappush(self._heap, (sample.valid_time, index, self._sequence, sample))
        if len(self._heap) > self._capacity:
            self.overflow += 1
            return self._release(self._heap[0][0])
        if any(seen is None for seen in self._seen):
            return []
        return self._release(min(t for t in self._seen if t is not None))

    def advance(self, now: int) -> list[Sample]:
        """Release samples whose maximum waiting time has passed."""
        return self._release(now - self._max_delay)

    def _release(self, watermark: int) -> list[Sample]:
        out = []
        while self._heap and self._heap[0][0] <= watermark:
            out.append(heapq.heappop(self._heap)[3])
        if out:
            self._released = out[-1].valid_time
        return out
