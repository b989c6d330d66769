"""Completion and progress events of FCL/PPCL commands (PlatformEvent, platform-events topic)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from hdrc3_platform_server.codes import EventKind


@dataclass(frozen=True, slots=True)
class CompletionEvent:
    """One PlatformEvent: which command (id and name), what happened, why, when (DRC clock)."""

    command_id: int
    command: str
    kind: EventKind
    reason: str
    time: float


EventSink = Callable[[CompletionEvent], None]
"""Where the command layers put their events (the node publishes them)."""


class EventLog:
    """An :data:`EventSink` that keeps every event (tests, fakes and the bench)."""

    def __init__(self) -> None:
        self.events: list[CompletionEvent] = []

    def __call__(self, event: CompletionEvent) -> None:
        """Store one event."""
        self.events.append(event)

    def of(self, command_id: int) -> list[CompletionEvent]:
        """Events about one command id, in order."""
        return [e for e in self.events if e.command_id == command_id]

    def final(self, command_id: int) -> CompletionEvent | None:
        """The terminal event (finished, failed, cancelled) of a command, if any."""
        for e in self.events:
            if e.command_id == command_id and e.kind in TERMINAL:
                return e
        return None


TERMINAL = frozenset({EventKind.FINISHED, EventKind.FAILED, EventKind.CANCELLED})
"""Kinds that end a command; every accepted command gets exactly one of them."""
