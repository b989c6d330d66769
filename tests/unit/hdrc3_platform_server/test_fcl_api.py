"""Every row of the FCL semantics table (README) on the pure core with the fake PFC."""

from __future__ import annotations

import math

import pytest

from hdrc3_hcsm.loader import load_text
from hdrc3_hcsm.tables import compile_model
from hdrc3_platform_server import drc
from hdrc3_platform_server.codes import EventKind, FclCode, FclCommand
from hdrc3_platform_server.drc import FlightState, PlatformState, model_path
from hdrc3_platform_server.fakes import FakeRig
from hdrc3_platform_server.geo_frame import WorldFrame

FRAME = WorldFrame(55.70, 13.47, 95.0)
C = FclCommand


def rig_in(state: str) -> FakeRig:
    """A rig whose DRC is in the named situation."""
    rig = FakeRig(FRAME, on_ground=state in ("ground", "unknown", "ground_manual"))
    if state == "unknown":
        rig.pfc_online = False
        rig.run(2.5)  # longer than the 2 s after which PFC data counts as stale
    elif state in ("manual", "ground_manual"):
        rig.pfc.auto = False
        rig.run(0.1)
    elif state == "busy":
        assert rig.core.fcl.submit(C.TRAJ3D_FLYTO, args(C.TRAJ3D_FLYTO), rig.t).code is FclCode.OK
    return rig


def args(command: FclCommand) -> tuple[float, ...]:
    """Valid arguments of each command (targets 100 m east of the origin, 30 m up)."""
    lon, lat, alt = FRAME.to_wgs84(100.0, 0.0, 30.0)
    return {
        C.LAND: (0.5,),
        C.YAW: (0.5,),
        C.CLIMB: (FRAME.altitude + 20.0,),
        C.TRAJ3D_FLYTO: (lon, lat, alt, 8.0),
        C.TRAJ3D: (0, 0, 10, 50, 0, 10, 1, 0, 0, 1, 0, 0, 5.0, 0.0),
    }.get(command, ())


ROWS = [
    # command, state, immediate answer, terminal event kind (None: no command started)
    (C.TAKEOFF, "unknown", FclCode.NOT_ACCEPTED, None),
    (C.TAKEOFF, "ground", FclCode.OK, EventKind.FINISHED),
    (C.TAKEOFF, "hover", FclCode.NOT_ACCEPTED, None),
    (C.TAKEOFF, "manual", FclCode.NOT_ACCEPTED, None),
    (C.TAKEOFF, "ground_manual", FclCode.NOT_ACCEPTED, None),
    (C.TAKEOFF, "busy", FclCode.BUSY, None),
    (C.LAND, "unknown", FclCode.NOT_ACCEPTED, None),
    (C.LAND, "ground", FclCode.NOT_ACCEPTED, None),
    (C.LAND, "hover", FclCode.OK, EventKind.FINISHED),
    (C.LAND, "manual", FclCode.NOT_ACCEPTED, None),
    (C.LAND, "busy", FclCode.BUSY, None),
    (C.YAW, "ground", FclCode.NOT_ACCEPTED, None),
    (C.YAW, "hover", FclCode.OK, EventKind.FINISHED),
    (C.YAW, "manual", FclCode.NOT_ACCEPTED, None),
    (C.YAW, "busy", FclCode.BUSY, None),
    (C.CLIMB, "ground", FclCode.NOT_ACCEPTED, None),
    (C.CLIMB, "hover", FclCode.OK, EventKind.FINISHED),
    (C.CLIMB, "busy", FclCode.BUSY, None),
    (C.TRAJ3D_FLYTO, "unknown", FclCode.NOT_ACCEPTED, None),
    (C.TRAJ3D_FLYTO, "ground", FclCode.NOT_ACCEPTED, None),
    (C.TRAJ3D_FLYTO, "hover", FclCode.OK, EventKind.FINISHED),
    (C.TRAJ3D_FLYTO, "manual", FclCode.NOT_ACCEPTED, None),
    (C.TRAJ3D_FLYTO, "busy", FclCode.BUSY, None),
    (C.TRAJ3D, "ground", FclCode.NOT_ACCEPTED, None),
    (C.TRAJ3D, "hover", FclCode.OK, EventKind.FINISHED),
    (C.TRAJ3D, "busy", FclCode.BUSY, None),
    (C.TRACK, "ground", FclCode.NOT_ACCEPTED, None),
    (C.TRACK, "hover", FclCode.OK, EventKind.CANCELLED),  # runs until fcl_cancel
    (C.TRACK, "busy", FclCode.BUSY, None),
    (C.CANCEL, "unknown", FclCode.OK, EventKind.FINISHED),
    (C.CANCEL, "ground", FclCode.OK, EventKind.FINISHED),
    (C.CANCEL, "hover", FclCode.OK, EventKind.FINISHED),
    (C.CANCEL, "manual", FclCode.OK, EventKind.FINISHED),
    (C.CANCEL, "busy", FclCode.OK, EventKind.FINISHED),
    (C.EMERGENCY_BRAKE, "unknown", FclCode.OK, EventKind.FINISHED),
    (C.EMERGENCY_BRAKE, "ground", FclCode.OK, EventKind.FINISHED),
    (C.EMERGENCY_BRAKE, "hover", FclCode.OK, EventKind.FINISHED),
    (C.EMERGENCY_BRAKE, "manual", FclCode.OK, EventKind.FINISHED),
    (C.EMERGENCY_BRAKE, "busy", FclCode.OK, EventKind.FINISHED),
]


