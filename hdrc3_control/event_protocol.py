"""The PFC side of the DRC event contract (docs/realtime_events.md) on top of the interpreter.

The automata SEND replies with the command's payload (id first) or with the data of a control
function's event. Before the events leave, :class:`EventProtocol`:

- trims id-only replies to the id and gives Cmd-Rejected/Failed/Cancelled their reason text
  (from the control function's event, the failing function, a per-transition reason, or the
  state the command met);
- keeps the set of accepted, unfinished command ids: a final reply for an id that is not active
  is dropped (so "finish whatever Command-DO holds" after a hover never repeats an answer), and
  replies for id 0 (commands from the ground UI) never go to the DRC;
- answers every DRC command event that no transition took with Cmd-Rejected-EV, naming the state
  it met, so each command gets exactly one answer.

It learns which transition sent what from the interpreter's trace (:class:`SendLog`).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from hdrc3_control.event_codec import command_id_of, encode
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.trace import TraceRecord, TraceSink

ID_ONLY = frozenset({"Cmd-Accepted-EV", "Cmd-Finished-EV", "Traj-Arrived-EV", "Request-Segment-EV"})
WITH_REASON = frozenset({"Cmd-Rejected-EV", "Cmd-Failed-EV", "Cmd-Cancelled-EV"})
FINAL = frozenset(
    {"Cmd-Finished-EV", "Traj-Arrived-EV", "Cmd-Failed-EV", "Cmd-Cancelled-EV", "Cmd-Rejected-EV"}
)
FUNCTION_EVENT_PREFIX = "Fn-"
"""Events posted by the control functions already carry the contract's payload."""

# Reasons of transitions whose meaning the generic text would not carry.
REASONS: dict[str, str] = {
    "A.38": "take-off refused: the engine is not running",
    "A.78": "failsafe: hovering on dead reckoning (GPS lost); only land, cancel, brake",
    "A.79": "failsafe: hovering on dead reckoning (GPS lost); only land, cancel, brake",
    "A.80": "failsafe: hovering on dead reckoning (GPS lost); only land, cancel, brake",
    "A.81": "failsafe: hovering on dead reckoning (GPS lost); only land, cancel, brake",
    "A.84": "failsafe: hovering on dead reckoning (GPS lost); only land, cancel, brake",
    "A.82": "failsafe emergency landing in progress: only the RC switch (manual) stops it",
    "A.83": "failsafe emergency landing in progress: only the RC switch (manual) stops it",
    "W.4": "RC switch to manual: the safety pilot has the aircraft",
    "A.40": "emergency brake",
    "A.41": "emergency brake",
    "A.42": "emergency brake",
    "A.43": "emergency brake",
    "A.44": "emergency brake",
    "A.45": "emergency brake",
    "A.46": "emergency brake",
    "A.47": "emergency brake",
    "A.48": "emergency brake",
    "A.50": "emergency brake",
    "A.56": "emergency brake",
    "A.61": "cancelled",
    "A.62": "cancelled",
    "A.63": "cancelled",
    "A.64": "cancelled",
    "A.65": "cancelled",
    "A.57": "cancelled",
}


@dataclass(frozen=True, slots=True)
class SendRecord:
    """One remote SEND action of a fired transition."""

    event: str
    tid: str
    trigger: str
    where: str
    """``machine:state`` the transition left."""


@dataclass(frozen=True, slots=True)
class Unanswered:
    """A DRC command event that no transition took."""

    event: str
    data: bytes
    state: str


def _remote_send(action: str) -> str | None:
    """Event name of ``SEND X ... to C`` (None for other actions and local sends)."""
    parts = action.split()
    if len(parts) < 2 or parts[0] != "SEND" or "to" not in parts[2:]:
        return None
    return parts[1]


def _where(configuration: Iterable[str]) -> str:
    """``machine:state`` of the innermost active machine that decides about commands."""
    states = {}
    for entry in configuration:
        path, _, state = entry.rpartition(":")
        states[path.rsplit("/", 1)[-1]] = state
    for machine in ("Mode-Switch", "Auto-Switch", "Root"):
        if machine in states:
            return f"{machine}:{states[machine]}"
    return ""


