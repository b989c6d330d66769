"""Whole-stack speed: sim seconds per wall second of `hdrc3 demo` and of a bounded mission leg I.

Each case launches the real stack through the real CLI on a private ROS domain, with recording on:
- ``demo``: ``hdrc3 demo --basic`` (one RMAX: take-off, fly-to, survey, landing), run to the end;
- ``leg1``: ``hdrc3 tst run examples/tst/leg1_scan.tst --launch --agents uav0,uav1 --speed max``
  (two RMAXes, cameras, saliency), stopped with SIGINT once ``--leg1-seconds`` of sim time passed
  (a /clock subscriber of this process watches; it adds one reader to a topic that has several).

Figures come from the recording: the first and last ``/clock`` message give the sim time flown and
the wall time it took (their log times), so start-up and the report are not counted; the total wall
time of the command is printed too. Per process, the CPU seconds it used per sim second (psutil,
sampled every second over the command's process tree, from the first /clock on so that start-up
imports are not counted) are the costs; the largest are listed. For leg I also the images per sim
second and agent (``camera_info`` is published with every image) and the saliency pairs processed
(``saliency/pair_result``, one per thermal image).

The machine is shared: the load average before and after is printed with the figures.

Run: .venv/bin/python bench/mission.py [--case demo|leg1|all] [--leg1-seconds 120]
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter, defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import psutil
import rclpy
from rclpy.context import Context
from rclpy.experimental.events_executor import EventsExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock

from hdrc3.mcap_recording import RecordingReader
from hdrc3_base.stamps import stamp_s

HDRC3 = str(Path(sys.executable).parent / "hdrc3")
ROOT = Path(__file__).resolve().parent.parent
DOMAIN_ID = int(os.environ.get("HDRC3_BENCH_DOMAIN", "141"))
TIMEOUT_S = 3600.0


@dataclass
class Run:
    """What one case measured."""

    name: str
    returncode: int
    total_wall_s: float
    sim_s: float = 0.0
    flight_wall_s: float = 0.0
    cpu_s: dict[str, float] = field(default_factory=dict)
    counts: Counter[str] = field(default_factory=Counter)
    load: tuple[str, str] = ("", "")

    @property
    def factor(self) -> float:
        """Sim seconds per wall second between the first and the last recorded /clock."""
        return self.sim_s / self.flight_wall_s if self.flight_wall_s > 0 else float("nan")


def _label(proc: psutil.Process) -> str:
    """A short name: the console script plus the agent namespace, if any."""
    try:
        args = proc.cmdline()
    except psutil.Error:
        return "?"
    script = next((Path(a).name for a in args if "/bin/" in a and "python" not in a), "?")
    if script == "hdrc3" and len(args) > 2:
        script = f"hdrc3 {args[2]}"
    ns = next((a.split(":=/")[1] for a in args if a.startswith("__ns:=/")), "")
    return f"{ns}/{script}" if ns else script


class TreeCpu:
    """Samples the CPU time of every process of a tree (a process's last sample counts)."""

    def __init__(self, root: int) -> None:
        """Watch the tree under pid ``root``."""
        self.root = psutil.Process(root)
        self.last: dict[int, tuple[str, float]] = {}
        self.start: dict[int, float] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True)
        self._thread.start()

    def _loop(self) -> None:
        while not self._stop.wait(1.0):
            self.sample()

    def sample(self) -> None:
        """Take one sample of every live process of the tree."""
        try:
            procs = [self.root, *self.root.children(recursive=True)]
        except psutil.Error:
            return
        for p in procs:
            try:
                t = p.cpu_times()
                # labelled at every sample: a child seen between fork and exec has its
                # parent's command line
                self.last[p.pid] = (_label(p), t.user + t.system)
            except psutil.Error:
                continue

    def mark(self) -> None:
        """Count CPU from now on (called at the first /clock: start-up imports excluded)."""
        self.sample()
        self.start = {pid: cpu for pid, (_, cpu) in self.last.items()}

    def stop(self) -> dict[str, float]:
        """Stop sampling; CPU seconds per process label since :meth:`mark` (labels summed)."""
        self._stop.set()
        self._thread.join()
        out: dict[str, float] = defaultdict(float)
        for pid, (name, cpu) in self.last.items():
            out[name] += cpu - self.start.get(pid, 0.0)
        return dict(out)


class ClockWatch:
    """Subscribes to /clock on the case's domain and sets ``reached`` at a sim time."""

    def __init__(self, domain_id: int, until_s: float) -> None:
        """Watch ``/clock`` until it reads ``until_s`` s past the first message seen."""
        self.reached = threading.Event()
        self.started = threading.Event()
        self._until = until_s
        self._first: float | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._spin, args=(domain_id,), daemon=True)
        self._thread.start()

    def _spin(self, domain_id: int) -> None:
        context = Context()
        rclpy.init(context=context, domain_id=domain_id)
        node = rclpy.create_node("bench_mission_clock", context=context)
        qos = QoSProfile(
            depth=1,
            reliability=ReliabilityPolicy.RELIABLE,
            durability=DurabilityPolicy.TRANSIENT_LOCAL,
        )
        node.create_subscription(Clock, "/clock", self._on_clock, qos)
        executor = EventsExecutor(context=context)
        executor.add_node(node)
        while not self._stop.is_set():
            executor.spin_once(timeout_sec=0.2)
        executor.shutdown()
        node.destroy_node()
        context.try_shutdown()

    def _on_clock(self, msg: Clock) -> None:
        t = stamp_s(msg.clock)
        if self._first is None:
            self._first = t
            self.started.set()
        if t - self._first >= self._until:
            self.reached.set()

    def close(self) -> None:
        """Stop the subscriber."""
        self._stop.set()
        self._thread.join()


