"""The ``live_view`` node: subscribes to the sources of the live channels and serves them.

Thin adapter around :class:`~hdrc3.live.view.LiveView` (the converters) and
:class:`~hdrc3.live.server.LiveServer` (foxglove-sdk's WebSocket server). Topics are found by
discovery, like the recorder's: every ``/<agent>/<source>`` of a registered source type, so the
node needs no agent list and picks up agents that join later.

Messages arrive serialized and are decoded only if some channel wants them now (a camera image
the rate limit drops is not decoded). The sources of on-demand channels (camera images) are
subscribed only while a client subscribes to the agent's channel, and unsubscribed after. What
the converters skip (an unknown image encoding, a malformed map) is logged every
:data:`SKIP_LOG_PERIOD_S` while the counts grow.
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from dataclasses import dataclass
from typing import Any

from rclpy.context import Context
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.subscription import Subscription

from hdrc3.live import DEFAULT_HOST, DEFAULT_PORT
from hdrc3.live.converters import SkipReason
from hdrc3.live.server import LiveServer
from hdrc3.live.view import LiveView
from hdrc3.message_types import message_class
from hdrc3.recorder import subscription_qos
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import run_events_node
from sim.world_loader import WorldError, load_world

NODE_NAME = "live_view"
DISCOVERY_PERIOD_S = 0.5
LATCH_PERIOD_S = 0.1
SKIP_LOG_PERIOD_S = 5.0
NEWEST_ONLY = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE
)
"""Camera images: never hold up the publisher, take only the newest."""


@dataclass(slots=True)
class _Demand:
    """A source topic subscribed only while one of its channels has a client."""

    topic: str
    agent: str
    suffix: str
    type_name: str
    qos: QoSProfile
    channels: tuple[str, ...]
    subscription: Subscription | None = None


class LiveViewNode(Node):
    """Streams the running system to Foxglove clients."""

    def __init__(self, context: Context, **kwargs: Any) -> None:
        """Read ``world``, ``host`` and ``port``; start the server (ConfigError if it cannot)."""
        super().__init__(NODE_NAME, context=context, **kwargs)
        world_name = str(self.declare_parameter("world", "revinge").value)
        host = str(self.declare_parameter("host", DEFAULT_HOST).value)
        port = int(self.declare_parameter("port", DEFAULT_PORT).value)
        try:
            world = load_world(world_name)
        except WorldError as exc:
            raise ConfigError(str(exc)) from None
        self.view = LiveView(world)
        self.server = LiveServer(host, port, self.view.channels)
        self._subscribed: set[str] = set()
        self._demand: dict[str, _Demand] = {}
        self._logged_skips: dict[str, Counter[SkipReason]] = {}
        now = time.time_ns()
        self.server.send(self.view.start(now), now)
        self.create_timer(DISCOVERY_PERIOD_S, self.discover)
        self.create_timer(LATCH_PERIOD_S, self._on_clients)
        self.create_timer(SKIP_LOG_PERIOD_S, self._log_skips)
        self.discover()
        self.get_logger().info(f"live view on ws://{host}:{self.server.port}")
        print(f"live view: ws://{host}:{self.server.port}", flush=True)

    def discover(self) -> None:
        """Subscribe to source topics that appeared since the last look."""
        for topic, types in self.get_topic_names_and_types():
            if topic in self._subscribed or len(types) != 1:
                continue
            route = self.view.route(topic, types[0])
            if route is None:
                continue
            agent, suffix = route
            offered = [info.qos_profile for info in self.get_publishers_info_by_topic(topic)]
            qos = NEWEST_ONLY if self.view.newest_only(suffix) else subscription_qos(offered)
            channels = self.view.channels_of(suffix)
            if all(c.on_demand for c in channels):
                names = tuple(self.server.advertise(c, agent) for c in channels)
                self._demand[topic] = _Demand(topic, agent, suffix, types[0], qos, names)
            else:
                self._subscribe(topic, agent, suffix, types[0], qos)
            self._subscribed.add(topic)

    def _subscribe(
        self, topic: str, agent: str, suffix: str, type_name: str, qos: QoSProfile
    ) -> Subscription:
        msg_type = message_class(type_name)

        def on_message(data: bytes) -> None:
            now = time.time_ns()
            if self.view.wants(agent, suffix, now):
                msg = deserialize_message(data, msg_type)
                self.server.send(self.view.on_message(agent, suffix, msg, now), now)

        return self.create_subscription(msg_type, topic, on_message, qos, raw=True)

    def _on_clients(self) -> None:
        """Re-send latched channels to new subscribers; follow the on-demand subscriptions."""
        now = time.time_ns()
        for topic in self.server.resubscribed():
            self.server.send(self.view.latched(topic), now)
        for d in self._demand.values():
            wanted = any(self.server.has_subscribers(c) for c in d.channels)
            if wanted and d.subscription is None:
                d.subscription = self._subscribe(d.topic, d.agent, d.suffix, d.type_name, d.qos)
            elif not wanted and d.subscription is not None:
                self.destroy_subscription(d.subscription)
                d.subscription = None

    def _log_skips(self) -> None:
        skipped = self.view.skipped()
        if skipped == self._logged_skips:
            return
        self._logged_skips = skipped
        text = "; ".join(
            f"{topic}: " + ", ".join(f"{n} x {reason.value}" for reason, n in counts.items())
            for topic, counts in skipped.items()
        )
        self.get_logger().warning(f"source messages skipped so far: {text}")

    def destroy_node(self) -> None:
        """Stop the server with the node."""
        self.server.close()
        super().destroy_node()


def main() -> int:
    """Console script ``hdrc3-live-view``: 0 on SIGINT/SIGTERM, 2 on bad parameters/port."""
    return run_events_node(LiveViewNode, "hdrc3-live-view: error")


if __name__ == "__main__":
    sys.exit(main())
