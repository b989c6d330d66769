"""Argument checks: None when fine, otherwise a reason naming the problem."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

from hdrc3_control.ppc_hardware import PtuLimits
from hdrc3_platform_server import limits as check
from hdrc3_platform_server.codes import FclCode, FclCommand, PpclCode, PpclCommand, Resource
from hdrc3_platform_server.commands import PPCL
from hdrc3_platform_server.fakes import FakeRig
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.limits import FlightLimits

FLIGHT = FlightLimits()
FRAME = WorldFrame(55.7, 13.47, 95.0, bounds=(-300.0, -200.0, 300.0, 200.0), margin=100.0)


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: check.velocity(FLIGHT, 8.0), None),
        (lambda: check.velocity(FLIGHT, 25.0), "flight envelope"),
        (lambda: check.velocity(FLIGHT, math.nan), "finite"),
        (lambda: check.position(FRAME, FLIGHT, 0.0, 0.0, 30.0, "t"), None),
        (lambda: check.position(FRAME, FLIGHT, 500.0, 0.0, 30.0, "t"), "far outside"),
        (lambda: check.position(FRAME, FLIGHT, 0.0, 0.0, 1.0, "t"), "below the ground"),
        (lambda: check.position(FRAME, FLIGHT, 0.0, 0.0, 151.0, "t"), "ceiling"),
        (lambda: check.wgs84(13.47, 55.7), None),
        (lambda: check.wgs84(13.47, 95.0), "WGS84"),
        (lambda: check.pan_tilt(PtuLimits(), 0.0, math.pi / 2), None),
        (lambda: check.pan_tilt(PtuLimits(), 0.0, math.pi), "PTU limits"),
        (lambda: check.camera(0), None),
        (lambda: check.camera(3), "unknown camera"),
        (lambda: check.unit_interval("zoom", 1.0), None),
        (lambda: check.unit_interval("zoom", 1.01), "outside [0, 1]"),
        (lambda: check.shutter(0.01), None),
        (lambda: check.shutter(0.0), "shutter"),
        (lambda: check.laser_angular(0.25), None),
        (lambda: check.laser_angular(math.inf), "angular resolution"),
        (lambda: check.laser_distance(0.01), None),
        (lambda: check.laser_distance(0.005), "distance resolution"),
        (lambda: check.laser_speed(-math.pi), None),
        (lambda: check.laser_speed(4.0), "rotation speed"),
        (lambda: check.pixel(719.0, 575.0), None),
        (lambda: check.pixel(720.0, 0.0), "outside"),
    ],
)
def test_checks(call: Callable[[], str | None], words: str | None) -> None:
    reason = call()
    if words is None:
        assert reason is None
    else:
        assert reason is not None and words in reason


@pytest.mark.parametrize(("value", "text"), [(12.345, "12.3"), (-3e6, "-3e+06"), (1e308, "1e+308")])
def test_numbers_in_reasons_stay_short(value: float, text: str) -> None:
    assert check.shown(value) == text


_RIG_FRAME = WorldFrame(55.70, 13.47, 95.0)
_SEGMENT = [0.0, 0.0, 120.0, 20.0, 0.0, 120.0]


@pytest.mark.parametrize(
    ("command", "args", "words"),
    [
        (FclCommand.LAND, [1e308], "heading 1e+308 rad outside"),
        (FclCommand.YAW, [1e308], "heading 1e+308 rad outside"),
        (FclCommand.YAW, [1e17], "heading 1e+17 rad outside"),
        (FclCommand.YAW, [-1e17], "heading -1e+17 rad outside"),
        (
            FclCommand.TRAJ3D,
            [*_SEGMENT, 0, 0, 0, 1, 0, 0, 5, 0],
            "start direction must be a non-zero",
        ),
        (
            FclCommand.TRAJ3D,
            [*_SEGMENT, 1, 0, 0, 0, 0, 0, 5, 0],
            "end direction must be a non-zero",
        ),
        (FclCommand.CLIMB, [1e308], "altitude 1e+308 m is above the ceiling"),
        (FclCommand.CLIMB, [-1e308], "altitude -1e+308 m is below the ground"),
        (FclCommand.TRAJ3D_FLYTO, [13.47, 55.70, 1e308, 5.0], "more than 10000 m"),
        (FclCommand.TRAJ3D_FLYTO, [13.47, 55.70, 120.0, 1e308], "flight envelope"),
    ],
)
def test_absurd_fcl_arguments_are_not_accepted(
    command: FclCommand, args: list[float], words: str
) -> None:
    """The absurd values listed in issue 21 answer FCL_NOT_ACCEPTED with a short reason."""
    rig = FakeRig(_RIG_FRAME, on_ground=False)
    answer = rig.core.fcl.submit(command, args, rig.t)
    assert answer.code is FclCode.NOT_ACCEPTED
    assert words in answer.reason and len(answer.reason) < 200


@pytest.mark.parametrize(
    ("command", "args", "words"),
    [
        (PpclCommand.LOOK_AT, [13.47, 55.70, 1.0, 1e308], "look-at altitude 1e+308 m"),
        (PpclCommand.LOOK_AT, [13.47, 55.70, 1.0, -1e308], "look-at altitude -1e+308 m"),
        (PpclCommand.LASER_ROTATION_ANGLE, [1e308], "rotation_angle 1e+308 rad outside"),
        (PpclCommand.LASER_ROTATION_ANGLE, [-1e308], "rotation_angle -1e+308 rad outside"),
    ],
)
def test_absurd_ppcl_arguments_are_not_accepted(
    command: PpclCommand, args: list[float], words: str
) -> None:
    rig = FakeRig(_RIG_FRAME, on_ground=False)
    resource = PPCL[command].resource
    assert rig.core.ppcl.control(resource, True, "me").code is PpclCode.OK
    answer = rig.core.ppcl.submit(command, args, rig.t)
    assert answer.code is PpclCode.NOT_ACCEPTED
    assert words in answer.reason and len(answer.reason) < 200


@pytest.mark.parametrize("owner", ["x" * 100_000, "x" * (check.MAX_OWNER_LENGTH + 1)])
def test_overlong_owner_names_are_not_accepted(owner: str) -> None:
    rig = FakeRig(_RIG_FRAME)
    answer = rig.core.ppcl.control(Resource.PTU, True, owner)
    assert answer.code is PpclCode.NOT_ACCEPTED
    assert f"at most {check.MAX_OWNER_LENGTH}" in answer.reason and len(answer.reason) < 200
