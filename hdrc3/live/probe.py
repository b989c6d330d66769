"""A minimal Foxglove WebSocket client for tests and benches.

The server of foxglove-sdk 0.30 accepts the subprotocols ``foxglove.sdk.v1`` and
``foxglove.sdk.v1.1`` only (a client asking for the older name ``foxglove.websocket.v1`` gets
HTTP 400); ``foxglove.sdk.v1`` keeps the message layout of ``foxglove.websocket.v1``, which this
client speaks: JSON ``serverInfo``/``advertise``/``subscribe``, binary message frames.

Reads the server's channel advertisements, subscribes to channels by topic and yields their
binary message frames (opcode 1: subscription id, log time, payload). Uses the ``websockets``
package (the ``dev`` extra); the live view itself does not need it.
"""

from __future__ import annotations

import json
import struct
import time
from dataclasses import dataclass
from types import TracebackType
from typing import Any

from websockets.sync.client import ClientConnection, connect
from websockets.typing import Subprotocol

SUBPROTOCOL = Subprotocol("foxglove.sdk.v1")
MESSAGE_DATA = 0x01
_HEADER = struct.Struct("<BIQ")


@dataclass(frozen=True, slots=True)
class Frame:
    """One message received on a subscribed channel."""

    topic: str
    log_time_ns: int
    data: bytes


class FoxgloveProbe:
    """A connected client; every wait is bounded by the caller's timeout."""

    def __init__(self, url: str, timeout_s: float = 10.0) -> None:
        """Connect to ``url`` (``ws://127.0.0.1:8765``)."""
        self._ws: ClientConnection = connect(
            url, subprotocols=[SUBPROTOCOL], open_timeout=timeout_s, max_size=None
        )
        self.channels: dict[str, dict[str, Any]] = {}
        """Advertised channels by topic (the server's JSON objects)."""
        self._subscriptions: dict[int, str] = {}
        self._pending: list[Frame] = []

    def __enter__(self) -> FoxgloveProbe:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()

    @property
    def subprotocol(self) -> str | None:
        """The subprotocol the server accepted."""
        return self._ws.subprotocol

    def wait_for_channels(self, topics: set[str], timeout_s: float) -> bool:
        """Read until every topic of ``topics`` is advertised; False at the deadline."""
        deadline = time.monotonic() + timeout_s
        while not topics <= set(self.channels):
            if not self._read_one(deadline):
                return False
        return True

    def subscribe(self, topics: list[str]) -> None:
        """Subscribe to advertised channels (KeyError for one not advertised)."""
        subs = []
        for topic in topics:
            sub_id = len(self._subscriptions) + 1
            self._subscriptions[sub_id] = topic
            subs.append({"id": sub_id, "channelId": self.channels[topic]["id"]})
        self._ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))

    def receive(self, timeout_s: float) -> Frame | None:
        """The next message of a subscribed channel, or None at the deadline."""
        deadline = time.monotonic() + timeout_s
        while not self._pending:
            if not self._read_one(deadline):
                return None
        return self._pending.pop(0)

    def close(self) -> None:
        """Close the connection."""
        self._ws.close()

    def _read_one(self, deadline: float) -> bool:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return False
        try:
            raw = self._ws.recv(timeout=remaining)
        except TimeoutError:
            return False
        if isinstance(raw, str):
            op = json.loads(raw)
            if op.get("op") == "advertise":
                self.channels.update({c["topic"]: c for c in op["channels"]})
            elif op.get("op") == "unadvertise":
                gone = set(op["channelIds"])
                self.channels = {t: c for t, c in self.channels.items() if c["id"] not in gone}
        elif raw and raw[0] == MESSAGE_DATA:
            _, sub_id, log_time = _HEADER.unpack_from(raw)
            topic = self._subscriptions.get(sub_id)
            if topic is not None:
                self._pending.append(Frame(topic, log_time, bytes(raw[_HEADER.size :])))
        return True
