from __future__ import annotations

from hdrc3_control.event_codec import decode, encode
from hdrc3_control.event_protocol import EventProtocol, SendLog, SendRecord, Unanswered
from hdrc3_control.kernel import load_model
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.trace import FiredTransition, TraceRecord

REJECTED_ID = load_model().events.id_of("Cmd-Rejected-EV")


def ev(name: str, data: bytes, event_id: int = 1) -> WireEvent:
    return WireEvent(event_id, name, data, "PFC", "DRC")


def rec(event: str, tid: str, trigger: str = "pulse") -> SendRecord:
    return SendRecord(event, tid, trigger, "Mode-Switch:Hovering-ST")


def test_id_only_replies_are_trimmed_and_finals_sent_once() -> None:
    p = EventProtocol(lambda: "", REJECTED_ID)
    payload = encode(4, (1.0, 2.0))  # the command's payload with its arguments
    out = p.outgoing(
        [ev("Cmd-Accepted-EV", payload), ev("Cmd-Finished-EV", payload)],
        [rec("Cmd-Accepted-EV", "A.28"), rec("Cmd-Finished-EV", "A.29")],
        [],
    )
    assert [(e.name, e.data) for e in out] == [
        ("Cmd-Accepted-EV", encode(4)),
        ("Cmd-Finished-EV", encode(4)),
    ]
    again = p.outgoing([ev("Cmd-Finished-EV", payload)], [rec("Cmd-Finished-EV", "A.5")], [])
    assert again == [] and p.dropped == 1 and p.current == 0


def test_a_function_s_note_rides_on_its_command_s_final_reply_once() -> None:
    notes = {4: "landed on vision: pad L1", 5: "never said"}
    p = EventProtocol(lambda: "", REJECTED_ID, finish_note=lambda cid: notes.pop(cid, ""))
    p.active = {4, 5}
    out = p.outgoing(
        [ev("Cmd-Finished-EV", encode(4)), ev("Cmd-Failed-EV", encode(5, (), "no fix"))],
        [rec("Cmd-Finished-EV", "A.29"), rec("Cmd-Failed-EV", "C.12", trigger="Fn-Failed-EV")],
        [],
    )
    assert [(e.name, decode(e.data, 0, with_reason=True).reason) for e in out] == [
        ("Cmd-Finished-EV", "landed on vision: pad L1"),
        ("Cmd-Failed-EV", "no fix"),  # a failure keeps its own reason; the note is dropped
    ]
    assert notes == {}


def test_a_function_s_plan_rides_on_its_command_s_acceptance_once() -> None:
    plans = {4: "landing on GPS and barometer: no vision fix of pad L1: no vision pipeline"}
    p = EventProtocol(lambda: "", REJECTED_ID, accept_note=lambda cid: plans.pop(cid, ""))
    out = p.outgoing(
        [ev("Cmd-Accepted-EV", encode(4, (0.0,))), ev("Cmd-Accepted-EV", encode(5, (0.0,)))],
        [rec("Cmd-Accepted-EV", "L.2"), rec("Cmd-Accepted-EV", "A.28")],
        [],
    )
    assert [(e.name, decode(e.data, 0, with_reason=True).reason) for e in out] == [
        ("Cmd-Accepted-EV", "landing on GPS and barometer: no vision fix of pad L1: no vision "
         "pipeline"),
        ("Cmd-Accepted-EV", ""),  # no note: the id alone, as before
    ]  # fmt: skip
    assert out[1].data == encode(5) and plans == {} and p.active == {4, 5}


def test_reasons_come_from_table_function_failure_or_function_event() -> None:
    p = EventProtocol(lambda: "rotor at 0 rpm", REJECTED_ID)
    p.active = {1, 2, 3}
    out = p.outgoing(
        [
            ev("Cmd-Cancelled-EV", encode(1)),
            ev("Cmd-Rejected-EV", encode(2)),
            ev("Cmd-Failed-EV", encode(3, (), "safety braking")),
        ],
        [
            rec("Cmd-Cancelled-EV", "W.4"),
            rec("Cmd-Rejected-EV", "A.14", trigger="Ctrl-Error-EV"),
            rec("Cmd-Failed-EV", "C.12", trigger="Fn-Failed-EV"),
        ],
        [],
    )
    reasons = [decode(e.data, 0, with_reason=True).reason for e in out]
    assert reasons[0].startswith("RC switch to manual")
    assert reasons[1] == "rotor at 0 rpm"
    assert reasons[2] == "safety braking"


def test_ui_commands_get_no_replies_and_unanswered_commands_are_rejected() -> None:
    p = EventProtocol(lambda: "", REJECTED_ID)
    out = p.outgoing(
        [ev("Cmd-Accepted-EV", encode(0)), ev("Hover-Stable-EV", b"", 1021)],
        [rec("Cmd-Accepted-EV", "A.40"), rec("Hover-Stable-EV", "A.5")],
        [Unanswered("FCL-Land-EV", encode(9, (0.0,)), "Braking-ST"), Unanswered("X", b"", "")],
    )
    assert [(e.name, e.event_id) for e in out] == [
        ("Hover-Stable-EV", 1021),
        ("Cmd-Rejected-EV", REJECTED_ID),
    ]
    rejected = decode(out[1].data, 0, with_reason=True)
    assert rejected.command_id == 9 and "Braking-ST" in rejected.reason


def test_send_log_pairs_external_events_with_their_records() -> None:
    log = SendLog(frozenset({"FCL-Land-EV"}))
    log.posted("FCL-Land-EV", encode(3, (1.0,)))
    config = (
        "Root:Run-ST",
        "Root/Run-ST/Run/Running-ST/Auto-Switch/Auto-ST/Mode-Switch:Braking-ST",
    )
    log.record(TraceRecord("PFC", 1, 1, 0.0, "FCL-Land-EV", "external", (), (), config))
    fired = FiredTransition(
        "A.5", "x/Mode-Switch", "Stabilizing-ST", "Hovering-ST",
        ("SEND Hover-Stable-EV to DRC", "SET PFC-Auto-Idle-AC", "SEND Ctrl-Stop-EV"),
    )  # fmt: skip
    log.record(TraceRecord("PFC", 1, 2, 0.0, "pulse", "pulse", (fired,), (), config))
    sends, unanswered = log.take()
    assert [(s.event, s.tid, s.where) for s in sends] == [
        ("Hover-Stable-EV", "A.5", "Mode-Switch:Stabilizing-ST")
    ]
    assert unanswered == [Unanswered("FCL-Land-EV", encode(3, (1.0,)), "Mode-Switch:Braking-ST")]
    assert log.take() == ([], [])
