"""Every row of the PPCL semantics table (README) on the pure core with the fake PPC."""

from __future__ import annotations

import math

import pytest

from hdrc3_control.event_codec import decode
from hdrc3_platform_server.codes import (
    EventKind,
    FclCode,
    FclCommand,
    PpclCode,
    PpclCommand,
    PtuActivity,
    Resource,
)
from hdrc3_platform_server.fakes import FakeRig
from hdrc3_platform_server.geo_frame import WorldFrame

FRAME = WorldFrame(55.70, 13.47, 95.0)
P = PpclCommand
LON, LAT, _ = FRAME.to_wgs84(40.0, 30.0, 0.0)
VALID: dict[PpclCommand, tuple[float, ...]] = {
    P.TURN_TO: (0.0, math.radians(90.0)),
    P.LOOK_AT: (LON, LAT, 0.0, 0.0),
    P.PTU_ABORT: (),
    P.ZOOM: (0.0, 0.5),
    P.EXPOSURE: (0.0, 1.0),
    P.IRIS: (1.0, 0.3),
    P.SHUTTER: (0.0, 0.002),
    P.LASER_ANGULAR_RESOLUTION: (0.5,),
    P.LASER_DISTANCE_RESOLUTION: (0.001,),
    P.LASER_ROTATION_SPEED: (-1.0,),
    P.LASER_ROTATION_ANGLE: (-1.0,),
    P.LASER_START_DATA_COLLECTION: (),
    P.LASER_STOP_DATA_COLLECTION: (),
    P.IP_COLOR_TRACKER: (100.0, 100.0),
    P.IP_STATE_ESTIMATION: (),
    P.IP_ABORT: (),
    P.IP_SALIENCY: (),
}
RESOURCE = {
    P.TURN_TO: Resource.PTU,
    P.LOOK_AT: Resource.PTU,
    P.PTU_ABORT: Resource.PTU,
    P.ZOOM: Resource.CAMERA,
    P.EXPOSURE: Resource.CAMERA,
    P.IRIS: Resource.CAMERA,
    P.SHUTTER: Resource.CAMERA,
    P.IP_COLOR_TRACKER: Resource.IMAGE_PROCESSING,
    P.IP_STATE_ESTIMATION: Resource.IMAGE_PROCESSING,
    P.IP_ABORT: Resource.IMAGE_PROCESSING,
    P.IP_SALIENCY: Resource.IMAGE_PROCESSING,
}


def rig(*held: Resource, landing: bool = False) -> FakeRig:
    r = FakeRig(FRAME, on_ground=False)
    for res in held:
        assert r.core.ppcl.control(res, True, "exec").code is PpclCode.OK
    if landing:
        assert r.core.fcl.submit(FclCommand.LAND, (0.0,), r.t).code is FclCode.OK
    return r


# --- ownership rows --------------------------------------------------------------------------
@pytest.mark.parametrize("res", list(Resource))
def test_request_free_resource_is_ok_and_idempotent(res: Resource) -> None:
    r = rig()
    assert r.core.ppcl.control(res, True, "a").code is PpclCode.OK
    assert r.core.ppcl.control(res, True, "a").code is PpclCode.OK


@pytest.mark.parametrize("res", list(Resource))
def test_request_held_by_other_is_denied(res: Resource) -> None:
    r = rig()
    r.core.ppcl.control(res, True, "a")
    answer = r.core.ppcl.control(res, True, "b")
    assert answer.code is PpclCode.CONTROL_DENIED and "'a'" in answer.reason


@pytest.mark.parametrize(
    ("res", "code"),
    [
        (Resource.PTU, PpclCode.CONTROL_DENIED),
        (Resource.CAMERA, PpclCode.CONTROL_DENIED),
        (Resource.IMAGE_PROCESSING, PpclCode.CONTROL_DENIED),
        (Resource.LASER, PpclCode.OK),
    ],
)
def test_request_during_vision_landing(res: Resource, code: PpclCode) -> None:
    answer = rig(landing=True).core.ppcl.control(res, True, "a")
    assert answer.code is code
    if code is PpclCode.CONTROL_DENIED:
        assert "landing" in answer.reason


@pytest.mark.parametrize(
    ("holder", "releaser", "code"),
    [("a", "a", PpclCode.OK), (None, "a", PpclCode.OK), ("a", "b", PpclCode.NOT_ACCEPTED)],
)
def test_release(holder: str | None, releaser: str, code: PpclCode) -> None:
    r = rig()
    if holder:
        r.core.ppcl.control(Resource.PTU, True, holder)
    assert r.core.ppcl.control(Resource.PTU, False, releaser).code is code
    assert (Resource.PTU in r.core.ppcl.owners) is (code is PpclCode.NOT_ACCEPTED)


