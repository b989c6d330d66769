"""The recorder node: subscribes to topics as raw CDR and writes them to an MCAP file.

QoS follows what the publishers offer (reliable only if all of them are, transient-local only if
all of them are), so late-joining the graph neither misses latched data nor breaks matching.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Sequence

from rclpy.context import Context
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message

from hdrc3.live.channels import registered
from hdrc3.live.view import Emission, LiveView
from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3.message_types import MessageTypeError, message_class

DISCOVERY_PERIOD_S = 0.25
FLUSH_PERIOD_S = 1.0
DRAIN_QUIET_PASSES = 20


def _qos_yaml(profiles: Sequence[QoSProfile]) -> str:
    """Render offered QoS profiles the way rosbag2 stores them in channel metadata."""
    lines = []
    for qos in profiles:
        lines += [
            f"- history: {int(qos.history)}",
            f"  depth: {qos.depth}",
            f"  reliability: {int(qos.reliability)}",
            f"  durability: {int(qos.durability)}",
        ]
    return "\n".join(lines)


def subscription_qos(offered: Sequence[QoSProfile]) -> QoSProfile:
    """A subscription QoS compatible with every offered publisher QoS."""
    reliable = bool(offered) and all(q.reliability == ReliabilityPolicy.RELIABLE for q in offered)
    latched = bool(offered) and all(
        q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in offered
    )
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=100,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


class RecorderNode(Node):
    """Discovers topics and records every message on the selected ones."""

    def __init__(
        self,
        context: Context,
        writer: RecordingWriter,
        topics: Sequence[str] = (),
        exclude: str | None = None,
        live: LiveView | None = None,
    ) -> None:
        """Record ``topics`` (all topics when empty) into ``writer``.

        Args:
            context: rclpy context to live in.
            writer: Open recording.
            topics: Explicit topic names; empty means every topic in the graph.
            exclude: Regular expression of topic names never to record.
            live: Also write the live view's channels, converted from the recorded topics, so
                that the recording opens in the live view's Foxglove layout.

        """
        super().__init__("hdrc3_recorder", context=context)
        self._writer = writer
        self._wanted = set(topics)
        self._exclude = re.compile(exclude) if exclude else None
        self._subscribed: set[str] = set()
        self.warnings: list[str] = []
        self._live = live
        self._live_topics: set[str] = set()
        if live is not None:
            for channel in live.channels:
                if not channel.per_agent:
                    self._add_live_channel(channel.topic)
            self._write_live(live.start(time.time_ns()), time.time_ns())
        self.create_timer(DISCOVERY_PERIOD_S, self.discover)
        self.create_timer(FLUSH_PERIOD_S, writer.flush)
        self.discover()

    @property
    def subscribed_topics(self) -> set[str]:
        """Topics being recorded."""
        return set(self._subscribed)

    def drain(self, spin_once: Callable[[float], None], budget_s: float) -> None:
        """Handle already-delivered messages until none arrive for a moment, within a budget.

        Args:
            spin_once: Executes at most one ready callback, waiting up to its argument (s).
            budget_s: Wall-clock bound for the whole drain.
        """
        deadline = time.monotonic() + budget_s
        quiet = 0
        while quiet < DRAIN_QUIET_PASSES and time.monotonic() < deadline:
            before = self._writer.message_count
            spin_once(0.01)
            quiet = quiet + 1 if self._writer.message_count == before else 0

    def missing_topics(self) -> set[str]:
        """Explicitly requested topics not seen in the graph so far."""
        return self._wanted - self._subscribed

    def discover(self) -> None:
        """Subscribe to topics that appeared since the last look."""
        for topic, types in self.get_topic_names_and_types():
            if topic in self._subscribed:
                continue
            if self._wanted and topic not in self._wanted:
                continue
            if self._exclude is not None and self._exclude.search(topic):
                continue
            self._subscribe(topic, types)

    def _subscribe(self, topic: str, types: Sequence[str]) -> None:
        if len(types) != 1:
            self._warn(f"{topic} has several types {types}; recording {types[0]}")
        try:
            msg_type = message_class(types[0])
            offered = [info.qos_profile for info in self.get_publishers_info_by_topic(topic)]
            self._writer.add_topic(TopicInfo(topic, types[0], _qos_yaml(offered)))
        except MessageTypeError as exc:
            self._warn(f"not recording {topic}: {exc}")
            self._subscribed.add(topic)  # do not retry every discovery pass
            return

        route = self._live.route(topic, types[0]) if self._live is not None else None

        def on_message(data: bytes, topic: str = topic) -> None:
            now = time.time_ns()
            self._writer.write(topic, data, now)
            if route is not None and self._live is not None and self._live.wants(*route, now):
                msg = deserialize_message(data, msg_type)
                self._write_live(self._live.on_message(*route, msg, now), now)

        self.create_subscription(msg_type, topic, on_message, subscription_qos(offered), raw=True)
        self._subscribed.add(topic)

    def _add_live_channel(self, topic: str) -> bool:
        """Register a live channel (a per-agent one on its first message); False if unknown."""
        channel = registered(topic, self._live.channels) if self._live is not None else None
        if channel is None:
            return False
        schema = (channel.schema.name, channel.schema.encoding, channel.schema.data)
        self._writer.add_channel(topic, schema, channel.schema.message_encoding)
        self._live_topics.add(topic)
        return True

    def _write_live(self, emissions: list[Emission], log_time_ns: int) -> None:
        for e in emissions:
            if e.channel in self._live_topics or self._add_live_channel(e.channel):
                self._writer.write(e.channel, e.data, log_time_ns)

    def _warn(self, text: str) -> None:
        self.warnings.append(text)
        self.get_logger().warning(text)
