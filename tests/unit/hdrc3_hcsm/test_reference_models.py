"""Figure 14 and Figure 23 of the chapter, reproduced on the shipped pfc_modes.hcsm model."""

from __future__ import annotations

from dataclasses import dataclass

from hdrc3_hcsm.conditions import ConditionTable
from hdrc3_hcsm.control_function import (
    ControlFunctionRunner,
    ControlFunctionSet,
    FunctionState,
    StatusFlag,
)
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.fakes import ScriptedFunction
from hdrc3_hcsm.interpreter import Interpreter
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.main_loop import MainLoop
from hdrc3_hcsm.memory import ActionFlags, MemoryBank
from hdrc3_hcsm.models import model_path
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.trace import TraceRecorder, fired_ids
from hdrc3_hcsm.transport import LoopbackNetwork, LoopbackTransport

PERIOD = 0.02


class FlagLog:
    """Consumer that remembers the flags of every iteration (before they are unset)."""

    def __init__(self) -> None:
        self.seen: list[frozenset[str]] = []

    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        self.seen.append(flags.active())


@dataclass
class Rig:
    loop: MainLoop
    interp: Interpreter
    conds: ConditionTable
    functions: ControlFunctionSet
    hover: ControlFunctionRunner
    traj: ControlFunctionRunner
    trace: TraceRecorder
    flags: FlagLog
    drc: LoopbackTransport
    time: float = 0.0

    def tick(self, n: int = 1) -> None:
        for _ in range(n):
            self.loop.iterate(self.time)
            self.time += PERIOD

    def drc_names(self) -> list[str]:
        return [e.name for e in self.drc.receive()]


def make_rig() -> Rig:
    model = compile_model(load_file(model_path("pfc_modes.hcsm")))
    conds = ConditionTable(
        ["Braking-Done-CO", "Hover-Stable-CO", "Single-Segment-CO", "Traj-Arrived-CO"]
    )
    hover = ControlFunctionRunner("hover", ScriptedFunction())
    traj = ControlFunctionRunner("traj3d", ScriptedFunction())
    functions = ControlFunctionSet({"Hover-Mode-AC": hover, "Traj3D-Mode-AC": traj})
    trace = TraceRecorder()
    interp = Interpreter(model, {**conds.callables(), **functions.conditions()}, trace=trace)
    network = LoopbackNetwork()
    flags = FlagLog()
    loop = MainLoop(interp, [functions, flags], network.endpoint("PFC"))
    return Rig(loop, interp, conds, functions, hover, traj, trace, flags, network.endpoint("DRC"))


FIGURE_14 = [
    ("pulse", "A.1"),  # Mode Switch starts: make sure no control function is active
    ("Ctrl-Stop-EV", "B.1"),
    ("Ctrl-Stopped-EV", "A.2"),  # braking (SET Braking-AC), event to the DRC
    ("pulse", "A.3"),  # Braking-Done-CO: save position, PFC-Hover-EV + Ctrl-Start-EV
    ("PFC-Hover-EV", "B.2"),
    ("Ctrl-Start-EV", "B.7"),
    ("pulse", "B.8"),  # hover function initialized: Ctrl-Ok-EV
    ("Ctrl-Ok-EV", "A.4"),
    ("pulse", "A.5"),  # Hover-Stable-CO: Hover-Stable-EV to the DRC, SET PFC-Auto-Idle-AC
]


def fly_figure_14(rig: Rig) -> None:
    rig.interp.memory.write("Position-DO", b"pos:58.4,15.6,60.0")
    rig.tick(2)
    assert rig.interp.configuration()[0] == "Mode-Switch:Braking-ST"
    rig.conds.set("Braking-Done-CO")
    rig.tick(3)
    assert rig.interp.configuration()[0] == "Mode-Switch:Stabilizing-ST"
    rig.conds.set("Hover-Stable-CO")
    rig.tick(2)


def test_figure_14_control_mode_switching() -> None:
    rig = make_rig()
    fly_figure_14(rig)
    assert fired_ids(rig.trace) == FIGURE_14
    assert rig.interp.configuration() == ("Mode-Switch:Hovering-ST", "Control-Mode:Ctrl-Run-ST")
    assert rig.interp.memory.read("Hovering-DO") == b"pos:58.4,15.6,60.0"
    assert rig.hover.state is FunctionState.RUNNING
    assert any("Braking-AC" in f for f in rig.flags.seen)
    assert any({"Hover-Mode-AC", "Ctrl-Start-AC"} <= f for f in rig.flags.seen)
    assert any("PFC-Auto-Idle-AC" in f for f in rig.flags.seen)
    assert rig.drc_names() == ["Braking-Started-EV", "Hover-Stable-EV"]


