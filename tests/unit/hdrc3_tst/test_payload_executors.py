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
from hdrc3_tst.payload_executors import (
    CARRY_CABLE,
    FIRST_CABLE,
    HOVER_HEIGHT,
    PAYLOAD_EXECUTORS,
    REACH,
    SEARCH_HEIGHT,
    SETTLE_S,
    SIGHT_TIMEOUT_S,
)
from hdrc3_tst.platform_port import Command, PlatformState, Sighting

FRAME = frame_from_world("revinge")
POINTS = {"box1": ((-166.0, 96.0, 0.0),), "body1": ((40.0, -20.0, 0.0),)}
FLYING = PlatformState(0.0, 0.0, 30.0, on_ground=False, autonomous=True)
LOWER = (HookAction.LOWER, HOVER_HEIGHT + REACH, "")
ONTO = (HookAction.LOWER, 5.7 + REACH, "")
MAGNET_OFF = (HookAction.RELEASE, 0.0, "")
"""A pick-up's last lowering: as deep as the camera sees the box (5.7 m below the winch)."""
FIRST = (HookAction.LOWER, FIRST_CABLE, "")
"""A pick-up lowers twice: to FIRST_CABLE, then (aligned again) onto the object."""


def test_the_uav_logistics_operators_map_one_to_one_onto_executors() -> None:
    domain = TalReader().read_domain(UAV_DOMAIN.read_text())
    operators = {op.name for op in domain.operators} - {"fly-to"}
    assert set(PAYLOAD_EXECUTORS) == operators
    assert set(PAYLOAD_EXECUTORS) <= set(ACTIONS)


BELOW = Sighting((0.05, -0.03, -5.7), 1.0)
"""The hook camera sees box1 right below the winch."""


def _run(action: str, args: dict[str, float | str]) -> tuple[FakePlatform, Stepper]:
    platform = FakePlatform(sample=FLYING, sightings={"box1": BELOW})
    ctx = ActionContext("n", "uav0", ACTIONS[action], args, POINTS, platform, FRAME, 0.0)
    return platform, Stepper(PAYLOAD_EXECUTORS[action](), ctx)


def _search(platform: FakePlatform, stepper: Stepper, seen: Sighting | None = BELOW) -> None:
    """A pick-up's start: the magnet switched off and the hook wound in (each ending at once
    here), the climb over box1's point, a new sighting (or none), the descent (the caller
    completes it)."""
    assert stepper.step(0.0).progress is Progress.RUNNING
    (release,) = platform.sent
    assert _hook_call(release) == MAGNET_OFF
    platform.complete(release)
    stepper.step(0.02)
    wind = platform.sent[-1]
    assert _hook_call(wind) == (HookAction.RAISE, 0.0, "")
    platform.complete(wind)
    stepper.step(0.05)
    up = platform.sent[-1]
    east, north, _ = POINTS["box1"][0]
    alt = FRAME.to_wgs84(east, north, FRAME.ground_up(east, north) + SEARCH_HEIGHT)[2]
    assert up.args["altitude"] == pytest.approx(alt)
    platform.complete(up)
    stepper.step(0.5)  # arrived: waits for a sighting newer than the last one
    assert len(platform.sent) == 3
    if seen is None:
        stepper.step(1.0 + SIGHT_TIMEOUT_S)
    else:
        platform.sightings["box1"] = Sighting(seen.offset, seen.time + 0.5)
        stepper.step(0.6)
    assert len(platform.sent) == 4  # the descent


def _lowered_twice(platform: FakePlatform, stepper: Stepper, t: float = 1.0) -> None:
    """Aligned at once: the first lowering, a new image, the last lowering; attach sent."""
    stepper.step(t)
    stepper.step(t + 0.1)
    assert _hook_call(platform.sent[-1]) == FIRST
    platform.complete(platform.sent[-1])
    stepper.step(t + 0.2)
    assert _hook_call(platform.sent[-1]) == FIRST  # waits for an image after the lowering
    platform.sightings["box1"] = Sighting(BELOW.offset, t + 10.0)
    stepper.step(t + 0.3)
    stepper.step(t + 0.4)
    assert _hook_call(platform.sent[-1]) == ONTO
    platform.complete(platform.sent[-1])
    stepper.step(t + 0.5)
    assert platform.sent[-1].command is HookAction.ATTACH


def _hook_call(command: Command) -> tuple[object, ...]:
    return (command.command, command.args["length"], command.tag)


