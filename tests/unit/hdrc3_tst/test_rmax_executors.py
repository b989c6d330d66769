"""The RMAX executors: one per action of the registry, and the commands each sends."""

from __future__ import annotations

import math

import pytest

from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.executor import ActionContext, Progress, Status, Stepper
from hdrc3_tst.fake_platform import FakePlatform
from hdrc3_tst.platform_port import PlatformState
from hdrc3_tst.rmax_executors import DATA_TIMEOUT_S, RMAX_EXECUTORS

FRAME = frame_from_world("revinge")
POINTS = {"Sq": ((100.0, 50.0, 30.0),)}
FLYING = PlatformState(0.0, 0.0, 30.0, on_ground=False, autonomous=True)
FLYING_ELSEWHERE = PlatformState(100.0, 60.0, 30.0, on_ground=False, autonomous=True)


def test_every_action_has_an_rmax_executor() -> None:
    assert set(RMAX_EXECUTORS) == set(ACTIONS)


def step(action: str, args: dict[str, float | str], platform: FakePlatform) -> Stepper:
    """The action's executor with ``args`` and the defaults of the parameters not given."""
    spec = ACTIONS[action]
    defaults = {p.name: p.default for p in spec.params if p.default is not None}
    ctx = ActionContext("n", "uav0", spec, defaults | args, POINTS, platform, FRAME, 0.0)
    return Stepper(RMAX_EXECUTORS[action](), ctx)


@pytest.mark.parametrize(
    ("action", "args", "command", "sent"),
    [
        ("land", {"heading": 90.0}, FclCommand.LAND, {"heading": math.pi / 2}),
        ("ptu-turn-to", {"pan": 90.0, "tilt": 45.0}, PpclCommand.TURN_TO,
         {"pan": math.pi / 2, "tilt": math.pi / 4}),
        ("camera-zoom", {"camera": 0.0, "zoom": 20.0}, PpclCommand.ZOOM,
         {"camera_id": 0.0, "value": 1.0}),
        ("fly-to", {"speed": 4.0, "destination": "Sq"}, FclCommand.TRAJ3D_FLYTO, None),
        ("look-at", {"target": "Sq"}, PpclCommand.LOOK_AT, None),
    ],
)  # fmt: skip
def test_one_command_and_its_outcome(
    action: str, args: dict[str, float | str], command: object, sent: dict[str, float] | None
) -> None:
    platform = FakePlatform(sample=FLYING)
    stepper = step(action, args, platform)
    assert stepper.step(0.0) == Status(Progress.RUNNING)
    (handle,) = platform.sent
    assert handle.command is command
    if sent is not None:
        assert handle.args == pytest.approx(sent)
    else:  # WGS84 of the local point
        lon, lat, _ = FRAME.to_wgs84(100.0, 50.0, 30.0)
        assert (handle.args["longitude"], handle.args["latitude"]) == pytest.approx((lon, lat))
    platform.complete(handle, ok=False, reason="FAILED on fire")
    assert stepper.step(1.0) == Status(Progress.FAILED, f"{handle.label}: FAILED on fire")


def test_flight_actions_take_off_from_the_ground_first() -> None:
    platform = FakePlatform()
    stepper = step("fly-to", {"speed": 4.0, "destination": "Sq"}, platform)
    stepper.step(0.0)
    assert [c.command for c in platform.sent] == [FclCommand.TAKEOFF]
    platform.complete(platform.sent[0])
    stepper.step(1.0)
    assert [c.command for c in platform.sent] == [FclCommand.TAKEOFF, FclCommand.TRAJ3D_FLYTO]


def test_no_data_interface_fails_after_the_data_timeout() -> None:
    platform = FakePlatform(sample=None)
    stepper = step("hover", {"duration": 100.0}, platform)
    assert stepper.step(DATA_TIMEOUT_S).progress is Progress.RUNNING
    assert stepper.step(DATA_TIMEOUT_S + 1) == Status(
        Progress.FAILED, "no Data Interface sample from uav0 in 10 s"
    )


