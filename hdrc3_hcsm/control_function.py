"""The control-function template of chapter 6.1.1 and the set of functions the flags select.

Every control function goes through *initializing*, *running* and *stopping* driven by an input
flag, and reports errors through a status flag. The framework owns this lifecycle; a function
only implements :meth:`ControlFunction.step`, called once per main-loop iteration with the phase
it is in. :class:`ControlFunctionSet` turns the HCSM action flags (mode selection, start, stop)
into input flags and exposes the function status as atomic conditions for guards.
"""

from __future__ import annotations

import enum
import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Protocol

from hdrc3_hcsm.memory import ActionFlags, MemoryBank

_log = logging.getLogger(__name__)


class Phase(enum.Enum):
    """Internal state a control function is asked to work in."""

    INITIALIZING = "initializing"
    RUNNING = "running"
    STOPPING = "stopping"


class HookResult(enum.Enum):
    """What a function reports for one call: phase finished, needs more calls, or failed."""

    DONE = "done"
    BUSY = "busy"
    FAILED = "failed"


class FunctionState(enum.Enum):
    """Lifecycle state of a control function as kept by the template."""

    OFF = "off"
    INITIALIZING = "initializing"
    RUNNING = "running"
    STOPPING = "stopping"
    ERROR = "error"


class InputFlag(enum.Enum):
    """The input flag that switches between the internal states."""

    NONE = "none"
    START = "start"
    STOP = "stop"


class StatusFlag(enum.Enum):
    """The status flag used for error handling."""

    OK = "ok"
    ERROR = "error"


class ControlFunction(Protocol):
    """The one hook a control function implements."""

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Do the work of ``phase`` for one iteration at time ``now``."""


class FlagConsumer(Protocol):
    """Anything RunControlFunctions calls after the macro step with the flags of the iteration."""

    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        """React to the flags set in this iteration."""


_AFTER_DONE = {
    FunctionState.INITIALIZING: FunctionState.RUNNING,
    FunctionState.RUNNING: FunctionState.RUNNING,
    FunctionState.STOPPING: FunctionState.OFF,
}
_PHASE = {
    FunctionState.INITIALIZING: Phase.INITIALIZING,
    FunctionState.RUNNING: Phase.RUNNING,
    FunctionState.STOPPING: Phase.STOPPING,
}


class ControlFunctionRunner:
    """The template around one control function: internal states, input and status flags."""

    def __init__(self, name: str, function: ControlFunction) -> None:
        self.name = name
        self.function = function
        self.state = FunctionState.OFF
        self.input = InputFlag.NONE
        self.status = StatusFlag.OK
        self.last_error = ""

    def command(self, flag: InputFlag) -> None:
        """Set the input flag; it is consumed by the next :meth:`run`."""
        self.input = flag

    def run(self, memory: MemoryBank, now: float) -> FunctionState:
        """Apply the input flag, then call the function once in its current phase."""
        if self.input is InputFlag.START and self.state in (FunctionState.OFF, FunctionState.ERROR):
            self.state, self.status, self.last_error = FunctionState.INITIALIZING, StatusFlag.OK, ""
        elif self.input is InputFlag.STOP and self.state is not FunctionState.OFF:
            self.state = FunctionState.STOPPING
        self.input = InputFlag.NONE
        phase = _PHASE.get(self.state)
        if phase is None:
            return self.state
        try:
            result = self.function.step(phase, memory, now)
        except Exception as exc:  # a function is user code: an exception is its failure
            self.last_error = repr(exc)
            _log.error("control function %s failed in %s: %r", self.name, phase.value, exc)
            result = HookResult.FAILED
        if result is HookResult.DONE:
            self.state = _AFTER_DONE[self.state]
        elif result is HookResult.FAILED:
            self.status = StatusFlag.ERROR
            # A failed stop still leaves the function off; other failures park it in ERROR.
            stopping = self.state is FunctionState.STOPPING
            self.state = FunctionState.OFF if stopping else FunctionState.ERROR
        return self.state


@dataclass(frozen=True)
class FunctionSetNames:
    """Flag and condition names the Control Mode automaton uses (see models/pfc_modes.hcsm)."""

    start_flag: str = "Ctrl-Start-AC"
    stop_flag: str = "Ctrl-Stop-AC"
    ready_condition: str = "Ctrl-Ready-CO"
    failed_condition: str = "Ctrl-Failed-CO"
    halted_condition: str = "Ctrl-Halted-CO"


class ControlFunctionSet:
    """Selects one function by its mode flag, forwards start/stop, runs the selected one."""

    def __init__(
        self,
        functions: Mapping[str, ControlFunctionRunner],
        names: FunctionSetNames | None = None,
    ) -> None:
        self.functions = dict(functions)
        self.names = names or FunctionSetNames()
        self.current: ControlFunctionRunner | None = None
        self.rejected_selections = 0

    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        """RunControlFunctions for this set: update the active mode from the flags, execute it."""
        for flag, runner in self.functions.items():
            if not flags.is_set(flag) or runner is self.current:
                continue
            if self.current is None or self.current.state is FunctionState.OFF:
                self.current = runner
            else:
                # Control Mode only selects from Ctrl-Off-ST; anything else is a model bug.
                self.rejected_selections += 1
                _log.error("mode %s selected while %s is active", flag, self.current.name)
        if self.current is None:
            return
        if flags.is_set(self.names.stop_flag):
            self.current.command(InputFlag.STOP)
        elif flags.is_set(self.names.start_flag):
            self.current.command(InputFlag.START)
        self.current.run(memory, now)

    def conditions(self) -> dict[str, Callable[[], bool]]:
        """Atomic conditions about the selected function for the HCSM guards."""
        return {
            self.names.ready_condition: lambda: self._in(FunctionState.RUNNING),
            self.names.failed_condition: lambda: self._in(FunctionState.ERROR),
            self.names.halted_condition: lambda: (
                self.current is None or self.current.state is FunctionState.OFF
            ),
        }

    def _in(self, state: FunctionState) -> bool:
        return self.current is not None and self.current.state is state
