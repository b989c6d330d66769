"""A small rclpy client of one agent's Platform Server (used by ``hdrc3 fcl/ppcl/state``).

It subscribes to ``/<agent>/platform_events`` before calling a service, so the completion event
of the call cannot be missed, and waits with wall-clock bounds.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable
from typing import Any

from rclpy.node import Node

from hdrc3_base.agents import parse_agents
from hdrc3_base.answer_memory import RESEND_S, ensure_key
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import SERVICE_QOS, SERVICE_WAIT_S, RosProcess
from hdrc3_base.stamps import stamp_s
from hdrc3_interfaces.msg import PlatformEvent
from hdrc3_platform_server.codes import EventKind
from hdrc3_platform_server.completion import TERMINAL, CompletionEvent
from hdrc3_platform_server.node import EVENT_QOS


def check_agent(agent: str) -> str:
    """The agent name, or ConfigError if it cannot be a ROS namespace."""
    (name,) = parse_agents(agent)
    return name


def event_from_msg(msg: Any) -> CompletionEvent:
    """Convert a PlatformEvent message."""
    stamp = msg.header.stamp
    return CompletionEvent(
        int(msg.command_id),
        str(msg.command),
        EventKind(int(msg.kind)),
        str(msg.reason),
        stamp_s(stamp),
    )


class PlatformClient:
    """Service calls and platform events of one agent."""

    def __init__(self, process: RosProcess, agent: str) -> None:
        self.process = process
        self.agent = check_agent(agent)
        self.node = Node(f"hdrc3_cli_{os.getpid()}", context=process.context)
        process.add_node(self.node)
        self.events: list[CompletionEvent] = []
        self.node.create_subscription(
            PlatformEvent, f"/{self.agent}/platform_events", self._on_event, EVENT_QOS
        )

    def _on_event(self, msg: Any) -> None:
        # an unknown kind from a newer server is not ours to interpret
        with contextlib.suppress(ValueError):
            self.events.append(event_from_msg(msg))

    def call(self, srv_type: Any, name: str, request: Any, timeout: float) -> Any:
        """Call ``/<agent>/<name>``; ConfigError if no such service, None on timeout.

        A command request gets a fresh ``request_key`` and is sent again every
        :data:`RESEND_S` until answered: a lost answer (see ``answer_memory``) costs a resend,
        and the server runs the command once.
        """
        client = self.node.create_client(srv_type, f"/{self.agent}/{name}", qos_profile=SERVICE_QOS)
        if not self.process.spin_until(client.service_is_ready, SERVICE_WAIT_S):
            raise ConfigError(
                f"no service /{self.agent}/{name}: unknown agent {self.agent!r} or its "
                "platform_server is not running (same ROS_DOMAIN_ID?)"
            )
        # give the events subscription a moment to match before the call can complete
        self.process.spin_until(lambda: self._events_matched(), 1.0)
        if ensure_key(request):
            return self.process.first_answer(client, request, timeout, RESEND_S)
        future: Any = client.call_async(request)  # rclpy's Future is untyped
        self.process.spin_until(lambda: bool(future.done()), timeout)
        return future.result() if future.done() else None

    def _events_matched(self) -> bool:
        return self.node.count_publishers(f"/{self.agent}/platform_events") > 0

    def wait_final(
        self,
        command_id: int,
        timeout: float,
        on_event: Callable[[CompletionEvent], None],
    ) -> CompletionEvent | None:
        """Wait for the terminal event of ``command_id``; other events go to ``on_event``."""
        seen = 0
        deadline = time.monotonic() + timeout
        while True:
            while seen < len(self.events):
                event = self.events[seen]
                seen += 1
                if event.command_id != command_id:
                    continue
                if event.kind in TERMINAL:
                    return event
                on_event(event)
            remaining = deadline - time.monotonic()
            if remaining <= 0 or self.process.stop_requested.is_set():
                return None
            self.process.spin_once(min(0.1, remaining))
