"""Benchmark executor overhead: parent start -> child executor running (issue 12 target).

Same agent: the engine in-process on the fake platform; the time from ``execute(root)`` to each
child's RUNNING status, for a concurrent root over 10 ``wait`` children. Across agents: two real
``tst_manager`` processes (``hdrc3 launch --nodes tst_manager``, DDS on loopback); the root (a
sequence on uav0) starts a ``wait`` child held by uav1; the figure is the wall time between the
arrival, at one client, of the root's RUNNING status and of the child's (one service call from
uav0 to uav1 and one status hop more). Target: p99 <= 20 ms wall. The CPU time of the
in-process start is printed too: on a loaded machine the wall figures are mostly waiting for a
core (print the load average beside them). Sim time is not advanced in
either case (the overhead is a wall-clock cost); the in-process engine sees the same sim time.

Usage: .venv/bin/python bench/tst_executors.py [--runs 200] [--domain-id 88]
"""

from __future__ import annotations

import argparse
import gc
import os
import statistics
import time
from typing import Any

from hdrc3.launched_system import LaunchedSystem
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.check import load_text
from hdrc3_tst.engine import EngineContext, ExecutionEngine, NodeRecord
from hdrc3_tst.fake_platform import FakePlanner, FakePlatform, RecordingSink
from hdrc3_tst.mission_client import TstClient
from hdrc3_tst.model import NodeState
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS

HEAD = "world revinge\nagents uav0, uav1\n"
LOCAL = HEAD + (
    "m(P, TS, TE) = concurrent\n"
    + ";\n".join(f"  c{i}(T{i}a, T{i}b) = wait(T{i}a, T{i}b, 0)" for i in range(10))
    + "\nwhere P = uav0\n"
)
REMOTE = HEAD + (
    "m(P, TS, TE) = with P2, T1, T2 sequence\n"
    "  c(P2, T1, T2) = wait(T1, T2, 0)\n"
    "where P = uav0 and P2 = uav1\n"
)


def pct(values: list[float], q: float) -> float:
    """The q-quantile (0..1) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def line(label: str, ms: list[float]) -> str:
    """Median, p99 and max of ``ms``."""
    return (
        f"  {label:<34} n={len(ms):4d}  median {statistics.median(ms):7.3f} ms  "
        f"p99 {pct(ms, 0.99):7.3f} ms  max {max(ms):7.3f} ms"
    )


class _TimedSink(RecordingSink):
    def __init__(self) -> None:
        super().__init__()
        self.running_at: dict[str, float] = {}

    def status(self, record: NodeRecord) -> None:
        if record.state is NodeState.RUNNING:
            self.running_at.setdefault(record.node_id, time.perf_counter())
        super().status(record)


def same_agent(runs: int) -> tuple[list[float], list[float]]:
    """Wall ms from execute(root) to each child running, and CPU ms of each execute."""
    frame = frame_from_world("revinge")
    out: list[float] = []
    cpu: list[float] = []
    for _ in range(runs):
        tst = load_text(LOCAL).tst
        assert tst is not None
        sink = _TimedSink()
        ctx = EngineContext("uav0", FakePlatform(), FakePlanner(), sink, frame, RMAX_EXECUTORS)
        engine = ExecutionEngine("b", tst, ctx)
        gc.collect()  # the garbage of loading the mission is the create's cost, as in the node
        start, cpu_start = time.perf_counter(), time.process_time()
        engine.execute("m", 0.0, 0.0)
        cpu.append((time.process_time() - cpu_start) * 1e3)
        out += [(sink.running_at[f"c{i}"] - start) * 1e3 for i in range(10)]
    return out, cpu


def across_agents(runs: int, domain_id: int) -> list[float]:
    """Wall ms between the root's and the remote child's RUNNING statuses at one client."""
    arrivals: dict[tuple[str, str], float] = {}

    def on_status(msg: Any) -> None:
        if msg.state == NodeState.RUNNING.value:
            arrivals.setdefault((msg.mission, msg.node_id), time.perf_counter())

    out: list[float] = []
    system = LaunchedSystem(
        ("uav0", "uav1"), "revinge", "max", domain_id, nodes=("tst_manager",), log=lambda s: None
    )
    with system, RosProcess() as process:
        client = TstClient(process, on_status=on_status)
        for agent in ("uav0", "uav1"):
            client.follow(agent)
            topic = f"/{agent}/tst_status"
            matched = process.spin_until(lambda t=topic: client.node.count_publishers(t) > 0, 30.0)
            assert matched, f"no publisher of {topic}"
        for run in range(-1, runs):  # run -1 warms up (first service calls, discovery)
            mission = f"b{run}"
            created = client.create(mission, REMOTE, "bench.tst", ("uav0", "uav1"))
            assert created.ok, created.replies
            assert client.execute(mission, "uav0", "m").ok
            done = process.spin_until(lambda m=mission: (m, "c") in arrivals, 10.0)
            assert done and (mission, "m") in arrivals, f"run {run}: no statuses"
            if run >= 0:
                out.append((arrivals[(mission, "c")] - arrivals[(mission, "m")]) * 1e3)
    return out


def main() -> None:
    """Print the figures."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--domain-id", type=int, default=88)
    args = ap.parse_args()
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    print(f"executor overhead: parent start -> child running (target p99 <= 20 ms); load {load}")
    wall, cpu = same_agent(args.runs)
    print(line("same agent (in-process engine)", wall))
    print(line("  CPU of starting root + 10 children", cpu), flush=True)
    print(line("across agents (2 tst_manager, DDS)", across_agents(args.runs, args.domain_id)))


if __name__ == "__main__":
    main()