def refusal_words(command: FclCommand, state: str) -> str:
    """Words of the reason the DRC automaton gives (its first failing guard condition)."""
    if state == "busy":
        return "fcl_traj3d_flyto (command"
    if state == "unknown":
        return "no state data from the control kernel"
    if command is C.TAKEOFF:
        return "manual mode" if state == "ground_manual" else "only be commanded when"
    return "needs the aircraft hovering" if state == "ground" else "manual mode"


@pytest.mark.parametrize(("command", "state", "code", "final"), ROWS)
def test_semantics_row(
    command: FclCommand, state: str, code: FclCode, final: EventKind | None
) -> None:
    rig = rig_in(state)
    before = len(rig.log.events)
    answer = rig.core.fcl.submit(command, args(command), rig.t)
    assert answer.code is code, answer.reason
    if code is not FclCode.OK:
        assert refusal_words(command, state) in answer.reason and answer.command_id == 0
        rig.run(0.5)
        # a refused command produces no event of its own
        assert all(e.command_id != 0 for e in rig.log.events[before:])
        return
    assert answer.command_id > 0
    if command is C.TRACK:
        rig.run(5.0)  # fcl_track has no end of its own: accepted, it follows the car
        kinds = [e.kind for e in rig.log.of(answer.command_id)]
        assert kinds == [EventKind.INFO], kinds
        rig.core.fcl.submit(C.CANCEL, (), rig.t)
    event = rig.run_until_final(answer.command_id)
    assert event is not None and event.kind is final, event
    assert [e.kind for e in rig.log.of(answer.command_id)].count(event.kind) == 1


def test_busy_command_is_cancelled_by_cancel_and_brake() -> None:
    for stopper in (C.CANCEL, C.EMERGENCY_BRAKE):
        rig = rig_in("busy")
        running = rig.core.fcl.current
        assert running is not None
        rig.core.fcl.submit(stopper, (), rig.t)
        final = rig.log.final(running.command_id)
        assert final is not None and final.kind is EventKind.CANCELLED
        assert stopper.label in final.reason or "emergency brake" in final.reason


def test_new_command_accepted_right_after_cancel() -> None:
    rig = rig_in("busy")
    rig.core.fcl.submit(C.CANCEL, (), rig.t)
    rig.run(0.1)
    assert rig.core.fcl.submit(C.YAW, (1.0,), rig.t).code is FclCode.OK


def test_takeoff_flyto_land_sequence_ends_on_ground() -> None:
    rig = rig_in("ground")
    for command in (C.TAKEOFF, C.TRAJ3D_FLYTO, C.LAND):
        answer = rig.core.fcl.submit(command, args(command), rig.t)
        assert answer.code is FclCode.OK, answer.reason
        event = rig.run_until_final(answer.command_id)
        assert event is not None and event.kind is EventKind.FINISHED
    rig.run(0.2)
    assert rig.core.kernel.platform() is PlatformState.GROUND
    assert rig.published[-1].on_ground_flag


