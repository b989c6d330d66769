"""Knowledge processes and the host that runs them (section 8.1, Figure 24).

A knowledge process is a *source* (external data published into stream generators) or a
*computational unit* that refines input streams into output streams. Processes expose one hook,
:meth:`KnowledgeProcess.step`; the :class:`KnowledgeProcessHost` owns stream generators,
subscriptions and lifecycle: it delivers published samples asynchronously (on
:meth:`KnowledgeProcessHost.advance`), then steps every process with the samples that arrived
on its inputs. Time only moves when the host is advanced with an explicit ``now`` (ms).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Protocol

from hdrc3_dyknow.operators import MergeOp, StreamOperator
from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.sample import Sample, StreamError, Value
from hdrc3_dyknow.state_sync import StateSynchronizer
from hdrc3_dyknow.stream import Stream, StreamGenerator, StreamStatus

# Bound on publish/deliver rounds per advance: a cycle of processes cannot spin forever.
MAX_ROUNDS = 32


@dataclass(slots=True)
class StepContext:
    """What a process sees in one step: the time, its new input samples, and a publisher."""

    now: int
    inputs: Mapping[str, list[Sample]]
    publish: Callable[[str, Sample], None]


class KnowledgeProcess(Protocol):
    """The one hook a knowledge process implements."""

    def step(self, ctx: StepContext) -> None:
        """Consume ``ctx.inputs`` and publish derived samples with ``ctx.publish``."""


class ProcessStatus(StrEnum):
    """Lifecycle of a hosted process."""

    RUNNING = "running"
    FAILED = "failed"


@dataclass(slots=True)
class _Hosted:
    process: KnowledgeProcess
    inputs: dict[str, Stream]
    outputs: frozenset[str]
    status: ProcessStatus = ProcessStatus.RUNNING
    reason: str = ""


@dataclass(slots=True)
class KnowledgeProcessHost:
    """The stream manager and process host of one knowledge processing application."""

    capacity: int = 4096
    _generators: dict[str, StreamGenerator] = field(default_factory=dict)
    _processes: dict[str, _Hosted] = field(default_factory=dict)

    def declare(self, label: str, policy: Policy | None = None, annotation: str = "") -> None:
        """Declare a stream generator, or re-declare it with a new policy or annotation.

        Re-declaring keeps the existing subscriptions, so running processes keep receiving.

        Raises:
            StreamError: If the label is empty.

        """
        old = self._generators.get(label)
        if old is not None and old.policy == (policy or Policy()) and old.annotation == annotation:
            return
        generator = StreamGenerator(label, policy or Policy(), annotation, self.capacity)
        if old is not None:
            generator.adopt_subscribers(old)
        self._generators[label] = generator

    def remove(self, label: str) -> None:
        """Remove a stream generator (subscribers simply stop receiving)."""
        self._generators.pop(label, None)

    def labels(self) -> list[str]:
        """All stream generator labels, sorted."""
        return sorted(self._generators)

    def generator(self, label: str) -> StreamGenerator:
        """Return the stream generator called ``label``.

        Raises:
            StreamError: If there is none.

        """
        try:
            return self._generators[label]
        except KeyError:
            raise StreamError(f"unknown stream {label!r}; known streams: {self.labels()}") from None

    def publish(self, label: str, sample: Sample) -> None:
        """Publish one sample on ``label`` (sources and processes both use this)."""
        self.generator(label).publish(sample)

    def subscribe(self, label: str, policy: Policy | None = None) -> Stream:
        """Open a new stream of ``label``'s samples under ``policy``."""
        return self.generator(label).subscribe(policy or Policy(), self.capacity)

    def add_process(
        self,
        name: str,
        process: KnowledgeProcess,
        inputs: Mapping[str, Policy],
        outputs: Sequence[str] = (),
    ) -> None:
        """Host a process, subscribing it to ``inputs`` (label -> policy).

        Raises:
            StreamError: If the name is taken or an input label is unknown.

        """
        if name in self._processes:
            raise StreamError(f"knowledge process {name!r} already exists")
        for label in outputs:
            if label not in self._generators:
                self.declare(label)
        streams = {label: self.subscribe(label, policy) for label, policy in inputs.items()}
        self._processes[name] = _Hosted(process, streams, frozenset(outputs))

    def remove_process(self, name: str) -> None:
        """Stop hosting a process and close its subscriptions (no-op if unknown)."""
        hosted = self._processes.pop(name, None)
        if hosted is None:
            return
        for label, stream in hosted.inputs.items():
            if label in self._generators:
                self._generators[label].unsubscribe(stream)

    def process_status(self, name: str) -> tuple[ProcessStatus, str]:
        """Status and failure reason of a hosted process."""
        hosted = self._processes.get(name)
        if hosted is None:
            raise StreamError(f"unknown knowledge process {name!r}")
        return hosted.status, hosted.reason

    def advance(self, now: int) -> None:
        """Deliver published samples and step every running process at time ``now`` (ms)."""
        for generator in self._generators.values():
            generator.advance(now)
        for _ in range(MAX_ROUNDS):
            delivered = sum(g.flush() for g in list(self._generators.values()))
            for hosted in list(self._processes.values()):
                if hosted.status is ProcessStatus.RUNNING:
                    self._step(hosted, now)
            if not delivered and not any(g.pending for g in self._generators.values()):
                return

    def status(self) -> list[StreamStatus]:
        """Introspection snapshots of all stream generators, sorted by label."""
        return [self._generators[label].status() for label in self.labels()]

    def _step(self, hosted: _Hosted, now: int) -> None:
        inputs: dict[str, list[Sample]] = {}
        for label, stream in hosted.inputs.items():
            stream.advance(now)
            inputs[label] = stream.drain()

        def publish(label: str, sample: Sample) -> None:
            if label not in hosted.outputs:
                raise StreamError(f"process may not publish on {label!r}")
            self.publish(label, sample)

        try:
            hosted.process.step(StepContext(now, inputs, publish))
        except Exception as exc:  # a failing plug-in is isolated, not fatal
            hosted.status = ProcessStatus.FAILED
            hosted.reason = f"{type(exc).__name__}: {exc}"