def run_case(name: str, command: list[str], recording: Path, until_s: float | None) -> Run:
    """Run ``command`` (SIGINT after ``until_s`` sim s if given); measure it and its recording."""
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", PYTHONUNBUFFERED="1")
    load_before = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"$ {' '.join(command)}", flush=True)
    start = time.monotonic()
    with tempfile.TemporaryFile("w+") as log:
        proc = subprocess.Popen(command, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT)
        cpu = TreeCpu(proc.pid)
        watch = ClockWatch(DOMAIN_ID, math.inf if until_s is None else until_s)
        try:
            marked = False
            while proc.poll() is None and time.monotonic() - start < TIMEOUT_S:
                if not marked and watch.started.is_set():
                    cpu.mark()
                    marked = True
                if watch.reached.wait(0.5):
                    proc.send_signal(signal.SIGINT)
                    break
            code = proc.wait(timeout=TIMEOUT_S)
        finally:
            if proc.poll() is None:
                proc.kill()
            watch.close()
        total = time.monotonic() - start
        costs = cpu.stop()
        log.seek(0)
        tail = log.read().splitlines()[-25:]
    load_after = " ".join(f"{x:.2f}" for x in os.getloadavg())
    result = Run(name, code, total, cpu_s=costs, load=(load_before, load_after))
    if not recording.is_file():
        print("\n".join(tail))
        return result
    first = last = None
    for m in RecordingReader.open(recording).messages():
        result.counts[m.topic] += 1
        if m.topic == "/clock":
            c = deserialize_message(m.data, Clock).clock
            sample = (stamp_s(c), m.log_time_ns * 1e-9)
            first = first or sample
            last = sample
    if first is not None and last is not None:
        result.sim_s = last[0] - first[0]
        result.flight_wall_s = last[1] - first[1]
    if code not in (0, -signal.SIGINT) and until_s is None:
        print("\n".join(tail))
    return result


def report(run: Run, top: int) -> None:
    """Print the figures of one case."""
    print(f"== {run.name}: exit {run.returncode}, load average {run.load[0]} -> {run.load[1]}")
    print(
        f"sim {run.sim_s:.1f} s in {run.flight_wall_s:.1f} s wall (first to last /clock):"
        f" {run.factor:.2f} sim s / wall s; whole command {run.total_wall_s:.1f} s wall"
    )
    clocks = run.counts.get("/clock", 0)
    print(f"/clock messages recorded: {clocks} of {run.sim_s * 50 + 1:.0f} ticks")
    if run.sim_s > 0:
        print(
            f"CPU s per sim s, top {top} processes (sum over all: "
            f"{sum(run.cpu_s.values()) / run.sim_s:.3f}):"
        )
        for name, cpu in sorted(run.cpu_s.items(), key=lambda kv: -kv[1])[:top]:
            print(f"  {cpu / run.sim_s:7.3f}  {name}")
        images = {t: n for t, n in run.counts.items() if t.endswith("/camera_info")}
        for topic, n in sorted(images.items()):
            print(f"  images {topic}: {n / run.sim_s:.1f} per sim s")
        pairs = {t: n for t, n in run.counts.items() if t.endswith("saliency/pair_result")}
        for topic, n in sorted(pairs.items()):
            print(f"  saliency pairs {topic}: {n / run.sim_s:.1f} per sim s")
    print(flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=("demo", "leg1", "all"), default="demo")
    parser.add_argument("--leg1-seconds", type=float, default=120.0, help="sim s of leg I")
    parser.add_argument("--top", type=int, default=8, help="processes listed per case")
    parser.add_argument("--out", default=None, help="keep the outputs here (default: temp dir)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(args.out) if args.out else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        domain = ["--domain-id", str(DOMAIN_ID)]
        if args.case in ("demo", "all"):
            cmd = [HDRC3, "demo", "--basic", "--out", str(out / "demo"), *domain]
            report(run_case("hdrc3 demo", cmd, out / "demo" / "run.mcap", None), args.top)
        if args.case in ("leg1", "all"):
            cmd = [HDRC3, "tst", "run", "examples/tst/leg1_scan.tst", "--launch"]
            cmd += ["--agents", "uav0,uav1", "--world", "revinge", "--speed", "max"]
            cmd += ["--out", str(out / "leg1"), *domain]
            name = f"leg I, first {args.leg1_seconds:.0f} sim s"
            report(run_case(name, cmd, out / "leg1" / "run.mcap", args.leg1_seconds), args.top)
    print(f"{os.cpu_count()} cores")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
