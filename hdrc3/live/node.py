"""The ``live_view`` node: subscribes to the sources of the live channels and serves them.

Thin adapter around :class:`~hdrc3.live.view.LiveView` (the converters) and
:class:`~hdrc3.live.server.LiveServer` (foxglove-sdk's WebSocket server). Topics are found by
discovery, like the recorder's: every ``/<agent>/<source>`` of a registered source type, so the
node needs no agent list and picks up agents that join later.
"""

from __future__ import annotations

import sys
import time
from typing import Any

from rclpy.context import Context
from rclpy.node import Node

from hdrc3.live import DEFAULT_HOST, DEFAULT_PORT
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


class LiveViewNode(Node):
    """Streams the running system to Foxglove clients."""

    def __init__(self, context: Context) -> None:
        """Read ``world``, ``host`` and ``port``; start the server (ConfigError if it cannot)."""
        super().__init__(NODE_NAME, context=context)
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
        now = time.time_ns()
        self.server.send(self.view.start(now), now)
        self.create_timer(DISCOVERY_PERIOD_S, self.discover)
        self.create_timer(LATCH_PERIOD_S, self._resend_latched)
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

            def on_message(msg: Any, agent: str = agent, suffix: str = suffix) -> None:
                now = time.time_ns()
                self.server.send(self.view.on_message(agent, suffix, msg, now), now)

            self.create_subscription(
                message_class(types[0]), topic, on_message, subscription_qos(offered)
            )
            self._subscribed.add(topic)

    def _resend_latched(self) -> None:
        now = time.time_ns()
        for topic in self.server.resubscribed():
            self.server.send(self.view.latched(topic), now)

    def destroy_node(self) -> None:
        """Stop the server with the node."""
        self.server.close()
        super().destroy_node()


def main() -> int:
    """Console script ``hdrc3-live-view``: 0 on SIGINT/SIGTERM, 2 on bad parameters/port."""
    return run_events_node(LiveViewNode, "hdrc3-live-view: error")


if __name__ == "__main__":
    sys.exit(main())
