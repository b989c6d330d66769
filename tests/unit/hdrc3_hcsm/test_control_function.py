from __future__ import annotations

import pytest

from hdrc3_hcsm.control_function import (
    ControlFunctionRunner,
    ControlFunctionSet,
    FunctionState,
    HookResult,
    InputFlag,
    Phase,
    StatusFlag,
)
from hdrc3_hcsm.fakes import ScriptedFunction
from hdrc3_hcsm.memory import ActionFlags, MemoryBank

MEM = MemoryBank({})


class Exploding:
    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        raise RuntimeError("boom")


@pytest.mark.parametrize(
    ("function", "inputs", "states", "status"),
    [
        (ScriptedFunction(1), [InputFlag.START, InputFlag.NONE], ["running", "running"], "ok"),
        (ScriptedFunction(2), [InputFlag.START, InputFlag.NONE], ["initializing", "running"], "ok"),
        (ScriptedFunction(fail_init=True), [InputFlag.START], ["error"], "error"),
        (ScriptedFunction(1), [InputFlag.START, InputFlag.STOP], ["running", "off"], "ok"),
        (
            ScriptedFunction(1, stop_calls=2),
            [InputFlag.START, InputFlag.STOP, InputFlag.NONE],
            ["running", "stopping", "off"],
            "ok",
        ),
        (Exploding(), [InputFlag.START], ["error"], "error"),
        (ScriptedFunction(1), [InputFlag.STOP], ["off"], "ok"),
    ],
)
def test_template_lifecycle(
    function: object, inputs: list[InputFlag], states: list[str], status: str
) -> None:
    runner = ControlFunctionRunner("f", function)  # type: ignore[arg-type]
    seen = []
    for i, flag in enumerate(inputs):
        runner.command(flag)
        seen.append(runner.run(MEM, i * 0.02).value)
    assert seen == states
    assert runner.status is StatusFlag(status)


def test_set_selects_by_flag_and_exposes_conditions() -> None:
    hover = ControlFunctionRunner("hover", ScriptedFunction())
    traj = ControlFunctionRunner("traj", ScriptedFunction())
    fset = ControlFunctionSet({"Hover-AC": hover, "Traj-AC": traj})
    conds = fset.conditions()
    flags = ActionFlags(["Hover-AC", "Traj-AC", "Ctrl-Start-AC", "Ctrl-Stop-AC"])
    assert conds["Ctrl-Halted-CO"]() and not conds["Ctrl-Ready-CO"]()
    flags.raise_flag("Hover-AC")
    flags.raise_flag("Ctrl-Start-AC")
    fset.run(flags, MEM, 0.0)
    flags.clear()
    assert fset.current is hover and conds["Ctrl-Ready-CO"]()
    flags.raise_flag("Traj-AC")  # selecting while hover runs is refused
    fset.run(flags, MEM, 0.02)
    flags.clear()
    assert fset.current is hover and fset.rejected_selections == 1
    flags.raise_flag("Ctrl-Stop-AC")
    fset.run(flags, MEM, 0.04)
    assert hover.state is FunctionState.OFF and conds["Ctrl-Halted-CO"]()
    assert [p for p, _ in hover.function.calls] == [  # type: ignore[attr-defined]
        Phase.INITIALIZING,
        Phase.RUNNING,
        Phase.STOPPING,
    ]
