"""State synthesis for execution monitoring (HDRC3 chapter 8.4, 9.3, 9.3.2).

The execution monitor needs one state per sampling point that assigns a value to every fluent
its active formulas read. :class:`StateSynthesizer` builds them from two sources:

* **DyKnow streams** (subscriptions on a knowledge process host), one or more per fluent as
  found by semantic matching. Each stream keeps its declared policy; at a state's time ``t`` a
  fluent's value is the freshest sample at or before ``t`` over its matched streams (several
  matched streams are fused by freshness, not only the first). A sample
  older than one period is a *missing* value and the stream's policy decides (§8.2): hold the
  last value, extrapolate linearly from the two latest samples (§9.3.2: "extrapolating
  historical values"), or drop it. A stream with no sample for longer than ``stale_ms`` is
  *stale*: its fluents are absent from the state, whatever the policy, and a stale-data alarm is
  raised (and cleared when samples return).
* **Execution flags** (§9.3): ``executing-<op>(agent, args...)`` holds exactly while a step of
  ``op`` whose agent is the first argument and whose arguments include the others runs. Flags
  are the executor's own state: exact, never stale, false when no step runs.

States lie on the grid ``k * period_ms``; the state at ``t`` is emitted once every stream it
reads has reached ``t`` or, at the latest, at ``now >= t + max_delay_ms`` (§9.3.2: "delaying
state generation slightly to allow values to propagate"). Times are integer milliseconds.

Written here rather than with :class:`~hdrc3_dyknow.state_sync.StateSynchronizer` because the
set of fluents changes as operator-specific formulas are activated and retired, a missing fluent
must only hold back the formulas that read it, and staleness is an alarm, not a dropped state.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from hdrc3_dyknow.interpretation import FluentValue
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.policy import MAX_FILL, MissingHandling, estimate
from hdrc3_dyknow.sample import Sample, Value
from hdrc3_dyknow.stream import Stream

FLAG_PREFIX = "executing-"
HISTORY = 64
"""Samples kept per stream (the two before a state's time suffice; late ones need a few more)."""


@dataclass(frozen=True, slots=True)
class Step:
    """One running (or finished) execution of an elementary action."""

    node_id: str
    action: str
    agent: str
    arguments: tuple[tuple[str, str], ...]
    start_ms: int
    stop_ms: int | None = None

    def flags(self, name: str, args: tuple[str, ...]) -> bool:
        """Whether this step makes ``executing-<name>(args)`` true (ignoring time)."""
        if name != self.action or not args or args[0] != self.agent:
            return False
        values = {value for _, value in self.arguments}
        return all(arg in values for arg in args[1:])

    def running_at(self, time_ms: int) -> bool:
        """Whether the step runs at ``time_ms``."""
        return self.start_ms <= time_ms and (self.stop_ms is None or time_ms < self.stop_ms)


@dataclass(frozen=True, slots=True)
class SynthesizedState:
    """One state: its valid time, the fluent values, the fluents it lacks and when it was made."""

    time_ms: int
    values: Mapping[str, FluentValue]
    missing: frozenset[str]
    available_ms: int


@dataclass(frozen=True, slots=True)
class StaleChange:
    """A stream became stale (``stale``) or delivered again (not ``stale``) at ``time_ms``."""

    label: str
    stale: bool
    time_ms: int
    last_sample_ms: int | None


@dataclass(slots=True)
class _Source:
    stream: Stream
    missing: MissingHandling
    since_ms: int
    """When the stream was first needed (staleness of a stream that never delivered)."""
    samples: deque[Sample] = field(default_factory=lambda: deque(maxlen=HISTORY))
    stale: bool = False


class StateSynthesizer:
    """Synthesises states over a changing set of fluents from streams and execution flags."""

    def __init__(
        self, host: KnowledgeProcessHost, period_ms: int, max_delay_ms: int, stale_ms: int
    ) -> None:
        self._host = host
        self.period = period_ms
        self.max_delay = max_delay_ms
        self.stale = stale_ms
        self._sources: dict[str, _Source] = {}
        self._fluents: dict[str, tuple[str, ...]] = {}  # fluent key -> stream labels
        self._flags: dict[str, tuple[str, tuple[str, ...]]] = {}  # flag key -> (op, args)
        self._steps: dict[str, Step] = {}
        self._next: int | None = None
        self.states = 0

    @property
    def next_time(self) -> int | None:
        """Valid time of the next state (None before :meth:`start`)."""
        return self._next

    def start(self, now_ms: int) -> None:
        """Begin the state sequence with the first grid time at or after ``now_ms``."""
        self._next = -(-now_ms // self.period) * self.period

    def need(self, fluents: Mapping[str, tuple[str, ...]], now_ms: int) -> None:
        """Make states carry ``fluents`` (ground key -> matched stream labels)."""
        for key, labels in fluents.items():
            self._fluents[key] = labels
            for label in labels:
                if label not in self._sources:
                    generator = self._host.generator(label)
                    self._sources[label] = _Source(
                        self._host.subscribe(label), generator.policy.missing, now_ms
                    )

    def need_flags(self, flags: Mapping[str, tuple[str, tuple[str, ...]]]) -> None:
        """Make states carry execution flags (ground key -> (operator, arguments))."""
        self._flags.update(flags)

    def release(self, keys: Iterable[str]) -> None:
        """Stop carrying ``keys``; streams no fluent reads any more are unsubscribed."""
        for key in keys:
            self._fluents.pop(key, None)
            self._flags.pop(key, None)
        used = {label for labels in self._fluents.values() for label in labels}
        for label in [label for label in self._sources if label not in used]:
            source = self._sources.pop(label)
            self._host.generator(label).unsubscribe(source.stream)

    def step_started(self, step: Step) -> None:
        """An action step started (its flag is true from ``step.start_ms``)."""
        self._steps[step.node_id] = step

    def step_stopped(self, node_id: str, stop_ms: int) -> Step | None:
        """The step ``node_id`` ended at ``stop_ms``; returns it (None if unknown)."""
        step = self._steps.get(node_id)
        if step is None:
            return None
        ended = Step(step.node_id, step.action, step.agent, step.arguments, step.start_ms, stop_ms)
        self._steps[node_id] = ended
        return ended

    def advance(self, now_ms: int) -> tuple[list[SynthesizedState], list[StaleChange]]:
        """Emit every state that is complete or has waited ``max_delay_ms``, with alarms."""
        if self._next is None:
            return [], []
        for source in self._sources.values():
            for sample in source.stream.drain():
                if not source.samples or sample.valid_time > source.samples[-1].valid_time:
                    source.samples.append(sample)
        reached = min(
            (
                source.samples[-1].valid_time if source.samples else self._next - 1
                for source in self._sources.values()
            ),
            default=now_ms - self.max_delay,
        )
        until = max(now_ms - self.max_delay, min(reached, now_ms))
        if (until - self._next) // self.period > MAX_FILL:
            # After a very long pause (or a jump of the clock) restart near now: one wild
            # timestamp must not make the monitor replay millions of states.
            self._next = -(-(until - MAX_FILL * self.period) // self.period) * self.period
        states: list[SynthesizedState] = []
        changes: list[StaleChange] = []
        while self._next <= until:
            states.append(self._state(self._next, now_ms, changes))
            self._next += self.period
        self._prune()
        self.states += len(states)
        return states, changes

    def _state(self, time: int, now: int, changes: list[StaleChange]) -> SynthesizedState:
        values: dict[str, FluentValue] = {}
        missing: set[str] = set()
        estimates = {
            label: self._value(label, source, time, changes)
            for label, source in self._sources.items()
        }
        for key, labels in self._fluents.items():
            best: tuple[int, FluentValue] | None = None
            for label in labels:
                found = estimates[label]
                if found is not None and (best is None or found[0] > best[0]):
                    best = found
            if best is None:
                missing.add(key)
            else:
                values[key] = best[1]
        steps = [step for step in self._steps.values() if step.running_at(time)]
        for key, (name, args) in self._flags.items():
            values[key] = any(step.flags(name, args) for step in steps)
        return SynthesizedState(time, values, frozenset(missing), now)

    def _value(
        self, label: str, source: _Source, time: int, changes: list[StaleChange]
    ) -> tuple[int, FluentValue] | None:
        previous: Sample | None = None
        latest: Sample | None = None
        for sample in source.samples:
            if sample.valid_time > time:
                break
            previous, latest = latest, sample
        last_time = None if latest is None else latest.valid_time
        stale = time - (source.since_ms if last_time is None else last_time) > self.stale
        if stale != source.stale:
            source.stale = stale
            changes.append(StaleChange(label, stale, time, last_time))
        if latest is None or stale:
            return None
        value: Value | None = latest.value
        if latest.valid_time <= time - self.period:
            value = estimate(previous, latest, time, source.missing)
        if value is None or isinstance(value, tuple):
            return None
        return latest.valid_time, value

    def _prune(self) -> None:
        """Drop what no later state can use.

        Two samples at or before the next state's time per stream; finished steps once no
        state can fall into them.
        """
        assert self._next is not None
        for source in self._sources.values():
            samples = source.samples
            while len(samples) >= 3 and samples[2].valid_time <= self._next:
                samples.popleft()
        for node_id in [
            node_id
            for node_id, step in self._steps.items()
            if step.stop_ms is not None and step.stop_ms < self._next - self.period
        ]:
            del self._steps[node_id]

    def stale_labels(self) -> list[str]:
        """Streams currently stale, sorted."""
        return sorted(label for label, source in self._sources.items() if source.stale)

    def labels_of(self, key: str) -> tuple[str, ...]:
        """Streams matched to fluent ``key`` (empty for flags and unknown keys)."""
        return self._fluents.get(key, ())