class SendLog:
    """Trace sink: remembers remote SENDs and unanswered command events; forwards records.

    ``commands`` are the DRC's command events: those the PFC model declares ``from DRC``.
    """

    def __init__(self, commands: frozenset[str], forward: TraceSink | None = None) -> None:
        self.commands = commands
        self.forward = forward
        self.sends: list[SendRecord] = []
        self.unanswered: list[Unanswered] = []
        self._posted: deque[tuple[str, bytes]] = deque()

    def posted(self, name: str, data: bytes) -> None:
        """Note an external event the interpreter accepted (order = processing order)."""
        self._posted.append((name, data))

    def record(self, record: TraceRecord) -> None:
        """Take one micro step's record."""
        if record.origin == "external" and self._posted:
            name, data = self._posted.popleft()
            if name in self.commands and not record.transitions:
                self.unanswered.append(Unanswered(name, data, _where(record.configuration)))
        for fired in record.transitions:
            for action in fired.actions:
                event = _remote_send(action)
                if event is not None:
                    where = f"{fired.machine.rsplit('/', 1)[-1]}:{fired.source}"
                    self.sends.append(SendRecord(event, fired.tid, record.event, where))
        if self.forward is not None:
            self.forward.record(record)

    def take(self) -> tuple[list[SendRecord], list[Unanswered]]:
        """Records since the last call."""
        sends, unanswered = self.sends, self.unanswered
        self.sends, self.unanswered = [], []
        return sends, unanswered


class EventProtocol:
    """Turns the automata's outgoing events into the contract's payloads."""

    def __init__(
        self,
        failure_reason: Callable[[], str],
        rejected_id: int,
        trigger_reason: Callable[[str], str | None] = lambda _trigger: None,
        finish_note: Callable[[int], str] = lambda _command_id: "",
        accept_note: Callable[[int], str] = lambda _command_id: "",
    ) -> None:
        """``failure_reason`` gives the reason of the last control function failure.

        ``rejected_id`` is the model's id of Cmd-Rejected-EV, which the protocol sends itself.
        ``trigger_reason`` gives the reason of replies sent on an internal event that carries
        one (the failsafe's Fs-Hold-EV, Fs-Land-EV), None for the others. ``finish_note`` gives
        (and forgets) what a command's control function has to say when the command ends (the
        landing: which aid it used); a Cmd-Finished-EV carries it as its reason. ``accept_note``
        likewise what it has to say as it starts (the landing: which aid it plans on and why);
        a Cmd-Accepted-EV carries it.
        """
        self.failure_reason = failure_reason
        self.trigger_reason = trigger_reason
        self.finish_note = finish_note
        self.accept_note = accept_note
        self.rejected_id = rejected_id
        self.active: set[int] = set()
        self.dropped = 0
        self.current = 0
        """Id of the most recently accepted command still active (0: none)."""

    def outgoing(
        self, events: list[WireEvent], sends: list[SendRecord], unanswered: list[Unanswered]
    ) -> list[WireEvent]:
        """Rewrite one step's outbox; append rejections of unanswered commands."""
        out: list[WireEvent] = []
        j = 0
        for event in events:
            # the outbox holds the remote SENDs in the order the trace listed them
            send = None
            while j < len(sends) and send is None:
                send = sends[j] if sends[j].event == event.name else None
                j += 1
            fixed = self._fix(event, send)
            if fixed is None:
                self.dropped += 1
            else:
                out.append(fixed)
        for item in unanswered:
            cid = command_id_of(item.data)
            if cid == 0:
                continue
            reason = f"{item.event} not accepted in {item.state or 'the current state'}"
            out.append(
                WireEvent(
                    self.rejected_id, "Cmd-Rejected-EV", encode(cid, (), reason), "PFC", "DRC"
                )
            )
        return out

    def _fix(self, event: WireEvent, send: SendRecord | None) -> WireEvent | None:
        name = event.name
        if name not in ID_ONLY and name not in WITH_REASON:
            return event
        cid = command_id_of(event.data)
        if cid == 0:
            return None
        if name in FINAL and name != "Cmd-Rejected-EV" and cid not in self.active:
            return None
        if name == "Request-Segment-EV" and cid not in self.active:
            return None
        note = self.finish_note(cid) if name in FINAL else ""
        if name == "Cmd-Accepted-EV":
            note = self.accept_note(cid)
        if name in ("Cmd-Finished-EV", "Cmd-Accepted-EV") and note:
            data = encode(cid, (), note)
        elif name in ID_ONLY:
            data = event.data[:8]
        elif send is not None and send.trigger.startswith(FUNCTION_EVENT_PREFIX):
            data = event.data
        else:
            data = encode(cid, (), self._reason(name, send))
        if name == "Cmd-Accepted-EV":
            self.active.add(cid)
            self.current = cid
        elif name in FINAL:
            self.active.discard(cid)
            if self.current == cid:
                self.current = 0
        return WireEvent(event.event_id, name, data, event.source, event.target)

    def _reason(self, name: str, send: SendRecord | None) -> str:
        if send is None:
            return name
        if send.tid in REASONS:
            return REASONS[send.tid]
        by_trigger = self.trigger_reason(send.trigger)
        if by_trigger is not None:
            return by_trigger
        if send.trigger == "Ctrl-Error-EV":
            return self.failure_reason() or f"control function failed ({send.where})"
        return f"{send.trigger} in {send.where} ({send.tid})"
