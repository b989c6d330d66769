"""Benchmark: Platform Server answer latency, Data Interface rate, lost completion events.

Starts the real ``platform_server`` node and the fake kernels node (FakePfc + FakePpc behind the
real HCSM ROS transport, publishing /clock and pfc/state at 50 Hz of sim time) on a private ROS
domain, then runs N command cycles from an rclpy client over real DDS. Each cycle:
``fcl_yaw`` (-> FCL_OK), a second ``fcl_yaw`` at once (-> FCL_BUSY), ``fcl_climb(NaN)``
(-> FCL_NOT_ACCEPTED), then the client waits for the accepted yaw's terminal PlatformEvent
(the fake PFC yaws for --duration s of sim time, default 0.3).

Figures: service answer latency (wall, request sent -> response received) p50/p99/max per answer
kind; Data Interface rate in sim time over the whole run (helicopter_state pfc_time stamps);
completion events lost (accepted ids without exactly one terminal event).
Targets (issue 6): p99 <= 20 ms; 25 +/- 1 Hz; 0 lost over 1,000 cycles.

Run: .venv/bin/python bench/platform_server.py [--cycles 1000] [--speed 5] [--duration 0.3]
     [--plot out/x.png]
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import signal
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hdrc3_base.stamps import stamp_s

BIN = Path(sys.executable).parent
AGENT = "uav0"


def spawn(args: list[str], env: dict[str, str], log: str | None = None) -> subprocess.Popen[bytes]:
    out = open(log, "wb") if log else subprocess.DEVNULL  # noqa: SIM115
    return subprocess.Popen(
        args,
        stdout=out,
        stderr=subprocess.STDOUT,
        start_new_session=True,
        env=env,
    )


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, math.ceil(q * len(ordered)) - 1)]


class Client:
    """rclpy client: services, platform events, Data Interface stamps."""

    def __init__(self) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node

        from hdrc3_interfaces.msg import HelicopterState, PlatformEvent
        from hdrc3_platform_server.node import EVENT_QOS, STATE_QOS

        rclpy.init()
        self.node: Any = Node("bench_platform_client")
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.terminal: dict[int, int] = {}
        self.finished: set[int] = set()
        self.stamps: list[float] = []
        self.node.create_subscription(
            PlatformEvent, f"/{AGENT}/platform_events", self._on_event, EVENT_QOS
        )
        self.node.create_subscription(
            HelicopterState, f"/{AGENT}/helicopter_state", self._on_state, STATE_QOS
        )
        self.clients: dict[str, Any] = {}

    def _on_event(self, msg: Any) -> None:
        if msg.kind in (0, 1, 2):
            self.terminal[msg.command_id] = self.terminal.get(msg.command_id, 0) + 1
        if msg.kind == 0:
            self.finished.add(msg.command_id)

    def _on_state(self, msg: Any) -> None:
        self.stamps.append(stamp_s(msg.pfc_time))

    def spin_until(self, done: Callable[[], bool], timeout: float) -> bool:
        """Spin until ``done()`` or the wall-clock timeout."""
        deadline = time.monotonic() + timeout
        while not done() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.01)
        return done()

    def call(self, srv: Any, name: str, **fields: Any) -> tuple[Any, float]:
        """Call a service; returns the FclReturn and the wall-clock answer latency."""
        client = self.clients.get(name)
        if client is None:
            client = self.node.create_client(srv, f"/{AGENT}/{name}")
            if not self.spin_until(client.service_is_ready, 30.0):
                raise SystemExit(f"service {name} not available")
            self.clients[name] = client
        request = srv.Request()
        for key, value in fields.items():
            setattr(request, key, value)
        start = time.perf_counter()
        future = client.call_async(request)
        if not self.spin_until(future.done, 10.0):
            raise SystemExit(f"no answer from {name}")
        return future.result().result, time.perf_counter() - start


def run(args: argparse.Namespace) -> int:
    from hdrc3_interfaces.srv import FclClimb, FclTakeoff, FclYaw

    env = dict(os.environ, ROS_DOMAIN_ID=str(args.domain_id))
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ.update(env)
    ns = ["--ros-args", "-r", f"__ns:=/{AGENT}"]
    procs = [
        spawn([str(BIN / "hdrc3-platform-server"), *ns], env),
        spawn(
            [
                sys.executable,
                "-m",
                "hdrc3_platform_server.fake_node",
                *ns,
                "-p",
                f"speed:={args.speed}",
                "-p",
                f"duration:={args.duration}",
            ],
            env,
        ),
    ]
    latencies: dict[str, list[float]] = {"FCL_OK": [], "FCL_BUSY": [], "FCL_NOT_ACCEPTED": []}
    accepted: list[int] = []
    unexpected = 0
    surprises: dict[str, int] = {}
    try:
        c = Client()
        if not c.spin_until(lambda: len(c.stamps) > 5, 60.0):
            raise SystemExit("no Data Interface from the platform server")
        result, _ = c.call(FclTakeoff, "fcl/takeoff")
        deadline = time.monotonic() + 20.0
        while result.code != 0 and time.monotonic() < deadline:  # the DRC may not see the PFC yet
            c.spin_until(lambda: False, 0.5)
            result, _ = c.call(FclTakeoff, "fcl/takeoff")
        if result.code != 0 or not c.spin_until(lambda: result.command_id in c.terminal, 30.0):
            raise SystemExit(f"take-off failed: {result.reason}")
        c.stamps.clear()
        wall0 = time.monotonic()
        for i in range(args.cycles):
            ok, t_ok = c.call(FclYaw, "fcl/yaw", heading=0.1 * (i % 60))
            busy, t_busy = c.call(FclYaw, "fcl/yaw", heading=0.0)
            bad, t_bad = c.call(FclClimb, "fcl/climb", altitude=math.nan)
            for res, lat, want in ((ok, t_ok, 0), (busy, t_busy, 1), (bad, t_bad, 2)):
                if res.code != want:
                    unexpected += 1
                    key = f"expected {want}, got {res.code}: {res.reason[:60]}"
                    surprises[key] = surprises.get(key, 0) + 1
                name = {0: "FCL_OK", 1: "FCL_BUSY", 2: "FCL_NOT_ACCEPTED"}.get(res.code)
                if name is not None:
                    latencies[name].append(lat)
            started = [r.command_id for r in (ok, busy) if r.code == 0]
            accepted += started
            c.spin_until(lambda ids=started: all(cid in c.terminal for cid in ids), 10.0)
        wall = time.monotonic() - wall0
        c.spin_until(lambda: all(cid in c.terminal for cid in accepted), 5.0)
        stamps = list(c.stamps)
    finally:
        for p in procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
        for p in procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
    lost = sum(1 for cid in accepted if c.terminal.get(cid, 0) != 1)
    finished = sum(1 for cid in accepted if cid in c.finished)
    all_lat = [x for v in latencies.values() for x in v]
    span = stamps[-1] - stamps[0] if len(stamps) > 1 else 0.0
    rate = (len(stamps) - 1) / span if span > 0 else 0.0
    gaps = [b - a for a, b in itertools.pairwise(stamps)]
    print(
        f"platform_server benchmark: {args.cycles} cycles, fake kernels at {args.speed:g}x, "
        f"{wall:.1f} s wall"
    )
    for name, values in latencies.items():
        if values:
            print(
                f"  {name:17s} n={len(values):5d}  p50 {1e3 * statistics.median(values):6.2f} ms  "
                f"p99 {1e3 * percentile(values, 0.99):6.2f} ms  max {1e3 * max(values):6.2f} ms"
            )
    print(
        f"  all answers       n={len(all_lat):5d}  p99 {1e3 * percentile(all_lat, 0.99):6.2f} ms"
        f"  (target <= 20 ms)"
    )
    print(f"  unexpected answers: {unexpected}")
    for key, count in sorted(surprises.items(), key=lambda kv: -kv[1])[:5]:
        print(f"    {count:4d} x {key}")
    print(
        f"  Data Interface: {len(stamps)} samples over {span:.2f} s sim time = {rate:.3f} Hz "
        f"(target 25 +/- 1); intervals min {min(gaps):.4f} max {max(gaps):.4f} s"
    )
    print(
        f"  completion events: {len(accepted)} accepted, {finished} FCL_FINISHED, "
        f"{lost} lost (target 0)"
    )
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
        for name, values in latencies.items():
            a1.hist([1e3 * v for v in values], bins=60, alpha=0.6, label=name)
        a1.set_xlabel("service answer latency, ms (wall)")
        a1.set_ylabel("count")
        a1.legend()
        a2.plot(stamps[1:], [1e3 * g for g in gaps], ".", ms=2)
        a2.set_xlabel("sim time, s")
        a2.set_ylabel("DI interval, ms (sim)")
        a2.set_ylim(0.0, 100.0)  # 40 ms expected; a lost sample would show at 80 ms
        fig.tight_layout()
        Path(args.plot).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.plot, dpi=100)
        print(f"  plot: {args.plot}")
    ok = (
        percentile(all_lat, 0.99) <= 0.020
        and abs(rate - 25.0) <= 1.0
        and lost == 0
        and unexpected == 0
    )
    return 0 if ok else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=1000)
    parser.add_argument("--speed", type=float, default=5.0, help="fake kernels' real-time factor")
    parser.add_argument(
        "--duration", type=float, default=0.3, help="sim seconds each fake PFC activity takes"
    )
    parser.add_argument("--domain-id", type=int, default=91)
    parser.add_argument("--plot", default="out/platform_server.png")
    return run(parser.parse_args())


if __name__ == "__main__":
    sys.exit(main())