def test_a_failsafe_fails_hover() -> None:
    platform = FakePlatform(sample=FLYING)
    stepper = step("hover", {"duration": 10.0}, platform)
    assert stepper.step(1.0).progress is Progress.RUNNING
    platform.sample = PlatformState(0.0, 0.0, 30.0, False, True, failsafe="GPS lost")
    assert stepper.step(2.0) == Status(Progress.FAILED, "hover interrupted by a failsafe: GPS lost")


def start_scan(stepper: Stepper, platform: FakePlatform) -> None:
    """Step a scan past its camera commands (PTU down, saliency on), each done at once."""
    for t, command in enumerate((PpclCommand.TURN_TO, PpclCommand.IP_SALIENCY)):
        stepper.step(t / 10.0)
        assert platform.sent[-1].command is command
        platform.complete(platform.sent[-1])
    stepper.step(0.2)
    assert platform.sent[-1].command is FclCommand.TRAJ3D_FLYTO  # to the first leg


def test_a_path_ending_before_its_last_segment_fails() -> None:
    platform = FakePlatform(sample=FLYING)
    stepper = step("scan-area", {"speed": 5.0, "area": "A", "altitude": 30.0}, platform)
    stepper.ctx.points = {"A": ((0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0))}
    start_scan(stepper, platform)
    platform.complete(platform.sent[-1])  # the fly-to the first leg
    stepper.step(1.0)
    first = platform.sent[-1]
    assert first.command is FclCommand.TRAJ3D
    platform.complete(first)  # finished without asking for the next segment
    stepper.step(2.0)
    assert platform.sent[-1].command is PpclCommand.IP_ABORT  # the pipeline stops however it ends
    platform.complete(platform.sent[-1])
    outcome = stepper.step(2.1)
    assert outcome.progress is Progress.FAILED
    assert outcome.reason.startswith("path following ended after segment 0 of ")


def test_a_resumed_scan_starts_again_at_the_segment_it_was_flying() -> None:
    area = {"A": ((0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0))}
    platform = FakePlatform(sample=FLYING)
    stepper = step("scan-area", {"speed": 5.0, "area": "A", "altitude": 30.0}, platform)
    stepper.ctx.points = area
    start_scan(stepper, platform)
    platform.complete(platform.sent[-1])  # the fly-to the first leg
    for t in range(1, 4):  # segments 0, 1, 2 sent, each asking for the next
        stepper.step(float(t))
        platform.sent[-1].segment_requested = True
    stepper.step(4.0)
    flown = [c for c in platform.sent if c.command is FclCommand.TRAJ3D]
    assert len(flown) == 4  # segment 3 in flight: 0 to 2 are done
    assert stepper.ctx.memory == {
        "segments_done": 2,
        "scan_start_east": 0.0,
        "scan_start_north": 0.0,
    }
    # pause: the engine stops the commands and later starts a new run with the same memory
    again = step("scan-area", {"speed": 5.0, "area": "A", "altitude": 30.0}, platform)
    again.ctx.points, again.ctx.memory = area, stepper.ctx.memory
    platform.sample = FLYING_ELSEWHERE  # the entry corner stays the one planned first
    start_scan(again, platform)
    transit = platform.sent[-1]  # to the start of segment 2, not 0
    start = [flown[2].args[f"start_{axis}"] for axis in "xyz"]
    assert start != [flown[0].args[f"start_{axis}"] for axis in "xyz"]
    lon, lat, _ = FRAME.to_wgs84(*start)
    assert (transit.args["longitude"], transit.args["latitude"]) == pytest.approx((lon, lat))


