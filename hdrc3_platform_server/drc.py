"""The DRC's HCSM side: the DRC automaton, its conditions and its main loop (chapter 6.2.1).

One :class:`DrcKernel` runs ``automata/drc.hcsm`` on an HCSM interpreter.
The command layers post ``Api-*-EV`` events (the "shared memory" path of Figure 11);
:meth:`DrcKernel.step` is one Communicate + ExecuteStateMachine + Communicate pass, so a command
reaches the PFC/PPC in the same call that accepted it. Whether the automaton took the command is
in the step's result; :meth:`DrcKernel.refusal` says why it did not, from the same model.
"""

from __future__ import annotations

import enum
import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Protocol

from hdrc3_control.event_codec import command_id_of
from hdrc3_hcsm.conditions import blocking_condition
from hdrc3_hcsm.event import PostStatus, WireEvent
from hdrc3_hcsm.interpreter import Interpreter, StepResult
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.tables import CompiledModel, compile_model
from hdrc3_hcsm.transport import SendStatus, Transport
from hdrc3_platform_server.platform_status import PlatformStatus


class FlightState(enum.Enum):
    """States of the Flight automaton (F)."""

    IDLE = "Fl-Idle-ST"
    RUNNING = "Fl-Running-ST"
    PATH = "Fl-Path-ST"
    SETTLING = "Fl-Settling-ST"
    BRAKING = "Fl-Braking-ST"


class PlatformState(enum.Enum):
    """States of the Platform automaton (M): the PFC's state as the DRC mirrors it."""

    UNKNOWN = "Pl-Unknown-ST"
    GROUND = "Pl-Ground-ST"
    AIR = "Pl-Air-ST"
    MANUAL = "Pl-Manual-ST"


class RefusalKind(enum.Enum):
    """Why the Flight automaton made no transition on a command's input event."""

    BUSY = "busy"
    """No transition on it from the active state: another command is in progress."""
    NOT_ACCEPTED = "not_accepted"
    """A transition on it exists, but its guard is false in the aircraft's state."""


@dataclass(frozen=True, slots=True)
class Refusal:
    """The automaton's refusal of one command, with a reason for the caller."""

    kind: RefusalKind
    reason: str


REFUSALS: Mapping[str, str] = MappingProxyType(
    {
        "Data-Fresh-CO": "no state data from the control kernel (PFC): is control_kernel running?",
        "On-Ground-CO": "{label} can only be commanded when the aircraft is on the ground",
        "Airborne-CO": "{label} needs the aircraft hovering; it is on the ground",
        "Auto-CO": "the RC switch is in manual mode: the safety pilot must select autonomous",
    }
)
"""FCL_NOT_ACCEPTED reason per condition of a start transition's guard, when it is the one that
fails (``{label}``: the command); other conditions are named as they are."""


class WireListener(Protocol):
    """A command layer: sees every received event before the automaton, and each step's end."""

    def on_wire(self, event: WireEvent, now: float) -> None:
        """Correlate one event from the PFC/PPC."""

    def after_step(self, now: float) -> None:
        """React to the automaton's new states."""

    def on_restart(self, computer: str, now: float) -> None:
        """``computer`` (PFC or PPC) was heard with a new incarnation: it restarted."""


def model_path() -> Path:
    """Location of the DRC automaton file."""
    return Path(str(resources.files("hdrc3_platform_server.automata") / "drc.hcsm"))


@functools.cache
def load_model() -> CompiledModel:
    """Load and compile the DRC automaton once (raises on a broken file: a packaging error)."""
    return compile_model(load_file(model_path()))


