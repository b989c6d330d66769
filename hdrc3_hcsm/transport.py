"""Transport of external events between computers.

The interface, channel integrity (sequence numbers + CRC-32, as the chapter's real-time
channels have) and an in-process loopback network for tests and single-process simulation.
"""

from __future__ import annotations

import enum
from collections import deque
from dataclasses import dataclass
from typing import Protocol

from hdrc3_hcsm.event import WireEvent


class SendStatus(enum.Enum):
    """Outcome of handing one event to a transport."""

    SENT = "sent"
    NO_ROUTE = "no_route"


class Verdict(enum.Enum):
    """What the receiving side of a channel decided about one event."""

    ACCEPTED = "accepted"
    CORRUPT = "corrupt"
    DUPLICATE = "duplicate"


@dataclass
class ChannelStats:
    """Counters of one endpoint."""

    sent: int = 0
    received: int = 0
    corrupt: int = 0
    duplicates: int = 0
    lost: int = 0
    no_route: int = 0


class Transport(Protocol):
    """What the main loop's Communicate needs from a transport."""

    computer: str
    stats: ChannelStats

    def send(self, event: WireEvent) -> SendStatus:
        """Send one event to ``event.target`` (sealed with sequence and CRC by the transport)."""

    def receive(self) -> list[WireEvent]:
        """Events received and accepted since the last call, in order."""


class ChannelIntegrity:
    """Numbers outgoing events per target and checks incoming ones per source."""

    def __init__(self, stats: ChannelStats) -> None:
        self.stats = stats
        self._next: dict[str, int] = {}
        self._last: dict[str, int] = {}

    def seal(self, event: WireEvent) -> WireEvent:
        """Give ``event`` the next sequence number of its channel and its checksum."""
        sequence = self._next.get(event.target, 1)
        self._next[event.target] = sequence + 1
        return event.sealed(sequence)

    def accept(self, event: WireEvent) -> Verdict:
        """Check checksum and order; counts losses (sequence gaps), drops duplicates."""
        if not event.intact():
            self.stats.corrupt += 1
            return Verdict.CORRUPT
        last = self._last.get(event.source, 0)
        if event.sequence <= last:
            self.stats.duplicates += 1
            return Verdict.DUPLICATE
        self.stats.lost += event.sequence - last - 1
        self._last[event.source] = event.sequence
        self.stats.received += 1
        return Verdict.ACCEPTED


class LoopbackNetwork:
    """In-process network: endpoints keyed by computer name, delivery in send order."""

    def __init__(self) -> None:
        self._inboxes: dict[str, deque[WireEvent]] = {}

    def endpoint(self, computer: str) -> LoopbackTransport:
        """Create (or replace) the endpoint of ``computer``."""
        self._inboxes[computer] = deque()
        return LoopbackTransport(computer, self)

    def deliver(self, event: WireEvent) -> SendStatus:
        """Put ``event`` into its target's inbox."""
        inbox = self._inboxes.get(event.target)
        if inbox is None:
            return SendStatus.NO_ROUTE
        inbox.append(event)
        return SendStatus.SENT

    def drain(self, computer: str) -> list[WireEvent]:
        """Take everything waiting for ``computer``."""
        inbox = self._inboxes.get(computer)
        if inbox is None:
            return []
        out = list(inbox)
        inbox.clear()
        return out


class LoopbackTransport:
    """One computer's endpoint on a :class:`LoopbackNetwork`."""

    def __init__(self, computer: str, network: LoopbackNetwork) -> None:
        self.computer = computer
        self.stats = ChannelStats()
        self._network = network
        self._integrity = ChannelIntegrity(self.stats)

    def send(self, event: WireEvent) -> SendStatus:
        """Seal and deliver one event."""
        status = self._network.deliver(self._integrity.seal(event))
        if status is SendStatus.SENT:
            self.stats.sent += 1
        else:
            self.stats.no_route += 1
        return status

    def receive(self) -> list[WireEvent]:
        """Return the accepted events since the last call."""
        return [
            e
            for e in self._network.drain(self.computer)
            if self._integrity.accept(e) is Verdict.ACCEPTED
        ]