@pytest.mark.parametrize(
    ("action", "args", "over", "hook_calls"),
    [
        # a pick-up hovers where the hook camera saw the box from above (the aircraft's
        # estimate, here (0, 0), plus the camera's offset)
        ("pick-up-box", {"box": "box1"}, (0.05, -0.03),
         [FIRST, ONTO, (HookAction.ATTACH, 0.0, "box1"),
          (HookAction.RAISE, CARRY_CABLE, "")]),
        ("drop-box", {"box": "box1", "place": "body1"}, POINTS["body1"][0][:2],
         [LOWER, (HookAction.RELEASE, 0.0, ""), (HookAction.RAISE, 0.0, "")]),
    ],
)  # fmt: skip
def test_the_chapters_sequence_hover_lower_attach_or_release_raise(
    action: str,
    args: dict[str, float | str],
    over: tuple[float, float],
    hook_calls: list[tuple[object, ...]],
) -> None:
    platform, stepper = _run(action, args)
    if action == "pick-up-box":
        _search(platform, stepper)
    else:
        assert stepper.step(0.0).progress is Progress.RUNNING
    flight = platform.sent[-1]
    assert flight.command is FclCommand.TRAJ3D_FLYTO
    east, north = over
    up = FRAME.ground_up(east, north) + HOVER_HEIGHT
    lon, lat, alt = FRAME.to_wgs84(east, north, up)
    assert (flight.args["longitude"], flight.args["latitude"]) == pytest.approx((lon, lat))
    assert flight.args["altitude"] == pytest.approx(alt)
    for k, expected in enumerate(hook_calls):
        platform.complete(platform.sent[-1])
        assert stepper.step(1.0 + k).progress is Progress.RUNNING
        platform.sightings["box1"] = Sighting(BELOW.offset, 2.0 + k)  # a new image
        assert stepper.step(1.5 + k).progress is Progress.RUNNING
        assert _hook_call(platform.sent[-1]) == expected
    platform.complete(platform.sent[-1])
    assert stepper.step(10.0).progress is Progress.RUNNING
    climb = platform.sent[-1]
    assert climb.command is FclCommand.TRAJ3D_FLYTO  # back up clear of the ground
    _, _, alt = FRAME.to_wgs84(FLYING.east, FLYING.north, FRAME.ground_up(0.0, 0.0) + 12.0)
    assert climb.args["altitude"] == pytest.approx(alt)
    platform.complete(climb)
    assert stepper.step(11.0) == Status(Progress.SUCCEEDED)


def test_the_hook_camera_corrects_the_hover_over_the_box() -> None:
    platform, stepper = _run("pick-up-box", {"box": "box1"})
    _search(platform, stepper, Sighting((2.0, -1.0, -5.5), 1.0))  # seen 2.2 m off from above
    platform.complete(platform.sent[-1])  # the descent (the aircraft stays at (0, 0) here)
    stepper.step(1.0)
    stepper.step(1.5)
    correction = platform.sent[-1]
    assert correction.command is FclCommand.TRAJ3D_FLYTO
    lon, lat, _ = FRAME.to_wgs84(FLYING.east + 2.0, FLYING.north - 1.0, FLYING.up)
    assert (correction.args["longitude"], correction.args["latitude"]) == pytest.approx((lon, lat))
    platform.complete(correction)
    for k in range(round(SETTLE_S) + 2):  # hovering to settle
        stepper.step(2.0 + k)
    assert platform.sent[-1] is correction
    platform.sightings["box1"] = Sighting((0.4, 0.02, -5.6), 20.0)  # wandering: wait
    stepper.step(10.0)
    stepper.step(11.0)
    assert platform.sent[-1] is correction
    platform.sightings["box1"] = Sighting((0.1, 0.02, -5.6), 21.0)  # over the box
    stepper.step(12.0)
    stepper.step(13.0)
    assert _hook_call(platform.sent[-1]) == FIRST


def test_a_box_the_hook_camera_never_sees_fails_the_pick_up() -> None:
    platform, stepper = _run("pick-up-box", {"box": "box1"})
    platform.sightings.clear()
    _search(platform, stepper, None)
    descent = platform.sent[-1]  # unseen from above: down over the box's point
    east, north, _ = POINTS["box1"][0]
    _, _, alt = FRAME.to_wgs84(east, north, FRAME.ground_up(east, north) + HOVER_HEIGHT)
    assert descent.args["altitude"] == pytest.approx(alt)
    platform.complete(descent)
    stepper.step(10.0)
    outcome = stepper.step(11.0 + SIGHT_TIMEOUT_S)
    assert outcome == Status(Progress.FAILED, "the hook camera does not see box1")


WRONG = "FAILED wrong object: the magnet holds 'box10', not 'box1'"


@pytest.mark.parametrize(
    ("action", "args", "reason", "lets_go"),
    [
        ("pick-up-box", {"box": "box1"}, "FAILED the magnet gripped nothing", ()),
        ("attach-carrier", {"carrier": "box1"}, WRONG, (MAGNET_OFF,)),  # a box on the carrier
        ("take-from-carrier", {"box": "box1"}, WRONG, (MAGNET_OFF,)),  # its neighbour
        ("pick-up-box", {"box": "box1"}, WRONG, None),  # another box: a mis-stocked depot
    ],
)
def test_a_magnet_beside_the_object_is_wound_in_and_lowered_again(
    action: str, args: dict[str, float | str], reason: str, lets_go: tuple[object, ...] | None
) -> None:
    platform, stepper = _run(action, args)
    _search(platform, stepper)
    platform.complete(platform.sent[-1])  # flight
    _lowered_twice(platform, stepper)
    platform.complete(platform.sent[-1], ok=False, reason=reason)
    outcome = stepper.step(3.0)
    if lets_go is None:  # the pick-up fails with the platform's reason
        assert outcome == Status(Progress.FAILED, f"ppcl_hook: {reason}")
        assert len(platform.sent) == 7  # no raise after a failed attach
        return
    for k, expected in enumerate((*lets_go, (HookAction.RAISE, 0.0, ""))):
        assert _hook_call(platform.sent[-1]) == expected
        platform.complete(platform.sent[-1])
        stepper.step(3.5 + 0.1 * k)
    platform.sightings["box1"] = Sighting((0.1, 0.0, -5.7), 50.0)
    stepper.step(4.0)
    stepper.step(5.0)
    assert _hook_call(platform.sent[-1]) == FIRST