def test_pfc_rejection_is_reported_as_failure() -> None:
    rig = rig_in("hover")
    rig.pfc.reject_next = "switching modes"
    answer = rig.core.fcl.submit(C.YAW, (0.1,), rig.t)
    assert answer.code is FclCode.OK
    event = rig.run_until_final(answer.command_id)
    assert event is not None and event.kind is EventKind.FAILED
    assert event.reason == "rejected by the PFC: switching modes"


def test_late_reply_about_an_old_command_is_ignored() -> None:
    rig = rig_in("hover")
    first = rig.core.fcl.submit(C.YAW, (0.1,), rig.t)
    rig.core.fcl.submit(C.CANCEL, (), rig.t)
    second = rig.core.fcl.submit(C.YAW, (0.2,), rig.t)
    assert second.code is FclCode.OK
    # the fake PFC cancelled the first; replay a stale "finished" about it
    rig.pfc._send("Cmd-Finished-EV", first.command_id)
    rig.run(0.04)
    assert rig.core.fcl.current is not None
    assert rig.core.fcl.current.command_id == second.command_id
    assert rig.core.kernel.flight() is FlightState.RUNNING


@pytest.mark.parametrize(
    ("command", "bad", "words"),
    [
        (C.LAND, (math.nan,), "finite"),
        (C.YAW, (math.inf,), "finite"),
        (C.CLIMB, (FRAME.altitude - 50.0,), "below the ground"),
        (C.CLIMB, (FRAME.altitude + 1000.0,), "ceiling"),
        (C.TRAJ3D_FLYTO, (13.47, 55.70, FRAME.altitude + 30.0, 50.0), "flight envelope"),
        (C.TRAJ3D_FLYTO, (13.47, 55.70, FRAME.altitude + 30.0, 0.0), "flight envelope"),
        (C.TRAJ3D_FLYTO, (14.5, 55.70, FRAME.altitude + 30.0, 8.0), "far outside"),
        (C.TRAJ3D_FLYTO, (200.0, 55.70, FRAME.altitude + 30.0, 8.0), "WGS84"),
        (C.TRAJ3D_FLYTO, (13.47, math.nan, FRAME.altitude + 30.0, 8.0), "finite"),
        (C.TRAJ3D, (0, 0, 10, 50, 0, 10, 1, 0, 0, 1, 0, 0, 5.0, 6.0), "end velocity"),
        (C.TRAJ3D, (0, 0, 10, 0, 0, 10, 1, 0, 0, 1, 0, 0, 5.0, 0.0), "closer than 0.1 m"),
        (C.TRAJ3D, (0, 0, 10, 50, 0, 10, 0, 0, 0, 1, 0, 0, 5.0, 0.0), "start direction"),
        (C.TRAJ3D, (0, 0, 10, 50, 0, 10, 1, 0, 0, 0, 0, 0, 5.0, 0.0), "end direction"),
        (C.TRAJ3D, (0, 0, 10, 50, 0, 10, 1, 0, 0, 1, 0, math.inf, 5.0, 0.0), "end_direction_z"),
        (C.LAND, (1e308,), "outside [-2 pi, 2 pi]"),
        (C.YAW, (1e17,), "outside [-2 pi, 2 pi]"),
        (C.YAW, (-7.0,), "outside [-2 pi, 2 pi]"),
        (C.CLIMB, (-math.inf,), "altitude must be a finite number"),
        (C.TRAJ3D_FLYTO, (13.47, 55.70, 1e308, 8.0), "from the world's origin altitude"),
        (C.TRAJ3D_FLYTO, (13.47, 55.70, -1e308, 8.0), "from the world's origin altitude"),
        (C.YAW, ("north",), "bad arguments"),
        (C.TRAJ3D, (0, 0, 10, 50, 0, -30, 1, 0, 0, 1, 0, 0, 5.0, 0.0), "below the ground"),
        (C.TAKEOFF, (1.0,), "takes 0 argument(s)"),
        (C.TRAJ3D, (0.0, 1.0), "takes 14 argument(s)"),
    ],
)
def test_bad_arguments_are_not_accepted_in_any_state(
    command: FclCommand, bad: tuple[float, ...], words: str
) -> None:
    for state in ("hover", "busy"):
        rig = rig_in(state)
        answer = rig.core.fcl.submit(command, bad, rig.t)
        assert answer.code is FclCode.NOT_ACCEPTED
        assert words in answer.reason


