"""Winch and magnet state machine: lengths, speeds, stall, faults."""

from __future__ import annotations

import pytest

from sim.hook import Hook, HookFault, HookParams, WinchState

P = HookParams()


@pytest.mark.parametrize(
    ("command", "tension", "seconds", "length", "winch"),
    [
        (2.0, 0.0, 1.0, P.stowed_cable + P.winch_speed, WinchState.LOWERING),
        (2.0, 0.0, 10.0, 2.0, WinchState.STOPPED),
        (99.0, 0.0, 60.0, P.max_cable, WinchState.STOPPED),  # clamped to the drum
        (-5.0, 0.0, 1.0, P.stowed_cable, WinchState.STOPPED),  # clamped to stowed
    ],
)
def test_winch_pays_out_at_its_speed_within_its_limits(
    command: float, tension: float, seconds: float, length: float, winch: WinchState
) -> None:
    hook = Hook()
    hook.command(command, magnet=False)
    for _ in range(round(seconds / 0.005)):
        hook.step(0.005, tension)
    hook.step(0.005, tension)  # one more step reports the state at the end
    step = P.winch_speed * 0.005
    assert hook.length == pytest.approx(min(length, max(command, P.stowed_cable)), abs=step)
    assert hook.winch is winch


@pytest.mark.parametrize(
    ("tension", "winch", "wound_in"),
    [(100.0, WinchState.RAISING, True), (P.stall_tension + 1.0, WinchState.STALLED, False)],
)
def test_winding_in_stalls_above_the_rated_tension(
    tension: float, winch: WinchState, wound_in: bool
) -> None:
    hook = Hook()
    hook.command(5.0, magnet=True)
    for _ in range(2000):
        hook.step(0.005, 0.0)
    hook.command(0.0, magnet=True)
    hook.step(0.5, tension)
    assert hook.winch is winch
    assert (hook.length < 5.0 - 1e-6) is wound_in


def test_grip_and_faults() -> None:
    hook = Hook()
    assert not hook.may_grip()  # magnet off
    hook.command(1.0, magnet=True)
    assert hook.may_grip()
    hook.inject(HookFault.WRONG_BOX)
    assert hook.wrong_box
    hook.gripped("box1")
    assert not hook.wrong_box and not hook.may_grip() and not hook.must_let_go()
    reading = hook.reading()
    assert reading.carrying and reading.object_id == "box1" and reading.magnet
    hook.inject(HookFault.RELEASE)
    assert hook.must_let_go()
    hook.let_go()
    assert not hook.release_now and hook.reading().object_id == ""
    hook.inject(HookFault.HOOK_FAIL)
    assert not hook.may_grip()
    hook.inject(HookFault.NONE)
    hook.command(1.0, magnet=False)
    hook.command(1.0, magnet=True)
    assert hook.may_grip()


def test_release_with_nothing_held_does_not_drop_the_next_grip() -> None:
    hook = Hook()
    hook.command(1.0, magnet=True)
    hook.inject(HookFault.RELEASE)
    hook.gripped("box1")
    assert not hook.must_let_go()


def test_magnet_off_lets_go() -> None:
    hook = Hook()
    hook.command(1.0, magnet=True)
    hook.gripped("c1")
    hook.command(1.0, magnet=False)
    assert hook.must_let_go()


def test_a_magnet_that_lost_its_load_grips_again_only_after_being_switched_off_and_on() -> None:
    hook = Hook()
    hook.command(1.0, magnet=True)
    hook.gripped("box1")
    hook.inject(HookFault.RELEASE)
    hook.let_go()
    assert not hook.may_grip()
    hook.command(1.0, magnet=False)
    hook.command(1.0, magnet=True)
    assert hook.may_grip()


def test_the_load_cell_filters_the_jerks_of_a_falling_hook() -> None:
    hook = Hook()
    for k in range(400):  # an on-off pull averaging 15 N
        hook.step(0.005, 30.0 if k % 2 else 0.0)
    assert hook.reading().tension == pytest.approx(15.0, abs=1.0)
