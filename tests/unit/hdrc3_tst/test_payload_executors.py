"""Delivery executors: the UAV logistics operators, one each, and the hook commands they send."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.generators import UAV_DOMAIN
from hdrc3_deliberative.tal_language import TalReader
from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_platform_server.hook_api import HookAction
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.executor import ActionContext, Progress, Status, Stepper
from hdrc3_tst.fake_platform import FakePlatform
from hdrc3_tst.payload_executors import CARRY_CABLE, HOVER_HEIGHT, PAYLOAD_EXECUTORS, REACH
from hdrc3_tst.platform_port import Command, PlatformState

FRAME = frame_from_world("revinge")
POINTS = {"box1": ((-166.0, 96.0, 0.0),), "body1": ((40.0, -20.0, 0.0),)}
FLYING = PlatformState(0.0, 0.0, 30.0, on_ground=False, autonomous=True)
LOWER = (HookAction.LOWER, HOVER_HEIGHT + REACH, "")


def test_the_uav_logistics_operators_map_one_to_one_onto_executors() -> None:
    domain = TalReader().read_domain(UAV_DOMAIN.read_text())
    operators = {op.name for op in domain.operators} - {"fly-to"}
    assert set(PAYLOAD_EXECUTORS) == operators
    assert set(PAYLOAD_EXECUTORS) <= set(ACTIONS)


def _run(action: str, args: dict[str, float | str]) -> tuple[FakePlatform, Stepper]:
    platform = FakePlatform(sample=FLYING)
    ctx = ActionContext("n", "uav0", ACTIONS[action], args, POINTS, platform, FRAME, 0.0)
    return platform, Stepper(PAYLOAD_EXECUTORS[action](), ctx)


def _hook_call(command: Command) -> tuple[object, ...]:
    return (command.command, command.args["length"], command.args["object_id"])


@pytest.mark.parametrize(
    ("action", "args", "place", "hook_calls"),
    [
        ("pick-up-box", {"box": "box1"}, "box1",
         [LOWER, (HookAction.ATTACH, 0.0, "box1"), (HookAction.RAISE, CARRY_CABLE, "")]),
        ("drop-box", {"box": "box1", "place": "body1"}, "body1",
         [LOWER, (HookAction.RELEASE, 0.0, ""), (HookAction.RAISE, 0.0, "")]),
    ],
)  # fmt: skip
def test_the_chapters_sequence_hover_lower_attach_or_release_raise(
    action: str, args: dict[str, float | str], place: str, hook_calls: list[tuple[object, ...]]
) -> None:
    platform, stepper = _run(action, args)
    assert stepper.step(0.0).progress is Progress.RUNNING
    (flight,) = platform.sent
    assert flight.command is FclCommand.TRAJ3D_FLYTO
    east, north, _ = POINTS[place][0]
    up = FRAME.ground_up(east, north) + HOVER_HEIGHT
    lon, lat, alt = FRAME.to_wgs84(east, north, up)
    assert (flight.args["longitude"], flight.args["latitude"]) == pytest.approx((lon, lat))
    assert flight.args["altitude"] == pytest.approx(alt)
    for k, expected in enumerate(hook_calls):
        platform.complete(platform.sent[-1])
        assert stepper.step(1.0 + k).progress is Progress.RUNNING
        assert _hook_call(platform.sent[-1]) == expected
    platform.complete(platform.sent[-1])
    assert stepper.step(10.0) == Status(Progress.SUCCEEDED)


def test_a_wrong_box_fails_the_pick_up_with_the_platforms_reason() -> None:
    platform, stepper = _run("pick-up-box", {"box": "box1"})
    stepper.step(0.0)
    platform.complete(platform.sent[-1])  # flight
    stepper.step(1.0)
    platform.complete(platform.sent[-1])  # lowered
    stepper.step(2.0)
    wrong = "FAILED wrong object: the magnet holds 'box4', not 'box1'"
    platform.complete(platform.sent[-1], ok=False, reason=wrong)
    assert stepper.step(3.0) == Status(Progress.FAILED, f"ppcl_hook: {wrong}")
    assert len(platform.sent) == 3  # no raise after a failed attach
