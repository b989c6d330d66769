"""What the live view costs a running one-agent system, and the pose rate a client sees.

Starts ``hdrc3 launch`` with world_sim, control_kernel and platform_server for one agent (no live
view) on its own ROS domain and measures the CPU of its process tree over ``--window`` seconds.
Then starts ``hdrc3 live``, connects a Foxglove WebSocket client subscribed to every live channel
and measures, over the same window: the live view's own CPU, the system's CPU, and the rate of
``/live/tf`` messages arriving at the client. CPU is given in % of one core and in % of the
machine (all cores). Targets (issue 19): <= 10 % CPU added, 25 Hz poses.

``--cameras`` adds world_render to the system and keeps both cameras of uav0 rendering through
both windows (this process subscribes to their images, as an engaged saliency node would): the
renderer draws only while an image topic has a subscriber, so without that the second window
would also count the rendering that the client's subscription starts. The client then also
subscribes to the agent's camera channels, and their rates and bytes are reported.

Run: .venv/bin/python bench/live_view.py [--window 20] [--domain-id 97] [--speed 1] [--cameras]
"""

from __future__ import annotations

import argparse
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections import Counter
from pathlib import Path

import psutil
import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Image

from hdrc3.live.channels import CHANNELS, STATIC_CHANNEL_NAMES
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


class GraphSink:
    """Follows sim time and counts uav0's camera images (raw, in a thread): keeps them rendered.

    The simulator is lockstep (it waits for the controllers) and repeats a stalled tick's
    messages, so message rates are no measure of its speed; sim seconds per wall second are.
    """

    def __init__(self, domain_id: int, cameras: bool) -> None:
        self.context = Context()
        rclpy.init(context=self.context, domain_id=domain_id)
        self.node = Node("bench_sink", context=self.context)
        self.images = 0
        self.sim_ns = 0

        def on_image(data: bytes) -> None:
            self.images += 1

        def on_clock(msg: Clock) -> None:
            self.sim_ns = msg.clock.sec * 1_000_000_000 + msg.clock.nanosec

        for kind in ("color", "thermal") if cameras else ():
            self.node.create_subscription(
                Image, f"/uav0/camera/{kind}/image_raw", on_image, qos_profile_sensor_data, raw=True
            )
        self.node.create_subscription(Clock, "/clock", on_clock, qos_profile_sensor_data)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def close(self) -> None:
        """Stop spinning and leave the graph."""
        self.executor.shutdown()
        self.node.destroy_node()
        self.context.try_shutdown()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--window", type=float, default=20.0, help="seconds per measurement")
    parser.add_argument("--domain-id", default="97")
    parser.add_argument("--speed", default="1")
    parser.add_argument("--cameras", action="store_true", help="with world_render, see above")
    parser.add_argument(
        "--no-camera-channels", action="store_true",
        help="with --cameras: the client does not subscribe to the camera channels",
    )  # fmt: skip
    args = parser.parse_args()
    os.environ.update(ROS_DOMAIN_ID=args.domain_id, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    env = dict(os.environ)
    cores = psutil.cpu_count() or 1
    nodes = "world_sim,control_kernel,platform_server" + ",world_render" * args.cameras
    system = start(
        ["launch", "--agents", "uav0", "--speed", args.speed, "--nodes", nodes],
        env, "READY", 180,
    )  # fmt: skip
    live = None
    sink = GraphSink(int(args.domain_id), args.cameras)
    watch = args.cameras and not args.no_camera_channels
    cameras = {c.instance("uav0") for c in CHANNELS if c.per_agent} if watch else set()
    counts: Counter[str] = Counter()
    sizes: Counter[str] = Counter()
    try:
        procs = tree(system.pid)
        time.sleep(3.0)  # let the nodes settle after READY before measuring
        images, sim_ns = sink.images, sink.sim_ns
        before = cpu_seconds(procs)
        time.sleep(args.window)
        base = (cpu_seconds(procs) - before) / args.window * 100
        rendered = (sink.images - images) / args.window
        speed_base = (sink.sim_ns - sim_ns) / 1e9 / args.window

        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        live = start(["live", "--port", str(port)], env, "live view:", 60)
        with FoxgloveProbe(f"ws://127.0.0.1:{port}") as client:
            if not client.wait_for_channels({*STATIC_CHANNEL_NAMES, *cameras}, 20):
                raise SystemExit("channels not advertised within 20 s")
            client.subscribe([*STATIC_CHANNEL_NAMES, *cameras])
            while (f := client.receive(10)) is not None and f.topic != "/live/tf":
                pass
            live_procs = tree(live.pid)
            live_before, sys_before = cpu_seconds(live_procs), cpu_seconds(procs)
            images, sim_ns = sink.images, sink.sim_ns
            start_t = time.monotonic()
            while (now := time.monotonic()) < start_t + args.window:
                frame = client.receive(start_t + args.window - now)
                if frame is not None:
                    counts[frame.topic] += 1
                    sizes[frame.topic] += len(frame.data)
            poses = counts["/live/tf"]
            elapsed = time.monotonic() - start_t
            speed_live = (sink.sim_ns - sim_ns) / 1e9 / elapsed
            rendered_live = (sink.images - images) / elapsed
            live_cpu = (cpu_seconds(live_procs) - live_before) / elapsed * 100
            with_live = (cpu_seconds(procs) - sys_before) / elapsed * 100
    finally:
        sink.close()
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
    print(f"sim speed (sim s per wall s) without / with: {speed_base:4.2f} / {speed_live:4.2f}")
    if args.cameras:
        print(
            f"images rendered (both cameras) without / with: "
            f"{rendered:5.1f} / {rendered_live:5.1f} Hz"
        )
    for topic in sorted(cameras):
        n = counts[topic]
        size = sizes[topic] / n / 1000 if n else 0.0
        print(f"{topic}: {n / elapsed:4.1f} Hz at the client, {size:5.1f} kB per image")


if __name__ == "__main__":
    main()
