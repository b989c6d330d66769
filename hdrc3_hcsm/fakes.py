"""Test fakes shipped beside the code: a scripted control function."""

from __future__ import annotations

from hdrc3_hcsm.control_function import HookResult, Phase
from hdrc3_hcsm.memory import MemoryBank


class ScriptedFunction:
    """A control function that needs ``init_calls`` calls to initialize and records its calls."""

    def __init__(self, init_calls: int = 1, fail_init: bool = False, stop_calls: int = 1) -> None:
        self.init_calls = init_calls
        self.stop_calls = stop_calls
        self.fail_init = fail_init
        self.calls: list[tuple[Phase, float]] = []

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Succeed each phase after the scripted number of calls."""
        self.calls.append((phase, now))
        count = 0
        for p, _ in reversed(self.calls):
            if p is not phase:
                break
            count += 1
        if phase is Phase.RUNNING:
            return HookResult.BUSY
        if phase is Phase.INITIALIZING and self.fail_init:
            return HookResult.FAILED
        needed = self.init_calls if phase is Phase.INITIALIZING else self.stop_calls
        return HookResult.DONE if count >= needed else HookResult.BUSY
