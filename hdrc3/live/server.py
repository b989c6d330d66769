"""The Foxglove WebSocket server of the live view (foxglove-sdk), without ROS.

One SDK ``Context`` per server (no global state): its channels are created from the registry
(a per-agent channel when its agent appears: :meth:`LiveServer.advertise`), and a subscription to
a latched channel is remembered so that the owner re-sends that channel's latest messages (the
SDK has no latching of its own).
"""

from __future__ import annotations

import threading
from collections.abc import Iterable, Sequence

from foxglove.websocket import ChannelView, Client, ServerListener

import foxglove
from hdrc3.live import DEFAULT_HOST, DEFAULT_PORT
from hdrc3.live.channels import CHANNELS, LiveChannel, registered
from hdrc3.live.view import Emission
from hdrc3_base.errors import ConfigError


class PortInUseError(ConfigError):
    """The WebSocket port is taken (another live view, or another program)."""


class _Listener(ServerListener):
    """Collects subscriptions to latched channels (called on the SDK's threads)."""

    def __init__(self, channels: tuple[LiveChannel, ...]) -> None:
        self._channels = channels
        self._lock = threading.Lock()
        self._wanted: set[str] = set()

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        entry = registered(channel.topic, self._channels)
        if entry is not None and entry.latched:
            with self._lock:
                self._wanted.add(channel.topic)

    def take(self) -> set[str]:
        with self._lock:
            wanted, self._wanted = self._wanted, set()
        return wanted


class LiveServer:
    """A running WebSocket server with one channel per registry entry."""

    def __init__(
        self,
        host: str = DEFAULT_HOST,
        port: int = DEFAULT_PORT,
        channels: Sequence[LiveChannel] = CHANNELS,
    ) -> None:
        """Bind and start serving; raises PortInUseError or ConfigError."""
        if not 0 <= port <= 65535:
            raise ConfigError(f"invalid port {port}: expected 0..65535")
        self._context = foxglove.Context()
        self._registry = tuple(channels)
        self._channels: dict[str, foxglove.Channel] = {}
        for c in self._registry:
            if not c.per_agent:
                self._open(c, c.topic)
        self._listener = _Listener(self._registry)
        try:
            self._server = foxglove.start_server(
                name="hdrc3 live view",
                host=host,
                port=port,
                server_listener=self._listener,
                context=self._context,
            )
        except RuntimeError as exc:
            if "in use" in str(exc):
                raise PortInUseError(
                    f"port {port} on {host} is in use (another live view?); "
                    "choose another with --live-port / port:=N"
                ) from None
            raise ConfigError(
                f"cannot start the live view server on {host}:{port}: {exc}"
            ) from None

    @property
    def port(self) -> int:
        """The bound port (useful with port 0)."""
        return int(self._server.port)

    def advertise(self, channel: LiveChannel, agent: str) -> str:
        """Advertise ``agent``'s instance of a channel (if not yet); its name."""
        topic = channel.instance(agent)
        if topic not in self._channels:
            self._open(channel, topic)
        return topic

    def has_subscribers(self, topic: str) -> bool:
        """True while a client subscribes to the advertised channel ``topic``."""
        channel = self._channels.get(topic)
        return channel is not None and channel.has_sinks()

    def send(self, emissions: Iterable[Emission], log_time_ns: int) -> None:
        """Log messages on their channels (advertising a per-agent channel on its first)."""
        for e in emissions:
            channel = self._channels.get(e.channel)
            if channel is None:
                entry = registered(e.channel, self._registry)
                if entry is None:
                    continue  # not a registered channel: nothing to log it on
                channel = self._open(entry, e.channel)
            channel.log(e.data, log_time=log_time_ns)

    def resubscribed(self) -> set[str]:
        """Latched channels a client subscribed to since the last call."""
        return self._listener.take()

    def _open(self, c: LiveChannel, topic: str) -> foxglove.Channel:
        schema = foxglove.Schema(name=c.schema.name, encoding=c.schema.encoding, data=c.schema.data)
        channel = foxglove.Channel(
            topic, schema=schema, message_encoding=c.schema.message_encoding, context=self._context
        )
        self._channels[topic] = channel
        return channel

    def close(self) -> None:
        """Stop the server and close the channels."""
        self._server.stop()
        for ch in self._channels.values():
            ch.close()
