"""ppcl_hook: validation, one final event per command, outcomes from the carrying sensor."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from hdrc3_platform_server.codes import EventKind, PpclCode
from hdrc3_platform_server.completion import EventLog
from hdrc3_platform_server.fcl_api import IdSource
from hdrc3_platform_server.hook_api import (
    HookAction,
    HookCommandLayer,
    HookSample,
    HookSetpoint,
    Winch,
)

LOWER, ATTACH, RAISE, RELEASE = (int(a) for a in HookAction)
STOWED = HookSample(0.0, False, "", False, int(Winch.STOPPED), 0.15, 14.7)


class Rig:
    """A hook layer with its event log and the set-points it sent."""

    def __init__(self) -> None:
        self.log = EventLog()
        self.sent: list[HookSetpoint] = []
        self.layer = HookCommandLayer(self.log, IdSource(1), self.sent.append)
        self.layer.on_sample(STOWED)

    def sample(self, t: float, **changes: object) -> None:
        self.layer.on_sample(replace(STOWED, time=t, **changes))  # type: ignore[arg-type]

    def final(self, cid: int) -> tuple[EventKind, str] | None:
        e = self.log.final(cid)
        return None if e is None else (e.kind, e.reason)


@pytest.mark.parametrize(
    ("action", "length", "object_id", "reason"),
    [
        (7, 1.0, "", "unknown hook action 7"),
        (LOWER, math.nan, "", "cable length must be finite"),
        (LOWER, 25.0, "", "within [0, 20] m"),
        (RAISE, 5.0, "", "only 0.15 m of cable are out"),
        (ATTACH, 0.0, "x" * 65, "at most 64 printable"),
        (ATTACH, 0.0, "box\n1", "printable"),
    ],
)
def test_bad_input_is_answered_with_a_reason(
    action: int, length: float, object_id: str, reason: str
) -> None:
    rig = Rig()
    answer = rig.layer.submit(action, length, object_id, 0.0)
    assert answer.code is PpclCode.NOT_ACCEPTED and reason in answer.reason
    assert not rig.sent and not rig.log.events


def test_without_sensor_data_commands_are_refused() -> None:
    rig = Rig()
    answer = rig.layer.submit(LOWER, 2.0, "", 10.0)  # the last sample is 10 s old
    assert answer.code is PpclCode.NOT_ACCEPTED and "carrying sensor" in answer.reason


def test_lower_finishes_at_the_length() -> None:
    rig = Rig()
    cid = rig.layer.submit(LOWER, 2.0, "", 0.0).command_id
    assert rig.sent == [HookSetpoint(2.0, False)]
    rig.sample(1.0, cable_length=0.8, winch=int(Winch.LOWERING))
    assert rig.final(cid) is None
    rig.sample(3.0, cable_length=2.0)
    assert rig.final(cid) == (EventKind.FINISHED, "")


def test_lower_stops_when_the_hook_rests_on_something() -> None:
    rig = Rig()
    cid = rig.layer.submit(LOWER, 5.0, "", 0.0).command_id
    for k in range(12):
        rig.sample(1.0 + 0.1 * k, cable_length=2.5, tension=0.0, winch=int(Winch.LOWERING))
    kind, reason = rig.final(cid) or (None, "")
    assert kind is EventKind.FINISHED and "rests on something at 2.50 m" in reason
    assert rig.sent[-1] == HookSetpoint(2.5, False)  # the winch stops there


@pytest.mark.parametrize(
    ("expected", "held", "outcome"),
    [
        ("box1", "box1", (EventKind.FINISHED, "box1")),
        ("", "box4", (EventKind.FINISHED, "box4")),
        ("box1", "box4", (EventKind.FAILED, "wrong object: the magnet holds 'box4', not 'box1'")),
    ],
)
def test_attach_checks_what_the_magnet_holds(
    expected: str, held: str, outcome: tuple[EventKind, str]
) -> None:
    rig = Rig()
    cid = rig.layer.submit(ATTACH, 0.0, expected, 0.0).command_id
    assert rig.sent == [HookSetpoint(0.0, True)]
    rig.sample(0.5, carrying=True, object_id=held, magnet=True)
    assert rig.final(cid) == outcome


def test_attach_gripping_nothing_fails_and_switches_the_magnet_off() -> None:
    rig = Rig()
    cid = rig.layer.submit(ATTACH, 0.0, "", 0.0).command_id
    rig.sample(2.0, magnet=True)
    assert rig.final(cid) is None
    rig.sample(3.5, magnet=True)
    assert rig.final(cid) == (EventKind.FAILED, "the magnet gripped nothing")
    assert rig.sent[-1] == HookSetpoint(0.0, False)


def test_raise_fails_on_a_stalled_winch_and_on_a_lost_load() -> None:
    held = {"carrying": True, "object_id": "c1", "magnet": True, "cable_length": 3.0}
    rig = Rig()
    rig.sample(0.0, **held)
    cid = rig.layer.submit(RAISE, 0.5, "", 0.0).command_id
    for k in range(29):  # a stall shorter than stall_time is a moment of lift-off
        rig.sample(0.1 * k, winch=int(Winch.STALLED), tension=900.0, **held)
    assert rig.final(cid) is None
    rig.sample(3.0, winch=int(Winch.STALLED), tension=900.0, **held)
    kind, reason = rig.final(cid) or (None, "")
    assert kind is EventKind.FAILED and "stalled at 900 N" in reason
    cid = rig.layer.submit(RAISE, 0.5, "", 4.0).command_id
    rig.sample(4.5, cable_length=2.0, winch=int(Winch.RAISING))
    assert rig.final(cid) == (EventKind.FAILED, "the load was lost while raising")


def test_a_newer_command_cancels_the_running_one_and_every_command_ends_once() -> None:
    rig = Rig()
    first = rig.layer.submit(LOWER, 4.0, "", 0.0).command_id
    second = rig.layer.submit(RELEASE, 0.0, "", 0.1).command_id
    kind, reason = rig.final(first) or (None, "")
    assert kind is EventKind.CANCELLED and f"command {second}" in reason
    rig.sample(0.2)
    rig.sample(0.3)
    assert rig.final(second) == (EventKind.FINISHED, "")
    ends = [e for e in rig.log.events if e.kind is not EventKind.INFO]
    assert sorted(e.command_id for e in ends) == [first, second]


def test_a_world_reset_fails_the_running_command() -> None:
    rig = Rig()
    cid = rig.layer.submit(LOWER, 4.0, "", 0.0).command_id
    rig.layer.on_world_reset("reset", 1.0)
    assert rig.final(cid) == (EventKind.FAILED, "simulation reset: reset")
    assert rig.layer.submit(LOWER, 4.0, "", 1.0).code is PpclCode.NOT_ACCEPTED


def test_a_raise_to_zero_ends_at_the_wound_in_hook() -> None:
    rig = Rig()
    rig.sample(0.0, cable_length=3.0)
    cid = rig.layer.submit(RAISE, 0.0, "", 0.0).command_id
    rig.sample(5.0, cable_length=0.12)
    assert rig.final(cid) == (EventKind.FINISHED, "")
