"""`hdrc3 launch` end to end: READY, diagnostics, restart on crash, clean stop, recording."""

from __future__ import annotations

import os
import signal
import time
from collections import Counter
from pathlib import Path

import pytest
from diagnostic_msgs.msg import DiagnosticArray
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from hdrc3.mcap_recording import RecordingReader
from hdrc3_base.errors import DataError
from hdrc3_base.ros_runtime import STATUS_QOS, STATUS_TOPIC
from hdrc3_interfaces.msg import LaunchStatus, SupervisedProcess

pytestmark = pytest.mark.ros


def _spin_until(executor: SingleThreadedExecutor, predicate, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            return False
        executor.spin_once(timeout_sec=0.1)
    return True


def _flushed(path: Path) -> Counter[str]:
    """Messages per topic in the chunks a running recorder has flushed to ``path`` so far."""
    try:
        return Counter(m.topic for m in RecordingReader.open(path).messages())
    except DataError:  # not created yet, or a chunk read while it is being written
        return Counter()


def test_launch_records_supervises_and_stops_cleanly(hdrc3_cli, ros_context, tmp_path: Path):
    out = tmp_path / "run.mcap"
    launch = hdrc3_cli("launch", "--nodes", "system_monitor", "--record", str(out))
    launch.wait_for_line("READY", timeout=60)

    node = Node("observer", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    statuses: list[LaunchStatus] = []
    diagnostics: list[DiagnosticArray] = []
    node.create_subscription(LaunchStatus, STATUS_TOPIC, statuses.append, STATUS_QOS)
    node.create_subscription(DiagnosticArray, "/diagnostics", diagnostics.append, 10)

    def monitor_entry(level: int):
        for array in reversed(diagnostics):
            for status in array.status:
                if status.name == "hdrc3/system_monitor" and status.level == bytes([level]):
                    return status
        return None

    assert _spin_until(executor, lambda: monitor_entry(0) is not None, 20), diagnostics[-1:]
    pid = dict((v.key, v.value) for v in monitor_entry(0).values)["pid"]

    # A crashed node is reported and restarted.
    os.kill(int(pid), signal.SIGKILL)

    def restarted() -> bool:
        return any(
            p.name == "system_monitor"
            and p.restarts == 1
            and p.state == SupervisedProcess.STATE_RUNNING
            for s in statuses[-1:]
            for p in s.processes
        )

    assert _spin_until(executor, restarted, 20), statuses[-1:]
    launch.wait_for_line("system_monitor: restarted (restart 1)")

    # The recorder is a reader of its own: what this test received says nothing about what it
    # wrote (it may have subscribed after the first diagnostics). Wait for the file to show it.
    def recorded() -> bool:
        counts = _flushed(out)
        return counts["/diagnostics"] >= 1 and counts[STATUS_TOPIC] >= 2

    assert _spin_until(executor, recorded, 30), _flushed(out)
    node.destroy_node()

    # The supervisor signals, then kills, every node within its 4.5 s budget; how long the
    # launcher's own exit takes depends on the machine's load, so the bound is only a hang guard.
    assert launch.interrupt() == 0
    assert "stopped" in launch.lines

    # An independent reader decodes every message with the embedded schemas.
    counts: Counter[str] = Counter()
    with out.open("rb") as stream:
        for _, channel, _, decoded in make_reader(
            stream, decoder_factories=[DecoderFactory()]
        ).iter_decoded_messages():
            assert decoded is not None
            counts[channel.topic] += 1
    assert counts["/diagnostics"] >= 1
    assert counts[STATUS_TOPIC] >= 2


def test_second_launch_on_the_same_domain_is_refused(hdrc3_cli):
    first = hdrc3_cli("launch", "--agents", "uav0", "--nodes", "system_monitor")
    first.wait_for_line("READY", timeout=60)
    second = hdrc3_cli("launch", "--agents", "uav0", "--nodes", "system_monitor")
    assert second.finish(timeout=30) == 2
    assert any("already runs /" in line for line in second.lines), second.lines
    assert first.interrupt() == 0


def test_launches_started_together_leave_only_the_older_running(hdrc3_cli):
    launches = [hdrc3_cli("launch", "--agents", "uav0", "--nodes", "system_monitor") for _ in "ab"]
    deadline = time.monotonic() + 60
    while all(launch.proc.poll() is None for launch in launches):
        assert time.monotonic() < deadline, "both launches still run the same nodes"
        for launch in launches:
            launch.poll_output(0.1)
    survivors = [launch for launch in launches if launch.proc.poll() is None]
    assert len(survivors) == 1
    for launch in launches:
        if launch in survivors:
            launch.wait_for_line("READY", timeout=60)
            assert launch.interrupt() == 0
        else:
            assert launch.finish() == 2
            assert any("already runs /system_monitor" in line for line in launch.lines)
