"""Stream generators and streams: labelled publish/subscribe of samples (section 8.2).

A :class:`StreamGenerator` has a label and a declared policy; a knowledge process publishes
samples to it and it delivers them *asynchronously* (on the host's next dispatch) to every
:class:`Stream` subscribed to its label. Each subscription applies its own policy, so the same
samples can be consumed differently by different processes. Buffers are bounded and overflow is
counted. Times are in ms.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, replace

from hdrc3_dyknow.policy import Policy, PolicyFilter, PolicyStats
from hdrc3_dyknow.sample import Sample, StreamError

DEFAULT_CAPACITY = 4096
RATE_WINDOW = 50


class RateEstimator:
    """Samples per second of valid time over the last ``window`` samples."""

    def __init__(self, window: int = RATE_WINDOW) -> None:
        self._times: deque[int] = deque(maxlen=window)

    def reset(self) -> None:
        """Forget all samples."""
        self._times.clear()

    def update(self, sample: Sample) -> None:
        """Record one delivered sample."""
        self._times.append(sample.valid_time)

    @property
    def rate_hz(self) -> float:
        """The estimated rate, 0.0 until two samples with distinct times were seen."""
        if len(self._times) < 2 or self._times[-1] <= self._times[0]:
            return 0.0
        return 1000.0 * (len(self._times) - 1) / (self._times[-1] - self._times[0])


class Stream:
    """One subscription to a stream generator: a policy filter and a bounded inbox."""

    def __init__(self, label: str, policy: Policy, capacity: int = DEFAULT_CAPACITY) -> None:
        if capacity < 1:
            raise StreamError(f"stream capacity must be >= 1, got {capacity}")
        self.label = label
        self.policy = policy
        self.filter = PolicyFilter(policy)
        self.overflow = 0
        self._inbox: deque[Sample] = deque(maxlen=capacity)

    @property
    def stats(self) -> PolicyStats:
        """Counts of the subscription's policy filter."""
        return self.filter.stats

    def offer(self, sample: Sample) -> None:
        """Receive one sample from the generator (applies this subscription's policy)."""
        self._push(self.filter.update(sample))

    def advance(self, now: int) -> None:
        """Let a resampling policy emit grid samples whose maximum delay has passed."""
        self._push(self.filter.advance(now))

    def drain(self) -> list[Sample]:
        """Take all samples received since the last drain, oldest first."""
        out = list(self._inbox)
        self._inbox.clear()
        return out

    def _push(self, samples: list[Sample]) -> None:
        for sample in samples:
            if len(self._inbox) == self._inbox.maxlen:
                self.overflow += 1  # the deque drops the oldest sample
            self._inbox.append(sample)


@dataclass(frozen=True, slots=True)
class StreamStatus:
    """Introspection snapshot of one stream generator."""

    label: str
    policy: Policy
    annotation: str
    stats: PolicyStats
    rate_hz: float
    last_valid_time: int | None
    subscribers: int


class StreamGenerator:
    """A labelled producer of one stream; delivers published samples to its subscribers."""

    def __init__(
        self, label: str, policy: Policy, annotation: str = "", capacity: int = DEFAULT_CAPACITY
    ) -> None:
        if not label:
            raise StreamError("stream generator label must not be empty")
        self.label = label
        self.policy = policy
        self.annotation = annotation
        self.filter = PolicyFilter(policy)
        self.rate = RateEstimator()
        self.overflow = 0
        self._last: Sample | None = None
        self._outbox: deque[Sample] = deque(maxlen=capacity)
        self._subscribers: list[Stream] = []

    @property
    def pending(self) -> bool:
        """Whether published samples wait for delivery."""
        return bool(self._outbox)

    @property
    def last(self) -> Sample | None:
        """The last sample that passed the generator's policy."""
        return self._last

    def publish(self, sample: Sample) -> None:
        """Hand one sample to the generator; it is delivered on the next :meth:`flush`."""
        self._queue(self.filter.update(sample))

    def advance(self, now: int) -> None:
        """Let a resampling policy emit grid samples whose maximum delay has passed."""
        self._queue(self.filter.advance(now))

    def flush(self) -> int:
        """Deliver all queued samples to all subscribers; return how many were delivered."""
        count = len(self._outbox)
        while self._outbox:
            sample = self._outbox.popleft()
            for stream in self._subscribers:
                stream.offer(sample)
        return count

    def subscribe(self, policy: Policy, capacity: int = DEFAULT_CAPACITY) -> Stream:
        """Create a new stream of this generator's samples under ``policy``."""
        stream = Stream(self.label, policy, capacity)
        self._subscribers.append(stream)
        return stream

    def adopt_subscribers(self, other: StreamGenerator) -> None:
        """Take over the subscriptions of ``other`` (a generator this one replaces)."""
        self._subscribers.extend(other._subscribers)
        other._subscribers.clear()

    def unsubscribe(self, stream: Stream) -> None:
        """Stop delivering to ``stream`` (no-op if it is not subscribed)."""
        if stream in self._subscribers:
            self._subscribers.remove(stream)

    def status(self) -> StreamStatus:
        """Return an introspection snapshot."""
        stats = self.filter.stats
        return StreamStatus(
            label=self.label,
            policy=self.policy,
            annotation=self.annotation,
            stats=replace(stats),
            rate_hz=self.rate.rate_hz,
            last_valid_time=None if self._last is None else self._last.valid_time,
            subscribers=len(self._subscribers),
        )

    def _queue(self, samples: list[Sample]) -> None:
        for sample in samples:
            self.rate.update(sample)
            self._last = sample
            if len(self._outbox) == self._outbox.maxlen:
                self.overflow += 1
            self._outbox.append(sample)
