"""Path execution protocol (chapter 7.2, Figures 17-18) through the DRC with the fake PFC."""

from __future__ import annotations

import pytest

from hdrc3_hcsm.event import WireEvent
from hdrc3_platform_server.codes import EventKind, FclCode, FclCommand
from hdrc3_platform_server.fakes import FakeRig
from hdrc3_platform_server.geo_frame import WorldFrame

FRAME = WorldFrame(55.70, 13.47, 95.0)


def seg(x0: float, x1: float, end_velocity: float) -> tuple[float, ...]:
    return (x0, 0, 10, x1, 0, 10, 1, 0, 0, 1, 0, 0, 5.0, end_velocity)


def hover_rig() -> FakeRig:
    return FakeRig(FRAME, on_ground=False)


def kinds(rig: FakeRig, command_id: int) -> list[EventKind]:
    return [e.kind for e in rig.log.of(command_id) if e.kind is not EventKind.INFO]


def test_streamed_segments_each_get_a_request_and_one_completion() -> None:
    rig = hover_rig()
    first = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 5.0), rig.t)
    assert first.code is FclCode.OK
    ids = [first.command_id]
    for x0, x1, end in ((50, 100, 5.0), (100, 150, 0.0)):
        # the executor waits for the request of the segment in flight, then sends the next
        while not any(
            e.kind is EventKind.SEGMENT_REQUEST and e.command_id == ids[-1] for e in rig.log.events
        ):
            rig.run(0.02)
        answer = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(x0, x1, end), rig.t)
        assert answer.code is FclCode.OK, answer.reason
        ids.append(answer.command_id)
    final = rig.run_until_final(ids[-1])
    assert final is not None and final.kind is EventKind.FINISHED
    for cid in ids:
        assert kinds(rig, cid) == [EventKind.SEGMENT_REQUEST, EventKind.FINISHED]
    assert rig.pfc.position == (150.0, 0.0, 10.0)


def test_not_yet_flown_segment_is_replaced() -> None:
    rig = hover_rig()
    first = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 5.0), rig.t)
    second = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(50, 100, 0.0), rig.t)
    third = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(50, 80, 0.0), rig.t)
    assert (first.code, second.code, third.code) == (FclCode.OK,) * 3
    assert third.reason == "replaces the next segment"
    assert rig.log.final(second.command_id) is None  # until the PFC takes the replacement
    rig.run(0.04)
    replaced = rig.log.final(second.command_id)
    assert replaced is not None and replaced.kind is EventKind.CANCELLED
    assert replaced.reason == f"replaced by segment {third.command_id}"
    final = rig.run_until_final(third.command_id)
    assert final is not None and final.kind is EventKind.FINISHED
    assert rig.pfc.position == (80.0, 0.0, 10.0)
    # the PFC's Cmd-Cancelled-EV and the acceptance of the new one end the old one once
    assert kinds(rig, second.command_id) == [EventKind.CANCELLED]
    assert kinds(rig, third.command_id) == [EventKind.SEGMENT_REQUEST, EventKind.FINISHED]


def test_segment_after_a_stopping_segment_is_busy() -> None:
    rig = hover_rig()
    first = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 0.0), rig.t)
    busy = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(50, 100, 0.0), rig.t)
    assert busy.code is FclCode.BUSY and str(first.command_id) in busy.reason


def test_late_segment_ends_in_safety_braking_failure() -> None:
    rig = hover_rig()
    first = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 5.0), rig.t)
    final = rig.run_until_final(first.command_id)
    assert final is not None and final.kind is EventKind.FAILED
    assert "safety braking" in final.reason
    rig.run(0.1)
    assert rig.core.fcl.submit(FclCommand.YAW, (0.0,), rig.t).code is FclCode.OK


def test_other_commands_are_busy_while_a_path_runs() -> None:
    rig = hover_rig()
    rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 5.0), rig.t)
    answer = rig.core.fcl.submit(FclCommand.YAW, (0.0,), rig.t)
    assert answer.code is FclCode.BUSY and "fcl_traj3d" in answer.reason


def test_replacement_refused_by_the_pfc_keeps_the_queued_segment() -> None:
    rig = hover_rig()
    rig.pfc.replace_queued = False
    first = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 5.0), rig.t)
    second = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(50, 100, 0.0), rig.t)
    rig.run(0.04)
    third = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(50, 80, 0.0), rig.t)
    assert third.code is FclCode.OK
    rig.run(0.04)
    refused = rig.log.final(third.command_id)
    assert refused is not None and refused.kind is EventKind.FAILED
    assert refused.reason.startswith("rejected by the PFC: too late to replace")
    final = rig.run_until_final(second.command_id)
    assert final is not None and final.kind is EventKind.FINISHED
    assert kinds(rig, first.command_id) == [EventKind.SEGMENT_REQUEST, EventKind.FINISHED]
    assert rig.pfc.position == (100.0, 0.0, 10.0)


def test_last_segment_without_a_request_still_finishes_the_path() -> None:
    rig = hover_rig()
    rig.pfc.quiet_last_segment = True
    first = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(0, 50, 5.0), rig.t)
    last = rig.core.fcl.submit(FclCommand.TRAJ3D, seg(50, 100, 0.0), rig.t)
    final = rig.run_until_final(last.command_id)
    assert final is not None and final.kind is EventKind.FINISHED
    assert kinds(rig, first.command_id) == [EventKind.SEGMENT_REQUEST, EventKind.FINISHED]
    assert kinds(rig, last.command_id) == [EventKind.FINISHED]


@pytest.mark.parametrize(("first_flown", "in_flight"), [(False, 0), (True, 1)])
def test_a_pfc_fault_during_a_path_goes_to_the_segment_in_flight(
    first_flown: bool, in_flight: int
) -> None:
    # it went to the path's first segment, also when that one had long finished
    rig = hover_rig()
    rig.pfc.quiet_last_segment = True  # as the real PFC: the last segment is not requested
    ids = [
        rig.core.fcl.submit(FclCommand.TRAJ3D, seg(x0, x1, end), rig.t).command_id
        for x0, x1, end in ((0, 50, 5.0), (50, 100, 0.0))
    ]
    rig.run(0.04)
    if first_flown:
        rig.run_until_final(ids[0])
    assert rig.log.final(ids[1]) is None
    rig.pfc.transport.send(WireEvent(2108, "PFC-Fault-EV", b"GPS lost", "PFC", "DRC"))
    rig.run(0.04)
    info = [e for e in rig.log.events if e.reason == "PFC fault: GPS lost"]
    assert [(e.command_id, e.kind) for e in info] == [(ids[in_flight], EventKind.INFO)]
