"""The live view's core: routes ROS messages to the converters of the registry, keeps latches.

Pure (no rclpy): the node feeds it decoded messages with their topic and receive time and sends
what comes back; the recorder does the same to write the live channels into a recording.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from hdrc3.live.channels import CHANNELS, LiveChannel
from hdrc3.live.converters import Converter, Output, SkipReason
from hdrc3_base.agents import AGENT_NAME
from sim.world import World


@dataclass(frozen=True, slots=True)
class Emission:
    """One encoded message for one channel."""

    channel: str
    data: bytes


class LiveView:
    """Converters of every channel for one world."""

    def __init__(self, world: World, channels: Sequence[LiveChannel] = CHANNELS) -> None:
        self.channels = tuple(channels)
        self._converters: dict[str, Converter] = {c.topic: c.make(world) for c in self.channels}
        self._routes: dict[str, list[LiveChannel]] = {}
        for c in self.channels:
            for source in c.sources:
                self._routes.setdefault(source.suffix, []).append(c)
        self._types = {s.suffix: s.type_name for c in self.channels for s in c.sources}
        self._latched: dict[str, dict[str, bytes]] = {c.topic: {} for c in self.channels}

    def newest_only(self, suffix: str) -> bool:
        """True if the source should be subscribed best effort, newest message only."""
        return any(s.newest_only for c in self.channels for s in c.sources if s.suffix == suffix)

    def channels_of(self, suffix: str) -> tuple[LiveChannel, ...]:
        """The channels fed by a source suffix."""
        return tuple(self._routes.get(suffix, ()))

    def source_types(self) -> dict[str, str]:
        """ROS type name of every source suffix."""
        return dict(self._types)

    def route(self, topic: str, type_name: str) -> tuple[str, str] | None:
        """(agent, suffix) if ``topic`` of ``type_name`` is a source of some channel."""
        agent, _, suffix = topic.lstrip("/").partition("/")
        if not AGENT_NAME.match(agent) or self._types.get(suffix) != type_name:
            return None
        return agent, suffix

    def start(self, now_ns: int) -> list[Emission]:
        """What the channels know before any message (the world)."""
        return [
            e
            for c in self.channels
            for e in self._keep(c, self._converters[c.topic].start(now_ns), c.topic)
        ]

    def wants(self, agent: str, suffix: str, now_ns: int) -> bool:
        """False if a message from ``/<agent>/<suffix>`` now would give nothing (don't decode)."""
        return any(
            self._converters[c.topic].wants(suffix, agent, now_ns)
            for c in self._routes.get(suffix, ())
        )

    def on_message(self, agent: str, suffix: str, msg: Any, now_ns: int) -> list[Emission]:
        """Messages of every channel fed by ``/<agent>/<suffix>``."""
        out: list[Emission] = []
        for c in self._routes.get(suffix, ()):
            outputs = self._converters[c.topic].convert(suffix, agent, msg, now_ns)
            out += self._keep(c, outputs, c.instance(agent))
        return out

    def skipped(self) -> dict[str, Counter[SkipReason]]:
        """Source messages each channel's converter dropped so far, by reason (non-zero only)."""
        counts = {c.topic: self._converters[c.topic].skipped for c in self.channels}
        return {topic: Counter(n) for topic, n in counts.items() if n}

    def latched(self, topic: str) -> list[Emission]:
        """The latest message of every key of a latched channel (for a subscribing client).

        ``topic`` is an advertised name (``<name>/<agent>`` for a per-agent channel).
        """
        return [Emission(topic, data) for data in self._latched.get(topic, {}).values()]

    def _keep(self, channel: LiveChannel, outputs: list[Output], topic: str) -> list[Emission]:
        if channel.latched:
            for o in outputs:
                self._latched.setdefault(topic, {})[o.key] = o.data
        return [Emission(topic, o.data) for o in outputs]