@pytest.mark.parametrize(
    ("resource", "requesting", "owner", "words"),
    [
        (7, True, "a", "unknown resource"),
        (0, True, " ", "owner name is required"),
        (0, True, "x" * 100_000, "at most 64"),
        (0, False, "x" * 100_000, "at most 64"),
    ],
)
def test_bad_control_requests(resource: int, requesting: bool, owner: str, words: str) -> None:
    answer = rig().core.ppcl.control(resource, requesting, owner)
    assert answer.code is PpclCode.NOT_ACCEPTED and words in answer.reason


# --- mode and parameter rows -----------------------------------------------------------------
@pytest.mark.parametrize("command", list(P))
def test_command_without_control_is_not_accepted(command: PpclCommand) -> None:
    answer = rig().core.ppcl.submit(command, VALID[command], 0.2)
    assert answer.code is PpclCode.NOT_ACCEPTED and "request control" in answer.reason


@pytest.mark.parametrize("command", list(P))
def test_command_with_control_finishes(command: PpclCommand) -> None:
    r = rig(*Resource)
    answer = r.core.ppcl.submit(command, VALID[command], r.t)
    assert answer.code is PpclCode.OK and answer.command_id > 0, answer.reason
    r.run(0.5)
    final = r.log.final(answer.command_id)
    assert final is not None and final.kind is EventKind.FINISHED


@pytest.mark.parametrize("seed", [(0.0, 0.0), (719.5, 575.0), (360.0, 288.0)])
def test_colour_tracking_sends_its_seed_to_the_ppc(seed: tuple[float, float]) -> None:
    r = rig(Resource.IMAGE_PROCESSING)
    assert r.ppc is not None
    answer = r.core.ppcl.submit(P.IP_COLOR_TRACKER, seed, r.t)
    assert answer.code is PpclCode.OK, answer.reason
    r.run(0.2)
    sent = [e for e in r.ppc.received if e.name == "PPCL-IP-Tracker-EV"]
    assert [decode(e.data, 2).values for e in sent] == [seed]
    final = r.log.final(answer.command_id)
    assert final is not None and final.kind is EventKind.FINISHED


@pytest.mark.parametrize("command", [c for c in P if RESOURCE.get(c) is not None])
def test_ptu_camera_ip_commands_denied_during_landing(command: PpclCommand) -> None:
    r = rig(Resource.PTU, Resource.CAMERA, Resource.IMAGE_PROCESSING, landing=True)
    assert r.core.ppcl.submit(command, VALID[command], r.t).code is PpclCode.CONTROL_DENIED


def test_laser_commands_allowed_during_landing() -> None:
    r = rig(Resource.LASER, landing=True)
    assert r.core.ppcl.submit(P.LASER_START_DATA_COLLECTION, (), r.t).code is PpclCode.OK


def test_newer_ptu_mode_cancels_the_older_and_activity_follows() -> None:
    r = rig(Resource.PTU)
    turn = r.core.ppcl.submit(P.TURN_TO, VALID[P.TURN_TO], r.t)
    assert r.core.ppcl.activity is PtuActivity.TURNTO
    look = r.core.ppcl.submit(P.LOOK_AT, VALID[P.LOOK_AT], r.t)
    assert r.core.ppcl.activity is PtuActivity.LOOK_AT_POINT
    old = r.log.final(turn.command_id)
    assert old is not None and old.kind is EventKind.CANCELLED
    r.core.ppcl.submit(P.PTU_ABORT, (), r.t)
    assert r.core.ppcl.activity is PtuActivity.IDLE
    assert r.log.final(look.command_id) is not None


def test_ppc_failure_is_reported() -> None:
    r = rig(Resource.CAMERA)
    assert r.ppc is not None
    r.ppc.fail_next = "iris motor stalled"
    answer = r.core.ppcl.submit(P.IRIS, VALID[P.IRIS], r.t)
    r.run(0.1)
    final = r.log.final(answer.command_id)
    assert final is not None and final.kind is EventKind.FAILED
    assert final.reason == "iris motor stalled"


def test_commands_need_a_running_ppc() -> None:
    r = FakeRig(FRAME, on_ground=False, with_ppc=False)
    r.core.ppcl.control(Resource.PTU, True, "a")
    answer = r.core.ppcl.submit(P.TURN_TO, VALID[P.TURN_TO], r.t)
    assert answer.code is PpclCode.NOT_ACCEPTED and "perception kernel" in answer.reason