class OperatorUnit:
    """Computational unit: one input stream through an operator chain to one output stream."""

    def __init__(self, source: str, target: str, operator: StreamOperator) -> None:
        self.source = source
        self.target = target
        self._operator = operator

    def step(self, ctx: StepContext) -> None:
        """Push the new input samples through the operator and publish the results."""
        out = [
            s for sample in ctx.inputs.get(self.source, []) for s in self._operator.update(sample)
        ]
        out.extend(self._operator.advance(ctx.now))
        for sample in out:
            ctx.publish(self.target, sample)


class MergeUnit:
    """Computational unit: merge several input streams into one ordered by valid time."""

    def __init__(self, sources: Sequence[str], target: str, merge: MergeOp) -> None:
        self.sources = tuple(sources)
        self.target = target
        self._merge = merge

    def step(self, ctx: StepContext) -> None:
        """Offer the new samples of every input and publish what the merge releases."""
        out: list[Sample] = []
        for index, label in enumerate(self.sources):
            for sample in ctx.inputs.get(label, []):
                out.extend(self._merge.update_input(index, sample))
        out.extend(self._merge.advance(ctx.now))
        for sample in out:
            ctx.publish(self.target, sample)


class FunctionUnit:
    """Computational unit: a function of several synchronised input streams (e.g. XYDist)."""

    def __init__(
        self,
        sources: Sequence[str],
        target: str,
        function: Callable[[Sequence[Value]], Value],
        synchronizer: StateSynchronizer,
    ) -> None:
        if tuple(synchronizer.keys) != tuple(sources):
            raise StreamError(f"synchroniser keys {synchronizer.keys} != sources {sources}")
        self.sources = tuple(sources)
        self.target = target
        self._function = function
        self._sync = synchronizer

    def step(self, ctx: StepContext) -> None:
        """Synchronise new input samples and publish the function of every complete state."""
        for label in self.sources:
            for sample in ctx.inputs.get(label, []):
                self._sync.update(label, sample)
        for state in self._sync.advance(ctx.now):
            values: list[Value] = [state.values[key] for key in self.sources]
            ctx.publish(
                self.target, Sample(state.time, state.available_time, self._function(values))
            )