FIGURE_23 = [
    ("Traj3D-EV", "A.6"),  # segment saved in Traj3D-DO, stop the hovering function
    ("Ctrl-Stop-EV", "B.11"),
    ("pulse", "B.10"),  # hovering function stopped
    ("Ctrl-Stopped-EV", "C.1"),  # Traj3D started in its init state: PFC-Traj3D-EV + Ctrl-Start
    ("PFC-Traj3D-EV", "B.3"),
    ("Ctrl-Start-EV", "B.7"),
    ("pulse", "B.8"),
    ("Ctrl-Ok-EV", "C.2"),  # Single-Segment-CO: segment accepted (to the DRC)
    ("pulse", "C.3"),  # Traj-Arrived-CO: Traj-Arrived-EV to the DRC, stop the PFCM
    ("Ctrl-Stop-EV", "B.11"),
    ("pulse", "B.10"),
    ("Ctrl-Stopped-EV", "C.4"),  # Traj3D reaches its exit state
    ("exit", "A.7"),  # Mode Switch engages the default hovering function again
    ("PFC-Hover-EV", "B.2"),
    ("Ctrl-Start-EV", "B.7"),
    ("pulse", "B.8"),
    ("Ctrl-Ok-EV", "A.4"),
    ("pulse", "A.5"),
]


def test_figure_23_path_execution() -> None:
    rig = make_rig()
    fly_figure_14(rig)
    rig.drc_names()
    rig.trace.clear()
    segment = b"segment:cubic;v_end=0"
    rig.drc.send(WireEvent(1022, "Traj3D-EV", segment, "DRC", "PFC"))
    rig.tick()
    assert rig.interp.configuration()[:2] == (
        "Mode-Switch:Traj3D-ST",
        "Mode-Switch/Traj3D-ST/Traj3D:Traj3D-Init-ST",
    )
    assert rig.interp.memory.read("Traj3D-DO") == segment
    rig.tick()
    assert rig.traj.state is FunctionState.RUNNING
    rig.conds.set("Single-Segment-CO")
    rig.tick(2)
    assert "Mode-Switch/Traj3D-ST/Traj3D:Traj3D-Single-ST" in rig.interp.configuration()
    rig.interp.memory.write("Traj3D-End-DO", b"wp:120.0,40.0,60.0")
    rig.conds.set("Traj-Arrived-CO")
    rig.tick(5)
    assert fired_ids(rig.trace) == FIGURE_23
    assert rig.interp.configuration() == ("Mode-Switch:Hovering-ST", "Control-Mode:Ctrl-Run-ST")
    assert rig.interp.memory.read("Hovering-DO") == b"wp:120.0,40.0,60.0"
    assert (rig.hover.state, rig.traj.state) == (FunctionState.RUNNING, FunctionState.OFF)
    assert rig.drc_names() == ["Segment-Accepted-EV", "Traj-Arrived-EV", "Hover-Stable-EV"]


def test_failed_initialization_goes_through_the_error_states() -> None:
    rig = make_rig()
    rig.hover.function = ScriptedFunction(fail_init=True)
    rig.conds.set("Braking-Done-CO")
    rig.tick(5)
    assert fired_ids(rig.trace)[3:] == [
        ("pulse", "A.3"),
        ("PFC-Hover-EV", "B.2"),
        ("Ctrl-Start-EV", "B.7"),
        ("pulse", "B.9"),  # Ctrl-Failed-CO: the status flag reports the failed initialization
        ("Ctrl-Error-EV", "A.8"),
        ("pulse", "A.10"),  # Mode Switch stops the failed function and brakes again
        ("Ctrl-Stop-EV", "B.13"),
        ("pulse", "B.10"),
        ("Ctrl-Stopped-EV", "A.2"),
    ]
    # The status flag keeps the error until the next start; the function itself is off.
    assert (rig.hover.state, rig.hover.status) == (FunctionState.OFF, StatusFlag.ERROR)
    assert "Ctrl-Failure-EV" in rig.drc_names()
