"""Transport of external events between computers.

The interface, channel integrity (sequence numbers + CRC-32, as the chapter's real-time
channels have) and an in-process loopback network for tests and single-process simulation.

Restarts: every endpoint draws a random *incarnation* when it is created and stamps it on the
events it sends; sequence numbers count per target within one incarnation. The receiver keeps one
window per sender: an event of an incarnation it has not seen from that sender starts a new window
(the restarted sender's events, numbered from 1 again, are heard) and, if an older incarnation of
that sender was known, reports the sender as restarted (:meth:`Transport.restarts`); the old
incarnation is retired and its late events are dropped as stale. The table of verdicts is in
``docs/realtime_events.md`` (section "Restarts").
"""

from __future__ import annotations

import enum
import secrets
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
    STALE = "stale"
    """From an incarnation of the sender that a newer one replaced (a late event of a dead run)."""


RETIRED_KEPT = 8
"""Retired incarnations remembered per sender (to drop their late events)."""
RESTARTS_KEPT = 64
"""Restart notices kept until the owner reads them (an owner that never reads loses the oldest)."""


def new_incarnation() -> int:
    """A random non-zero 64-bit incarnation number for a transport that starts now."""
    return secrets.randbits(64) or 1


@dataclass
class ChannelStats:
    """Counters of one endpoint."""

    sent: int = 0
    received: int = 0
    corrupt: int = 0
    duplicates: int = 0
    lost: int = 0
    no_route: int = 0
    stale: int = 0
    restarts: int = 0


class Transport(Protocol):
    """What the main loop's Communicate needs from a transport."""

    computer: str
    stats: ChannelStats

    def send(self, event: WireEvent) -> SendStatus:
        """Send one event to ``event.target`` (sealed with sequence and CRC by the transport)."""

    def receive(self) -> list[WireEvent]:
        """Events received and accepted since the last call, in order."""

    def restarts(self) -> list[str]:
        """Computers heard with a new incarnation (restarted) since the last call, in order."""


@dataclass
class _Window:
    """What a receiver knows about the current incarnation of one sender."""

    incarnation: int
    last: int = 0


class ChannelIntegrity:
    """Numbers outgoing events per target and checks incoming ones per source and incarnation."""

    def __init__(self, stats: ChannelStats, incarnation: int | None = None) -> None:
        self.stats = stats
        self.incarnation = new_incarnation() if incarnation is None else incarnation
        """Stamped on every sealed event; a new endpoint (a restarted process) draws a new one."""
        self._next: dict[str, int] = {}
        self._windows: dict[str, _Window] = {}
        self._retired: dict[str, deque[int]] = {}
        self._restarted: deque[str] = deque(maxlen=RESTARTS_KEPT)

    def seal(self, event: WireEvent) -> WireEvent:
        """Give ``event`` the next sequence number of its channel and its checksum."""
        sequence = self._next.get(event.target, 1)
        self._next[event.target] = sequence + 1
        return event.sealed(sequence, self.incarnation)

    def accept(self, event: WireEvent) -> Verdict:
        """Check checksum, incarnation and order; counts losses (sequence gaps), drops repeats."""
        if not event.intact():
            self.stats.corrupt += 1
            return Verdict.CORRUPT
        window = self._windows.get(event.source)
        if window is None or window.incarnation != event.incarnation:
            retired = self._retired.setdefault(event.source, deque(maxlen=RETIRED_KEPT))
            if event.incarnation in retired:
                self.stats.stale += 1
                return Verdict.STALE
            if window is not None:
                retired.append(window.incarnation)
                self._restarted.append(event.source)
                self.stats.restarts += 1
            window = self._windows[event.source] = _Window(event.incarnation)
        if event.sequence <= window.last:
            self.stats.duplicates += 1
            return Verdict.DUPLICATE
        self.stats.lost += event.sequence - window.last - 1
        window.last = event.sequence
        self.stats.received += 1
        return Verdict.ACCEPTED

    def restarts(self) -> list[str]:
        """Senders that changed incarnation since the last call (oldest first)."""
        out = list(self._restarted)
        self._restarted.clear()
        return out


class LoopbackNetwork:
    """In-process network: endpoints keyed by computer name, delivery in send order."""

    def __init__(self) -> None:
        self._inboxes: dict[str, deque[WireEvent]] = {}

    def endpoint(self, computer: str) -> LoopbackTransport:
        """Create (or replace: a restart, with a new incarnation) the endpoint of ``computer``."""
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

    def restarts(self) -> list[str]:
        """Computers heard with a new incarnation since the last call."""
        return self._integrity.restarts()
