"""`hdrc3 demo`: the main job: launch a system, record it, stop it, summarise the recording."""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

from hdrc3.errors import ConfigError
from hdrc3.mcap_recording import RecordingReader

READY_TIMEOUT_S = 120.0


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `demo` subcommand."""
    parser = subparsers.add_parser("demo", help="run the demo mission and summarise it")
    parser.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    parser.add_argument("--duration", type=float, default=5.0, help="seconds to run (default 5)")
    parser.add_argument("--domain-id", type=int, default=42, help="ROS domain (default 42)")
    parser.set_defaults(handler=run)


def _wait_ready(launch: subprocess.Popen[str]) -> None:
    assert launch.stdout is not None
    deadline = time.monotonic() + READY_TIMEOUT_S
    for line in launch.stdout:
        print(f"  | {line.rstrip()}")
        if "READY" in line:
            return
        if time.monotonic() > deadline:
            break
    launch.kill()
    raise ConfigError("the system did not come up; see the launcher output above")


def run(args: argparse.Namespace) -> int:
    """Launch one agent with recording, let it run, stop it and print a summary."""
    if not args.duration > 0:
        raise ConfigError(f"--duration must be positive, got {args.duration}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    recording = out / "run.mcap"
    hdrc3 = str(Path(sys.executable).parent / "hdrc3")
    command = [hdrc3, "launch", "--agents", "uav0", "--record", str(recording)]
    command += ["--domain-id", str(args.domain_id)]
    print(f"$ {' '.join(command)}")
    launch = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=dict(os.environ, PYTHONUNBUFFERED="1"),
    )
    _wait_ready(launch)
    deadline = time.monotonic() + args.duration
    while time.monotonic() < deadline and launch.poll() is None:
        time.sleep(0.1)  # wall-clock run length of the demo; nothing to wait on
    launch.send_signal(signal.SIGINT)
    remaining, _ = launch.communicate(timeout=30)
    for line in remaining.splitlines():
        print(f"  | {line}")
    reader = RecordingReader.open(recording)
    counts = Counter(m.topic for m in reader.messages())
    print(f"\nrecording: {recording} ({recording.stat().st_size} bytes)")
    for topic, count in sorted(counts.items()):
        print(f"  {count:6d}  {topic}  [{reader.topics()[topic]}]")
    return launch.returncode