@pytest.mark.parametrize(("state", "command_id_is_zero"), [("hover", True), ("busy", False)])
def test_pfc_fault_is_reported_as_info(state: str, command_id_is_zero: bool) -> None:
    from hdrc3_hcsm.event import WireEvent

    rig = rig_in(state)
    rig.pfc.transport.send(WireEvent(2108, "PFC-Fault-EV", b"GPS lost", "PFC", "DRC"))
    rig.run(0.04)
    info = [e for e in rig.log.events if e.reason == "PFC fault: GPS lost"]
    assert len(info) == 1 and info[0].kind is EventKind.INFO
    assert (info[0].command_id == 0) is command_id_is_zero


@pytest.mark.parametrize(
    ("note", "said"),
    [
        ("", "accepted by the PFC"),
        (
            "landing on GPS and barometer: no vision fix of pad L1: no vision pipeline",
            "accepted by the PFC: landing on GPS and barometer: no vision fix of pad L1: no "
            "vision pipeline",
        ),
    ],
)
def test_the_pfc_s_plan_rides_on_its_acceptance(note: str, said: str) -> None:
    from hdrc3_control.event_codec import encode
    from hdrc3_hcsm.event import WireEvent

    rig = rig_in("hover")
    answer = rig.core.fcl.submit(C.LAND, (0.5,), rig.t)
    assert answer.code is FclCode.OK
    rig.run(0.04)  # the fake PFC's own acceptance (no note)
    data = encode(answer.command_id, (), note)
    rig.pfc.transport.send(WireEvent(2101, "Cmd-Accepted-EV", data, "PFC", "DRC"))
    rig.run(0.04)
    info = [e.reason for e in rig.log.events if e.reason.startswith("accepted")]
    assert info[-1] == said, info


def test_the_drc_model_decides_the_answer(monkeypatch: pytest.MonkeyPatch) -> None:
    # A DRC model whose land transition wants the ground: landing on the ground is then taken
    # and sent to the PFC, and landing in the air refused, with no change to the Python side.
    text = model_path().read_text(encoding="utf-8")
    land = "on Api-Land-EV [Data-Fresh-CO AND Airborne-CO AND Auto-CO]"
    assert land in text
    variant = compile_model(load_text(text.replace(land, land.replace("Airborne", "On-Ground"))))
    monkeypatch.setattr(drc, "load_model", lambda: variant)
    on_ground = rig_in("ground")
    assert on_ground.core.fcl.submit(C.LAND, (0.5,), on_ground.t).code is FclCode.OK
    assert on_ground.core.kernel.flight() is FlightState.RUNNING
    hovering = rig_in("hover")
    refused = hovering.core.fcl.submit(C.LAND, (0.5,), hovering.t)
    assert refused.code is FclCode.NOT_ACCEPTED
    assert "fcl_land can only be commanded when the aircraft is on the ground" in refused.reason


@pytest.mark.parametrize("state", ["hover", "busy"])
def test_a_pfc_failsafe_is_its_own_platform_event(state: str) -> None:
    from hdrc3_hcsm.event import WireEvent

    rig = rig_in(state)
    text = "failsafe: emergency landing: navigation lost: IMU frozen (identical samples)"
    rig.pfc.transport.send(WireEvent(2108, "PFC-Fault-EV", text.encode(), "PFC", "DRC"))
    rig.run(0.04)
    announced = [e for e in rig.log.events if e.reason == text]
    assert [(e.command_id, e.command, e.kind) for e in announced] == [
        (0, "pfc_failsafe", EventKind.INFO)
    ]


def test_a_world_reset_fails_the_running_commands_once() -> None:
    rig = rig_in("busy")
    running = rig.core.fcl.current
    assert running is not None
    rig.core.on_world_reset("world_sim restarted without a usable checkpoint", rig.t)
    rig.run(0.5)
    assert [
        (e.kind, e.reason) for e in rig.log.of(running.command_id) if e.kind is not EventKind.INFO
    ] == [(EventKind.FAILED, "simulation reset: world_sim restarted without a usable checkpoint")]
    assert rig.core.fcl.current is None and rig.core.kernel.flight() is FlightState.IDLE
