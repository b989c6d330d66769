"""Replay of an MCAP recording: publishers per topic, original timing scaled by a speed factor."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Sequence

from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from hdrc3.mcap_recording import RecordedMessage
from hdrc3.message_types import message_class
from hdrc3_base.errors import ConfigError

REPLAY_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=100,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)


def select_topics(recorded: dict[str, str], requested: Sequence[str]) -> dict[str, str]:
    """Pick the topics to replay; a requested topic missing from the file is an error."""
    if not requested:
        return dict(recorded)
    missing = [t for t in requested if t not in recorded]
    if missing:
        available = ", ".join(sorted(recorded)) or "(none)"
        raise ConfigError(f"topic {missing[0]} is not in the recording; it has: {available}")
    return {t: recorded[t] for t in requested}


class ReplayerNode(Node):
    """Owns one publisher per replayed topic."""

    def __init__(self, context: Context, topics: dict[str, str]) -> None:
        """Create publishers for ``topics`` (name -> message type)."""
        super().__init__("hdrc3_replayer", context=context)
        self.publishers_by_topic: dict[str, Publisher] = {
            topic: self.create_publisher(message_class(type_name), topic, REPLAY_QOS)
            for topic, type_name in topics.items()
        }

    def all_subscribed(self) -> bool:
        """True when every publisher has at least one matched subscription."""
        return all(p.get_subscription_count() > 0 for p in self.publishers_by_topic.values())

    def wait_for_acknowledgements(self, timeout_s: float) -> bool:
        """Wait until reliable subscribers acknowledged everything published so far."""
        return all(
            p.wait_for_all_acked(Duration(nanoseconds=int(timeout_s * 1e9)))
            for p in self.publishers_by_topic.values()
        )

    def publish(self, message: RecordedMessage) -> None:
        """Publish one recorded message as it was serialised."""
        self.publishers_by_topic[message.topic].publish(message.data)


def paced(
    messages: Iterable[RecordedMessage], speed: float, wait: Callable[[float], bool]
) -> Iterable[RecordedMessage]:
    """Yield messages at their recorded spacing divided by ``speed`` (wall clock).

    Args:
        messages: Recorded messages in log-time order.
        speed: Playback rate; 2.0 plays twice as fast.
        wait: ``wait(seconds) -> bool`` that returns True when playback should stop.

    """
    start_wall: float | None = None
    start_log = 0
    for message in messages:
        if start_wall is None:
            start_wall = time.monotonic()
            start_log = message.log_time_ns
        due = start_wall + (message.log_time_ns - start_log) / 1e9 / speed
        delay = due - time.monotonic()
        if delay > 0 and wait(delay):
            return
        yield message
