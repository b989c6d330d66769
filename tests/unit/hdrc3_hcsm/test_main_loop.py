from __future__ import annotations

from hdrc3_hcsm.event import PostStatus, WireEvent
from hdrc3_hcsm.interpreter import Interpreter
from hdrc3_hcsm.loader import load_text
from hdrc3_hcsm.main_loop import CommunicationResult, MainLoop
from hdrc3_hcsm.memory import ActionFlags, MemoryBank
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.transport import LoopbackNetwork

MODEL = """
model M on PFC; computers PFC, DRC;
event Go-EV = 11 from DRC; event Ack-EV = 12 to DRC;
flag Run-AC;
automaton A M { init S-ST; state T-ST;
    A.1: S-ST -> T-ST on Go-EV / SET Run-AC, SEND Ack-EV data cache to DRC;
    A.2: T-ST -> S-ST on Go-EV; }
root M;
"""


class Recorder:
    def __init__(self) -> None:
        self.calls: list[tuple[float, frozenset[str], bool]] = []

    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        # The memory bank is locked by the loop while functions run (RLock: re-entrant here).
        self.calls.append((now, flags.active(), memory.lock.acquire(blocking=False)))
        memory.lock.release()


def make() -> tuple[MainLoop, Recorder, object]:
    interp = Interpreter(compile_model(load_text(MODEL, "m.hcsm")), {})
    net = LoopbackNetwork()
    rec = Recorder()
    return MainLoop(interp, [rec], net.endpoint("PFC")), rec, net.endpoint("DRC")


def test_algorithm_1_order_communicate_execute_run() -> None:
    loop, rec, drc = make()
    drc.send(WireEvent(11, "Go-EV", b"hello", "DRC", "PFC"))  # type: ignore[attr-defined]
    first = loop.iterate(0.0)
    assert first.communication == CommunicationResult(0, 0, 1, 0)
    assert first.step.transitions == 1
    assert rec.calls == [(0.0, frozenset({"Run-AC"}), True)]
    assert loop.interpreter.flags.active() == frozenset()  # unset after the iteration
    assert drc.receive() == []  # type: ignore[attr-defined]
    second = loop.iterate(0.02)  # the Ack goes out in the next Communicate
    assert second.communication.sent == 1
    [ack] = drc.receive()  # type: ignore[attr-defined]
    assert (ack.name, ack.event_id, ack.data, ack.sequence) == ("Ack-EV", 12, b"hello", 1)
    assert rec.calls[1][1] == frozenset()


def test_received_events_that_do_not_fit_are_rejected() -> None:
    loop, _, drc = make()
    for bad in (
        WireEvent(99, "Go-EV", b"", "DRC", "PFC"),  # id mismatch
        WireEvent(13, "Who-EV", b"", "DRC", "PFC"),  # unknown
    ):
        drc.send(bad)  # type: ignore[attr-defined]
    result = loop.iterate(0.0)
    assert result.communication == CommunicationResult(0, 0, 0, 2)
    stats = loop.interpreter.stats
    assert stats.by_status == {PostStatus.ID_MISMATCH: 1, PostStatus.UNKNOWN_EVENT: 1}
    assert stats.unknown_events == 1
    wrong = WireEvent(11, "Go-EV", b"", "DRC", "PPC")
    assert loop.interpreter.post_wire(wrong) is PostStatus.WRONG_TARGET


def test_without_transport_outgoing_events_are_counted_undeliverable() -> None:
    interp = Interpreter(compile_model(load_text(MODEL, "m.hcsm")), {})
    loop = MainLoop(interp)
    interp.post_external("Go-EV", b"x")
    loop.iterate(0.0)
    assert loop.iterate(0.02).communication == CommunicationResult(0, 1, 0, 0)


DRC_MODEL = """
model D on DRC; computers PFC, DRC;
event Go-EV = 11 to PFC; event Ack-EV = 12 from PFC;
automaton A D { init Wait-ST; state Sent-ST; state Done-ST;
    A.1: Wait-ST -> Sent-ST on pulse / SEND Go-EV to PFC;
    A.2: Sent-ST -> Done-ST on Ack-EV; }
root D;
"""


def test_two_computers_each_with_its_own_interpreter() -> None:
    net = LoopbackNetwork()
    pfc = MainLoop(
        Interpreter(compile_model(load_text(MODEL, "pfc.hcsm")), {}), (), net.endpoint("PFC")
    )
    drc = MainLoop(
        Interpreter(compile_model(load_text(DRC_MODEL, "drc.hcsm")), {}), (), net.endpoint("DRC")
    )
    for k in range(4):  # DRC sends Go-EV, PFC answers Ack-EV one Communicate later
        drc.iterate(k * 0.02)
        pfc.iterate(k * 0.02)
    assert drc.interpreter.configuration() == ("D:Done-ST",)
    assert pfc.interpreter.configuration() == ("M:T-ST",)
