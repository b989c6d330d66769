"""CI replay test: record a short scenario to MCAP, replay it, check what a subscriber receives."""

from __future__ import annotations

from pathlib import Path

import pytest
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy

from hdrc3.mcap_recording import RecordingReader
from hdrc3_interfaces.msg import HelicopterState
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros
TOPIC = "/uav0/helicopter_state"
COUNT = 25
# keep every sample of the burst until the recorder has acknowledged it: a shallower keep-last
# history drops unacknowledged samples when the recorder is slow to read on a loaded machine
BURST_QOS = QoSProfile(depth=COUNT, reliability=ReliabilityPolicy.RELIABLE)


def test_record_then_replay_delivers_the_same_messages(hdrc3_cli, ros_context, tmp_path: Path):
    out = tmp_path / "scenario.mcap"
    node = Node("scenario", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    publisher = node.create_publisher(HelicopterState, TOPIC, BURST_QOS)

    recorder = hdrc3_cli("record", str(out), "--topics", TOPIC)
    assert spin_until(executor, lambda: publisher.get_subscription_count() > 0, 30)
    for i in range(COUNT):
        publisher.publish(HelicopterState(altitude=100.0 + i, on_ground_flag=i == 0))
    assert publisher.wait_for_all_acked(Duration(seconds=10))
    assert recorder.interrupt() == 0
    assert f"recorded {COUNT} messages on 1 topics to {out}" in recorder.lines

    recorded = list(RecordingReader.open(out).messages())
    assert len(recorded) == COUNT

    received: list[HelicopterState] = []
    node.create_subscription(HelicopterState, TOPIC, received.append, 100)
    node.destroy_publisher(publisher)
    replay = hdrc3_cli("replay", str(out), "--speed", "4", "--wait-for-subscribers", "30")
    assert spin_until(executor, lambda: len(received) == COUNT, 30), len(received)
    assert replay.finish() == 0
    assert [m.altitude for m in received] == [100.0 + i for i in range(COUNT)]
    assert [m.on_ground_flag for m in received[:2]] == [True, False]
    assert f"replayed {COUNT} messages on 1 topics" in replay.lines
    node.destroy_node()


def test_record_fails_on_a_topic_that_never_appears(hdrc3_cli, tmp_path: Path):
    out = tmp_path / "empty.mcap"
    recorder = hdrc3_cli("record", str(out), "--topics", "/no/such/topic", "--wait-topics", "1")
    assert recorder.finish(timeout=30) == 2
    assert "hdrc3 record: error: topic(s) not found: /no/such/topic" in recorder.lines
    assert RecordingReader.open(out).topics() == {}