@pytest.mark.parametrize(
    ("action", "args", "bound"),
    [
        ("ptu-turn-to", {"pan": 0.0, "tilt": 0.0}, 60.0),
        ("land", {"heading": 0.0}, 60.0 + 3.0 * 30.1),  # 30 m up over ground at -0.1 m
        (
            "fly-to",
            {"speed": 5.0, "destination": "Sq"},
            60.0 + 3.0 * math.dist((0, 0), (100, 50)) / 5,
        ),
    ],
)
def test_a_command_without_outcome_is_stopped_at_its_bound(
    action: str, args: dict[str, float | str], bound: float
) -> None:
    platform = FakePlatform(sample=FLYING)
    stepper = step(action, args, platform)
    stepper.step(0.0)
    assert stepper.step(bound - 0.5).progress is Progress.RUNNING
    status = stepper.step(bound + 0.5)
    assert status.progress is Progress.FAILED
    assert status.reason.endswith(f"no outcome in {bound:.0f} s")
    assert [c for c, _ in platform.stopped] == platform.sent


LASER_SETUP = (
    (PpclCommand.LASER_ANGULAR_RESOLUTION, {"angular_resolution": 1.0}),
    (PpclCommand.LASER_DISTANCE_RESOLUTION, {"distance_resolution": 0.01}),
    (PpclCommand.LASER_ROTATION_SPEED, {"rotation_speed": 3.0}),
    (PpclCommand.LASER_START_DATA_COLLECTION, {}),
)


@pytest.mark.parametrize("ending", ["flown", "aborted"])
def test_laser_mapping_collects_only_while_it_flies_its_pattern(ending: str) -> None:
    platform = FakePlatform(sample=FLYING)
    stepper = step("laser-map-area", {"speed": 5.0, "area": "A", "altitude": 30.0}, platform)
    stepper.ctx.points = {"A": ((0.0, 0.0), (100.0, 0.0), (100.0, 150.0), (0.0, 150.0))}
    for t, (command, args) in enumerate(LASER_SETUP):
        stepper.step(t / 10.0)
        assert (platform.sent[-1].command, platform.sent[-1].args) == (command, args)
        platform.complete(platform.sent[-1])
    stepper.step(1.0)
    assert platform.sent[-1].command is FclCommand.TRAJ3D_FLYTO  # to the first strip
    if ending == "aborted":
        stepper.close()
        assert platform.sent[-1].command is PpclCommand.LASER_STOP_DATA_COLLECTION
        return
    platform.complete(platform.sent[-1])
    for t in range(2, 30):  # each segment asks for the next at once
        stepper.step(float(t))
        platform.sent[-1].segment_requested = True
    strips = [c for c in platform.sent if c.command is FclCommand.TRAJ3D]
    platform.complete(strips[-1])
    assert stepper.step(30.0).progress is Progress.RUNNING
    assert platform.sent[-1].command is PpclCommand.LASER_STOP_DATA_COLLECTION
    platform.complete(platform.sent[-1])
    assert stepper.step(31.0).progress is Progress.SUCCEEDED
    # legs along the 150 m side; 100 m across with strips 52.9 m wide (less the overlap): three
    # legs joined by two turns
    assert len(strips) == 5
    assert {round(c.args["start_x"] - c.args["end_x"]) for c in strips[::2]} == {0}


@pytest.mark.parametrize(("altitude", "width"), [(30.0, 52.915), (0.0, 80.0), (45.0, 0.0)])
def test_the_laser_swath_is_the_chord_its_reach_cuts_on_the_ground(
    altitude: float, width: float
) -> None:
    from hdrc3_tst.rmax_executors import laser_swath_width

    assert laser_swath_width(altitude) == pytest.approx(width, abs=1e-3)


def test_laser_mapping_above_the_lasers_reach_fails_before_sending_anything() -> None:
    platform = FakePlatform(sample=FLYING)
    stepper = step("laser-map-area", {"speed": 5.0, "area": "A", "altitude": 45.0}, platform)
    stepper.ctx.points = {"A": ((0.0, 0.0), (100.0, 0.0), (100.0, 150.0), (0.0, 150.0))}
    outcome = stepper.step(0.0)
    assert outcome == Status(Progress.FAILED, "altitude 45 m: the laser maps well only within 40 m")
    assert not platform.sent
