"""What the live view costs a running one-agent system, and the pose rate a client sees.

Starts ``hdrc3 launch`` with world_sim, control_kernel and platform_server for one agent (no live
view) on its own ROS domain and measures the CPU of its process tree over ``--window`` seconds.
Then starts ``hdrc3 live``, connects a Foxglove WebSocket client subscribed to every live channel
and measures, over the same window: the live view's own CPU, the system's CPU, and the rate of
``/live/tf`` messages arriving at the client. CPU is given in % of one core and in % of the
machine (all cores). Targets (issue 19): <= 10 % CPU added, 25 Hz poses.

Run: .venv/bin/python bench/live_view.py [--window 20] [--domain-id 97] [--speed 1]
"""

from __future__ import annotations

import argparse
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import psutil

from hdrc3.live.channels import CHANNEL_NAMES
from hdrc3.live.probe import FoxgloveProbe

HDRC3 = str(Path(sys.executable).parent / "hdrc3")


def start(
    args: list[str], env: dict[str, str], needle: str, timeout: float
) -> subprocess.Popen[str]:
    """Start ``hdrc3 args`` and wait for a line containing ``needle``."""
    proc = subprocess.Popen(
        [HDRC3, *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
        start_new_session=True,
    )  # fmt: skip
    assert proc.stdout is not None
    deadline = time.monotonic() + timeout
    for line in proc.stdout:
        if needle in line:
            return proc
        if time.monotonic() > deadline:
            break
    os.killpg(proc.pid, signal.SIGKILL)
    raise SystemExit(f"hdrc3 {' '.join(args)}: no {needle!r} within {timeout} s")


def tree(pid: int) -> list[psutil.Process]:
    root = psutil.Process(pid)
    return [root, *root.children(recursive=True)]


def cpu_seconds(procs: list[psutil.Process]) -> float:
    total = 0.0
    for p in procs:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--window", type=float, default=20.0, help="seconds per measurement")
    parser.add_argument("--domain-id", default="97")
    parser.add_argument("--speed", default="1")
    args = parser.parse_args()
    env = dict(os.environ, ROS_DOMAIN_ID=args.domain_id, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    cores = psutil.cpu_count() or 1
    system = start(
        ["launch", "--agents", "uav0", "--speed", args.speed,
         "--nodes", "world_sim,control_kernel,platform_server"],
        env, "READY", 180,
    )  # fmt: skip
    live = None
    try:
        procs = tree(system.pid)
        time.sleep(3.0)  # let the nodes settle after READY before measuring
        before = cpu_seconds(procs)
        time.sleep(args.window)
        base = (cpu_seconds(procs) - before) / args.window * 100

        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        live = start(["live", "--port", str(port)], env, "live view:", 60)
        with FoxgloveProbe(f"ws://127.0.0.1:{port}") as client:
            if not client.wait_for_channels(set(CHANNEL_NAMES), 20):
                raise SystemExit("channels not advertised within 20 s")
            client.subscribe(list(CHANNEL_NAMES))
            while (f := client.receive(10)) is not None and f.topic != "/live/tf":
                pass
            live_procs = tree(live.pid)
            live_before, sys_before = cpu_seconds(live_procs), cpu_seconds(procs)
            start_t = time.monotonic()
            poses = 0
            while (now := time.monotonic()) < start_t + args.window:
                frame = client.receive(start_t + args.window - now)
                poses += frame is not None and frame.topic == "/live/tf"
            elapsed = time.monotonic() - start_t
            live_cpu = (cpu_seconds(live_procs) - live_before) / elapsed * 100
            with_live = (cpu_seconds(procs) - sys_before) / elapsed * 100
    finally:
        for proc in (live, system):
            if proc is not None and proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
                proc.wait(timeout=30)
    print(f"machine: {cores} cores; window {args.window:.0f} s; --speed {args.speed}")
    print(f"system without live view: {base:6.1f} % of one core ({base / cores:5.1f} % machine)")
    print(f"system with live view:    {with_live:6.1f} % of one core")
    machine = live_cpu / cores
    print(f"live view process:        {live_cpu:6.1f} % of one core ({machine:5.1f} % machine)")
    print(f"pose updates at the client: {poses / elapsed:5.1f} Hz ({poses} in {elapsed:.1f} s)")


if __name__ == "__main__":
    main()
