"""Restarts of the PFC and of the Platform Server itself (docs/realtime_events.md).

The pure core with the fake kernels over a loopback network whose endpoints are replaced as a
restarted process would replace them: a new incarnation counting from 1. Each command accepted
before a restart ends with exactly one terminal event and the next command works without cancel.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_control.pfc_state import FlightMode
from hdrc3_platform_server.codes import (
    EventKind,
    FclCode,
    FclCommand,
    PpclCode,
    PpclCommand,
    Resource,
)
from hdrc3_platform_server.completion import TERMINAL
from hdrc3_platform_server.fakes import FakePfcTiming, FakeRig
from hdrc3_platform_server.fcl_api import (
    ENDED_WHILE_DOWN,
    RESTARTED_DRC,
    RESTARTED_LOST,
    RESTARTED_PFC,
)
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.journal import CommandJournal
from hdrc3_platform_server.kernel_watch import KernelExit
from hdrc3_platform_server.ppcl_api import RESTARTED_PPC

FRAME = WorldFrame(55.70, 13.47, 95.0)
C = FclCommand
SLOW = FakePfcTiming(flyto=30.0)


def flyto(east: float) -> tuple[float, ...]:
    lon, lat, alt = FRAME.to_wgs84(east, 0.0, 30.0)
    return (lon, lat, alt, 8.0)


def terminal(rig: FakeRig, command_id: int) -> list[EventKind]:
    return [e.kind for e in rig.log.of(command_id) if e.kind in TERMINAL]


def start_flyto(rig: FakeRig) -> int:
    answer = rig.core.submit_fcl(C.TRAJ3D_FLYTO, flyto(200.0), rig.t)
    assert answer.code is FclCode.OK, answer.reason
    rig.run(1.0)
    assert rig.pfc.mode is FlightMode.FLYTO
    return answer.command_id


def next_command_works(rig: FakeRig) -> int:
    answer = rig.core.submit_fcl(C.YAW, (1.0,), rig.t)
    assert answer.code is FclCode.OK, answer.reason
    final = rig.run_until_final(answer.command_id)
    assert final is not None and final.kind is EventKind.FINISHED, rig.log.of(answer.command_id)
    return answer.command_id


def new_pfc(rig: FakeRig, announced: bool) -> None:
    """A new PFC process: it announces itself, or only its state report (boot mode) tells."""
    if announced:
        rig.restart_pfc()
    else:
        rig.pfc = type(rig.pfc)(rig.net.endpoint("PFC"), SLOW, on_ground=False)
        rig.pfc.mode = FlightMode.BOOT


@pytest.mark.parametrize("announced", [True, False], ids=["announced", "boot_mode_only"])
def test_pfc_restart_fails_the_running_command_once(announced: bool) -> None:
    rig = FakeRig(FRAME, on_ground=False, timing=SLOW)
    cid = start_flyto(rig)
    new_pfc(rig, announced)
    rig.run(0.1)
    assert terminal(rig, cid) == [EventKind.FAILED]
    assert rig.log.final(cid).reason == RESTARTED_PFC  # type: ignore[union-attr]
    rig.pfc.mode = FlightMode.HOVER  # the new PFC has booted into hover
    rig.run(0.5)
    next_command_works(rig)
    rig.run(5.0)
    assert terminal(rig, cid) == [EventKind.FAILED]


def test_server_restart_ends_the_command_the_pfc_reports() -> None:
    rig = FakeRig(FRAME, on_ground=False, timing=SLOW)
    cid = start_flyto(rig)
    before = len(rig.log.events)
    rig.restart_server(id_start=cid + 1_000_000)
    rig.run(0.2)
    after = rig.log.events[before:]
    ended = [e for e in after if e.command_id == cid]
    assert [(e.kind, e.command, e.reason) for e in ended] == [
        (EventKind.FAILED, "fcl_traj3d_flyto", RESTARTED_DRC)
    ]
    assert ended[0].time >= rig.t - 0.2  # stamped with the DRC clock of the report, not 0
    # the new server's cancel reached the PFC although it counts from 1 again
    assert rig.pfc.job is None and rig.pfc.mode is FlightMode.HOVER
    next_command_works(rig)
    rig.run(2.0)
    assert terminal(rig, cid) == [EventKind.FAILED]


def test_server_restart_with_an_idle_pfc_changes_nothing() -> None:
    rig = FakeRig(FRAME, on_ground=False)
    before = len(rig.log.events)
    rig.restart_server(id_start=5_000_000)
    rig.run(0.5)
    assert rig.log.events[before:] == []
    next_command_works(rig)


def test_a_final_reply_held_for_the_restarted_server_ends_the_command_once() -> None:
    rig = FakeRig(FRAME, on_ground=False, timing=SLOW)
    cid = start_flyto(rig)
    rig.pfc.job = None  # it arrived while the server was down ...
    rig.pfc.mode = FlightMode.HOVER
    rig.restart_server(id_start=cid + 1_000_000)
    rig.pfc._send("Traj-Arrived-EV", cid)  # ... and its transport held the reply meanwhile
    rig.run(0.5)
    assert terminal(rig, cid) == [EventKind.FINISHED]  # what the PFC said, not a guess
    assert rig.log.final(cid).reason == ENDED_WHILE_DOWN  # type: ignore[union-attr]
    next_command_works(rig)


@pytest.mark.parametrize(
    ("reply", "outcome"),
    [
        ("Traj-Arrived-EV", (EventKind.FINISHED, ENDED_WHILE_DOWN)),
        (None, (EventKind.FAILED, RESTARTED_LOST)),  # the reply went to the dead server
    ],
    ids=["reply_held", "reply_lost"],
)
def test_a_journaled_command_that_ended_while_the_server_was_down_ends_once(
    tmp_path: Path, reply: str | None, outcome: tuple[EventKind, str]
) -> None:
    path = tmp_path / "uav0.platform_server.checkpoint"
    rig = FakeRig(FRAME, on_ground=False, timing=SLOW, journal=CommandJournal(path))
    done = next_command_works(rig)  # ended before the crash: its terminal event is out already
    cid = start_flyto(rig)
    rig.pfc.job = None  # the PFC ends the fly-to while the server is down
    rig.pfc.mode = FlightMode.HOVER
    before = len(rig.log.events)
    for run in range(2):  # a second restart does not end it again
        rig.restart_server(id_start=cid + 1_000_000 * (run + 1), journal=CommandJournal(path))
        if reply is not None:
            rig.pfc._send(reply, cid)
        rig.pfc._send("Cmd-Finished-EV", done)  # a stale duplicate of an ended command's reply
        rig.run(2.0)
    ended = [(e.kind, e.command, e.reason) for e in rig.log.events[before:]]
    assert ended == [(outcome[0], "fcl_traj3d_flyto", outcome[1])]
    assert CommandJournal(path).earlier == {}
    next_command_works(rig)


@pytest.mark.parametrize("pending", [0, 1, 2])
def test_ppc_restart_fails_its_pending_commands_once_and_the_next_works(pending: int) -> None:
    rig = FakeRig(FRAME, on_ground=False)
    assert rig.core.ppcl.control(Resource.PTU, True, "exec").code is PpclCode.OK
    assert rig.core.ppcl.control(Resource.CAMERA, True, "exec").code is PpclCode.OK
    assert rig.ppc is not None
    rig.ppc.move_time = 60.0  # still moving when the PPC dies
    calls = [(PpclCommand.TURN_TO, (0.5, 0.2)), (PpclCommand.ZOOM, (0.0, 0.5))][:pending]
    ids = []
    for command, args in calls:
        answer = rig.core.ppcl.submit(command, args, rig.t)
        assert answer.code is PpclCode.OK, answer.reason
        ids.append(answer.command_id)
    rig.run(0.5)
    rig.restart_ppc()
    rig.run(0.5)
    for cid in ids:
        assert terminal(rig, cid) == [EventKind.FAILED]
        assert rig.log.final(cid).reason == RESTARTED_PPC  # type: ignore[union-attr]
    answer = rig.core.ppcl.submit(PpclCommand.TURN_TO, (0.1, 0.1), rig.t)
    assert answer.code is PpclCode.OK, answer.reason
    final = rig.run_until_final(answer.command_id)
    assert final is not None and final.kind is EventKind.FINISHED
    rig.run(1.0)
    assert all(terminal(rig, cid) == [EventKind.FAILED] for cid in ids)


PFC_EXIT = KernelExit("PFC", "control kernel (PFC) exited (code -9): the command was lost")
PPC_EXIT = KernelExit("PPC", "perception kernel (PPC) exited (code -9): the command was lost")


@pytest.mark.parametrize("announced", [True, False], ids=["announced", "boot_mode_only"])
def test_a_pfc_exit_seen_by_the_launcher_fails_the_command_before_the_restart(
    announced: bool,
) -> None:
    rig = FakeRig(FRAME, on_ground=False, timing=SLOW)
    cid = start_flyto(rig)
    rig.pfc_online = False  # dead: it sends nothing
    rig.core.on_kernel_exit(PFC_EXIT, rig.t)
    assert terminal(rig, cid) == [EventKind.FAILED]
    assert rig.log.final(cid).reason == PFC_EXIT.reason  # type: ignore[union-attr]
    # until the new PFC is heard: new commands are busy, and nothing is sent to the dead PFC
    busy = rig.core.submit_fcl(C.YAW, (1.0,), rig.t)
    assert busy.code is FclCode.BUSY, busy
    rig.run(1.0)
    assert rig.net.drain("PFC") == []
    rig.pfc_online = True
    new_pfc(rig, announced)
    rig.run(0.1)
    rig.pfc.mode = FlightMode.HOVER
    rig.run(0.5)
    next_command_works(rig)
    rig.run(5.0)
    assert terminal(rig, cid) == [EventKind.FAILED]  # the new PFC's notice ended nothing twice


def test_a_ppc_exit_seen_by_the_launcher_fails_its_pending_commands_once() -> None:
    rig = FakeRig(FRAME, on_ground=False)
    assert rig.core.ppcl.control(Resource.PTU, True, "exec").code is PpclCode.OK
    assert rig.ppc is not None
    rig.ppc.move_time = 60.0
    answer = rig.core.ppcl.submit(PpclCommand.TURN_TO, (0.5, 0.2), rig.t)
    assert answer.code is PpclCode.OK, answer.reason
    rig.run(0.5)
    rig.core.on_kernel_exit(PPC_EXIT, rig.t)
    rig.restart_ppc()
    rig.run(0.5)
    assert terminal(rig, answer.command_id) == [EventKind.FAILED]
    assert rig.log.final(answer.command_id).reason == PPC_EXIT.reason  # type: ignore[union-attr]
