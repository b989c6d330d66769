"""State generation: synchronise several fluent streams into a stream of states (section 8.4).

Streams of different features arrive at different rates and with different delays. A
:class:`StateSynchronizer` produces one :class:`State` per period on the grid
``k * period_ms``, each assigning one value to every feature: the latest sample at or before the
state's time, or an extrapolation, per the feature's missing-value handling. A state at time
``t`` is emitted as soon as every stream has reached ``t`` (nothing can change it any more) or,
at the latest, when ``now >= t + max_delay_ms`` — the policy's bound on waiting for late samples.
Times are in ms.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Hashable, Mapping, Sequence
from dataclasses import dataclass

from hdrc3_dyknow.policy import MAX_FILL, MissingHandling, estimate
from hdrc3_dyknow.sample import Sample, StreamError, Value

DEFAULT_HISTORY = 256


@dataclass(frozen=True, slots=True)
class State:
    """A synchronised state: one value per feature at one valid time.

    Attributes:
        time: Valid time of the state (ms).
        available_time: The ``now`` at which the state was emitted (ms).
        values: Value of every feature key.

    """

    time: int
    available_time: int
    values: Mapping[Hashable, Value]


@dataclass(slots=True)
class SyncStats:
    """Counts of a synchroniser since its last reset."""

    samples: int = 0
    states: int = 0
    incomplete: int = 0
    late: int = 0
    out_of_order: int = 0
    skipped: int = 0


class StateSynchronizer:
    """Turn samples of several keyed streams into a periodic stream of states."""

    def __init__(
        self,
        keys: Sequence[Hashable],
        period_ms: int,
        max_delay_ms: int,
        missing: MissingHandling | Mapping[Hashable, MissingHandling] = (
            MissingHandling.LAST_VALUE
        ),
        max_age_ms: int = 0,
        history: int = DEFAULT_HISTORY,
    ) -> None:
        """Create a synchroniser.

        Args:
            keys: The features (any hashable keys) each state assigns a value to.
            period_ms: State period (> 0).
            max_delay_ms: How long to wait for late samples before emitting a state (>= 0).
            missing: Missing-value handling, for all keys or per key.
            max_age_ms: A value older than this at the state's time counts as missing (0: no
                limit).
            history: Samples buffered per key (bounded).

        Raises:
            StreamError: On an empty key set, duplicate keys or non-positive periods.

        """
        if not keys or len(set(keys)) != len(keys):
            raise StreamError(f"state keys must be non-empty and distinct: {list(keys)}")
        if period_ms <= 0 or max_delay_ms < 0 or max_age_ms < 0 or history < 2:
            raise StreamError(
                f"bad synchroniser timing: period_ms={period_ms} max_delay_ms={max_delay_ms}"
                f" max_age_ms={max_age_ms} history={history}"
            )
        self.keys = tuple(keys)
        self.period = period_ms
        self.max_delay = max_delay_ms
        self.max_age = max_age_ms
        self._missing = {
            key: missing if isinstance(missing, MissingHandling) else missing[key]
            for key in self.keys
        }
        self._history = history
        self.stats = SyncStats()
        self._buffers: dict[Hashable, deque[Sample]] = {}
        self._next: int | None = None
        self.reset()

    def reset(self) -> None:
        """Forget all samples, counts and the position on the grid."""
        self.stats = SyncStats()
        self._buffers = {key: deque(maxlen=self._history) for key in self.keys}
        self._next = None

    @property
    def next_time(self) -> int | None:
        """Valid time of the next state to emit (None before the first sample)."""
        return self._next

    def update(self, key: Hashable, sample: Sample) -> None:
        """Add one sample of ``key``'s stream.

        Raises:
            StreamError: If ``key`` is not one of the synchroniser's keys.

        """
        buffer = self._buffers.get(key)
        if buffer is None:
            raise StreamError(f"unknown state key {key!r}; keys are {list(self.keys)}")
        self.stats.samples += 1
        if buffer and sample.valid_time <= buffer[-1].valid_time:
            self.stats.out_of_order += 1
            return
        if self._next is None:
            self._next = -(-sample.valid_time // self.period) * self.period
        elif sample.valid_time < self._next - self.period:
            self.stats.late += 1  # too late for the state it belonged to; later states may use it
        buffer.append(sample)

    def advance(self, now: int) -> list[State]:
        """Emit every state that is complete or whose waiting time has run out at ``now``."""
        if self._next is None:
            return []
        deadline = now - self.max_delay
        complete = min(
            (buffer[-1].valid_time if buffer else -(2**62) for buffer in self._buffers.values()),
        )
        until = max(deadline, complete)
        if (until - self._next) // self.period > MAX_FILL:
            jump = ((until - self._next) // self.period - MAX_FILL) * self.period
            self.stats.skipped += jump // self.period
            self._next += jump
        states = []
        while self._next <= until:
            state = self._state_at(self._next, now)
            if state is None:
                self.stats.incomplete += 1
            else:
                states.append(state)
            self._next += self.period
            self._prune(self._next)
        self.stats.states += len(states)
        return states

    def _state_at(self, time: int, now: int) -> State | None:
        values: dict[Hashable, Value] = {}
        for key, buffer in self._buffers.items():
            value = self._value_at(key, buffer, time)
            if value is None:
                return None
            values[key] = value
        return State(time, now, values)

    def _value_at(self, key: Hashable, buffer: deque[Sample], time: int) -> Value | None:
        previous: Sample | None = None
        latest: Sample | None = None
        for sample in buffer:
            if sample.valid_time > time:
                break
            previous, latest = latest, sample
        if latest is None or (self.max_age and time - latest.valid_time > self.max_age):
            return None
        if latest.valid_time > time - self.period:
            return latest.value  # a sample within the period: sample-and-hold
        return estimate(previous, latest, time, self._missing[key])

    def _prune(self, time: int) -> None:
        """Keep the two latest samples at or before ``time`` (for extrapolation) and all after."""
        for buffer in self._buffers.values():
            while len(buffer) >= 3 and buffer[2].valid_time <= time:
                buffer.popleft()
