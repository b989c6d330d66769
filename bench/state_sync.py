"""Benchmark: DyKnow state-synchronisation throughput (states/s from 10 fluent streams).

Ten streams with different sample periods (10-100 ms), random propagation delays (0-60 ms, so
samples arrive out of valid-time order across streams) and 1 % dropped samples are merged into
states every ``--period`` ms, waiting up to ``--max-delay`` ms for late samples (chapter 8.4).
Two set-ups are timed over the same simulated input (wall and CPU time: the CPU figure is the
one to compare when other processes share the machine):

* ``synchroniser``: the bare :class:`StateSynchronizer` (samples in available-time order);
* ``host pipeline``: stream generators with ordered policies -> asynchronous delivery through
  the :class:`KnowledgeProcessHost` -> a synchronising knowledge process, advanced every 10 ms.

Run: .venv/bin/python bench/state_sync.py [--seconds S] [--period MS] [--max-delay MS]
"""

from __future__ import annotations

import argparse
import random
import time

from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost, StepContext
from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.sample import Sample
from hdrc3_dyknow.state_sync import State, StateSynchronizer

STREAMS = 10
ADVANCE_MS = 10


def make_input(seconds: float, seed: int) -> list[tuple[int, str, Sample]]:
    """(available time, label, sample) for every stream, sorted by available time."""
    rng = random.Random(seed)
    events = []
    for index in range(STREAMS):
        label = f"feature{index}"
        period = 10 + 10 * index
        for valid in range(0, int(seconds * 1000), period):
            if rng.random() < 0.01:
                continue  # a dropout
            available = valid + rng.randint(0, 60)
            events.append((available, label, Sample(valid, available, rng.uniform(-1.0, 1.0))))
    events.sort(key=lambda event: (event[0], event[1]))
    return events


def bare(
    events: list[tuple[int, str, Sample]], period: int, delay: int
) -> tuple[int, float, float]:
    labels = [f"feature{i}" for i in range(STREAMS)]
    sync = StateSynchronizer(labels, period, delay)
    states = 0
    start, cpu = time.perf_counter(), time.process_time()
    next_advance = 0
    for available, label, sample in events:
        while next_advance <= available:
            states += len(sync.advance(next_advance))
            next_advance += ADVANCE_MS
        sync.update(label, sample)
    states += len(sync.advance(next_advance + delay + period))
    return states, time.perf_counter() - start, time.process_time() - cpu


class Collector:
    """Knowledge process: synchronise every input into states and count them."""

    def __init__(self, sync: StateSynchronizer) -> None:
        self.sync = sync
        self.states: list[State] = []

    def step(self, ctx: StepContext) -> None:
        """Feed new samples to the synchroniser and keep the states it emits."""
        for label, samples in ctx.inputs.items():
            for sample in samples:
                self.sync.update(label, sample)
        self.states.extend(self.sync.advance(ctx.now))


def pipeline(
    events: list[tuple[int, str, Sample]], period: int, delay: int
) -> tuple[int, float, float]:
    labels = [f"feature{i}" for i in range(STREAMS)]
    host = KnowledgeProcessHost()
    for label in labels:
        host.declare(label, Policy(max_delay_ms=delay))
    collector = Collector(StateSynchronizer(labels, period, delay))
    host.add_process("sync", collector, dict.fromkeys(labels, Policy()))
    start, cpu = time.perf_counter(), time.process_time()
    next_advance = 0
    for available, label, sample in events:
        while next_advance <= available:
            host.advance(next_advance)
            next_advance += ADVANCE_MS
        host.publish(label, sample)
    host.advance(next_advance + delay + period)
    return len(collector.states), time.perf_counter() - start, time.process_time() - cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=600.0, help="simulated seconds")
    parser.add_argument("--period", type=int, default=20, help="state period (ms)")
    parser.add_argument("--max-delay", type=int, default=80, help="wait for late samples (ms)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    events = make_input(args.seconds, args.seed)
    print(
        f"input: {STREAMS} streams, {len(events)} samples over {args.seconds:g} s simulated;"
        f" state period {args.period} ms, max delay {args.max_delay} ms"
    )
    for name, run in (("synchroniser", bare), ("host pipeline", pipeline)):
        states, wall, cpu = run(events, args.period, args.max_delay)
        print(
            f"{name:14s}: {states} states in {wall:.3f} s wall / {cpu:.3f} s CPU ->"
            f" {states / wall:,.0f} states/s wall, {states / cpu:,.0f} states/s CPU"
            f" ({len(events) / cpu:,.0f} samples/s CPU, {args.seconds / wall:,.0f}x real time)"
        )


if __name__ == "__main__":
    main()