@pytest.mark.parametrize(
    ("command", "bad", "words"),
    [
        (P.TURN_TO, (math.radians(200), 0.0), "PTU limits"),
        (P.TURN_TO, (0.0, math.radians(-45)), "PTU limits"),
        (P.TURN_TO, (math.nan, 0.0), "finite"),
        (P.ZOOM, (0.0, 1.5), "outside [0, 1]"),
        (P.ZOOM, (0.0, -0.1), "outside [0, 1]"),
        (P.ZOOM, (5.0, 0.5), "unknown camera"),
        (P.IRIS, (0.0, math.inf), "finite"),
        (P.SHUTTER, (0.0, 2.0), "shutter"),
        (P.LASER_ANGULAR_RESOLUTION, (0.3,), "angular resolution"),
        (P.LASER_DISTANCE_RESOLUTION, (0.1,), "distance resolution"),
        (P.LASER_ROTATION_SPEED, (10.0,), "rotation speed"),
        (P.LOOK_AT, (15.0, 55.7, 0.0, 0.0), "far outside"),
        (P.LOOK_AT, (math.nan, 55.7, 0.0, 0.0), "finite"),
        (P.IP_COLOR_TRACKER, (1000.0, 10.0), "outside"),
        (P.IP_COLOR_TRACKER, (-1.0, 10.0), "outside"),
        (P.IP_COLOR_TRACKER, (10.0, 576.0), "outside the 720x576 color image"),
        (P.IP_COLOR_TRACKER, (math.nan, 10.0), "finite"),
        (P.IP_COLOR_TRACKER, (10.0,), "takes 2 argument(s), got 1"),
        # fuzz-found: infinite camera ids once reached int() (OverflowError)
        (P.IRIS, (math.inf, 0.5), "camera_id must be a finite number"),
        (P.EXPOSURE, (math.inf, 1.0), "camera_id must be a finite number"),
        (P.ZOOM, (-math.inf, 0.5), "camera_id must be a finite number"),
        (P.ZOOM, (math.nan, 0.5), "camera_id must be a finite number"),
        (P.IRIS, (0.5, 0.3), "camera id must be an integer"),
        (P.SHUTTER, (1e300, 0.002), "unknown camera"),
        (P.EXPOSURE, (0.0, 0.5), "auto_exposure must be 0 or 1"),
        (P.LOOK_AT, (LON, LAT, 2.0, 0.0), "has_altitude must be 0 or 1"),
        (P.LOOK_AT, (LON, LAT, 1.0, 1e308), "from the world's origin altitude"),
        (P.LOOK_AT, (LON, LAT, 1.0, -1e308), "from the world's origin altitude"),
        (P.LASER_ROTATION_ANGLE, (1e308,), "outside [-2 pi, 2 pi]"),
        (P.LASER_ROTATION_ANGLE, (-1e308,), "outside [-2 pi, 2 pi]"),
        (P.TURN_TO, (0.0,), "takes 2 argument(s), got 1"),
    ],
)
def test_bad_arguments(command: PpclCommand, bad: tuple[float, ...], words: str) -> None:
    answer = rig(*Resource).core.ppcl.submit(command, bad, 0.2)
    assert answer.code is PpclCode.NOT_ACCEPTED and words in answer.reason


@pytest.mark.parametrize(
    ("camera", "code"), [(0, PpclCode.OK), (1, PpclCode.OK), (2, PpclCode.NOT_ACCEPTED)]
)
def test_camera_info(camera: int, code: PpclCode) -> None:
    answer, info = rig().core.ppcl.camera_info(camera)
    assert answer.code is code
    if info is not None:
        assert info.fx > 0 and info.width > 0 and 0 < info.hfov < math.pi


def test_scan_area_sequence_of_section_6_2_3() -> None:
    r = rig()
    ppcl = r.core.ppcl
    assert ppcl.control(Resource.PTU, True, "scan").code is PpclCode.OK
    assert ppcl.control(Resource.CAMERA, True, "scan").code is PpclCode.OK
    tilt = ppcl.submit(P.TURN_TO, (0.0, math.radians(90.0)), r.t)
    zoom = ppcl.submit(P.ZOOM, (0.0, 0.3), r.t)
    r.run(0.5)
    for answer in (tilt, zoom):
        final = r.log.final(answer.command_id)
        assert final is not None and final.kind is EventKind.FINISHED
    assert r.core.camera_states()[0].tilt == pytest.approx(math.radians(90.0))
    assert ppcl.control(Resource.PTU, False, "scan").code is PpclCode.OK
    assert ppcl.control(Resource.CAMERA, False, "scan").code is PpclCode.OK
    assert not ppcl.owners


def test_a_world_reset_fails_the_pending_commands_once() -> None:
    r = rig(Resource.PTU)
    turn = r.core.ppcl.submit(P.TURN_TO, VALID[P.TURN_TO], r.t)
    r.core.on_world_reset("no usable checkpoint", r.t)
    r.run(0.5)
    final = [e for e in r.log.of(turn.command_id) if e.kind is not EventKind.INFO]
    assert [(e.kind, e.reason) for e in final] == [
        (EventKind.FAILED, "simulation reset: no usable checkpoint")
    ]
    assert r.core.ppcl.activity is PtuActivity.IDLE and r.core.ppcl.pending == {}