class DrcKernel:
    """The DRC automaton with its conditions, fed by the command layers and a transport."""

    def __init__(
        self,
        status: PlatformStatus,
        transport: Transport | None = None,
        *,
        settle_timeout: float = 15.0,
        model: CompiledModel | None = None,
    ) -> None:
        self.status = status
        self.transport = transport
        self.settle_timeout = settle_timeout
        self.current_ids: frozenset[int] = frozenset()
        """Ids of the FCL command in progress (a path has one per segment)."""
        self.waiting_since: float | None = None
        """DRC time when Settling/Braking was entered (Settle-Timeout-CO)."""
        self.listeners: list[WireListener] = []
        self.undeliverable = 0
        self.conditions: dict[str, Callable[[], bool]] = {
            "Current-Cmd-CO": self._current_cmd,
            "On-Ground-CO": status.on_ground,
            "Airborne-CO": status.airborne,
            "Auto-CO": status.auto,
            "Data-Fresh-CO": status.pfc_fresh,
            "Hover-Stable-CO": status.hover_stable,
            "Settle-Timeout-CO": self._settle_timeout,
        }
        self.model = model or load_model()
        self.interpreter = Interpreter(self.model, self.conditions)

    # --- conditions -----------------------------------------------------------------------
    def _current_cmd(self) -> bool:
        return command_id_of(self.interpreter.memory.cache) in self.current_ids

    def _settle_timeout(self) -> bool:
        since = self.waiting_since
        return since is not None and self.status.now - since > self.settle_timeout

    # --- inspection -----------------------------------------------------------------------
    def _state_of(self, automaton: str) -> str:
        for entry in self.interpreter.configuration():
            path, state = entry.rsplit(":", 1)
            if path == automaton:
                return state
        raise KeyError(automaton)  # pragma: no cover - the model always has F, M and G

    def flight(self) -> FlightState:
        """Active state of the Flight automaton."""
        return FlightState(self._state_of("Flight"))

    def platform(self) -> PlatformState:
        """Active state of the Platform automaton."""
        return PlatformState(self._state_of("Platform"))

    def refusal(self, event: str, label: str) -> Refusal:
        """Why Flight makes no transition on ``event`` now (``label`` names the command)."""
        flight = self.model.automata["Flight"]
        state = self.flight().value
        specs = flight.table[flight.states.index(state)].get(self.model.events.index[event], ())
        if not specs:
            return Refusal(RefusalKind.BUSY, f"the DRC is in {state}")
        guard = specs[0].guard
        if guard is None:  # pragma: no cover - an unguarded transition is always taken
            return Refusal(RefusalKind.NOT_ACCEPTED, "the DRC automaton did not take it")
        name = blocking_condition(guard, self.conditions)
        return Refusal(RefusalKind.NOT_ACCEPTED, REFUSALS.get(name, name).format(label=label))

    # --- loop -----------------------------------------------------------------------------
    def post(self, name: str, data: bytes) -> PostStatus:
        """Queue an ``Api-*-EV`` event from a command layer."""
        return self.interpreter.post_external(name, data)

    def _flush(self) -> None:
        outgoing = self.interpreter.take_outbox()
        if self.transport is None:
            self.undeliverable += len(outgoing)
            return
        for event in outgoing:
            if self.transport.send(event) is not SendStatus.SENT:
                self.undeliverable += 1

    def step(self, now: float) -> StepResult:
        """Communicate, execute one macro step at DRC time ``now``, communicate again."""
        self.status.now = max(self.status.now, now)
        self._flush()
        if self.transport is not None:
            received = self.transport.receive()
            for computer in self.transport.restarts():
                for listener in self.listeners:
                    listener.on_restart(computer, self.status.now)
            for event in received:
                for listener in self.listeners:
                    listener.on_wire(event, self.status.now)
                self.interpreter.post_wire(event)
        before = self.flight()
        result = self.interpreter.execute(self.status.now)
        after = self.flight()
        if after is not before:
            waiting = after in (FlightState.SETTLING, FlightState.BRAKING)
            self.waiting_since = self.status.now if waiting else None
        for listener in self.listeners:
            listener.after_step(self.status.now)
        self._flush()
        return result
