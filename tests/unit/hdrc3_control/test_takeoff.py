"""Take-off: refusals, and the overweight take-off failure reported instead of hanging."""

from __future__ import annotations

from types import ModuleType

import pytest

from hdrc3_control.commands import EstimatedState
from hdrc3_control.takeoff import Takeoff, TakeoffStatus


@pytest.mark.parametrize(
    ("on_ground", "rpm", "status"),
    [
        (True, 850.0, TakeoffStatus.CLIMBING),
        (False, 850.0, TakeoffStatus.REFUSED_NOT_ON_GROUND),
        (True, 300.0, TakeoffStatus.SPOOLING),
    ],
)
def test_start_conditions(on_ground: bool, rpm: float, status: TakeoffStatus) -> None:
    state = EstimatedState(
        0.0, (0.0, 0.0, 0.45), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0, on_ground=on_ground, rotor_rpm=rpm
    )
    fn = Takeoff()
    assert fn.start(state, 0.0) is status
    out = fn.update(state, 0.02, 0.02)
    assert out.status is status
    assert (out.command.vertical > 0.0) is (status is TakeoffStatus.CLIMBING)


@pytest.mark.parametrize(
    ("rpms", "status"),
    [
        ((300.0, 600.0, 805.0), TakeoffStatus.CLIMBING),
        ((300.0, 300.0, 300.0), TakeoffStatus.REFUSED_ENGINE),
    ],
)
def test_spooling_waits_for_governed_rotor_speed(
    rpms: tuple[float, ...], status: TakeoffStatus
) -> None:
    fn = Takeoff()
    times = (0.0, 10.0, 31.0)

    def state(rpm: float) -> EstimatedState:
        return EstimatedState(
            0.0, (0.0, 0.0, 0.45), (0.0, 0.0, 0.0), 0.0, 0.0, 0.0, on_ground=True, rotor_rpm=rpm
        )

    assert fn.start(state(rpms[0]), times[0]) is TakeoffStatus.SPOOLING
    assert fn.update(state(rpms[1]), times[1], 0.02).status is TakeoffStatus.SPOOLING
    out = fn.update(state(rpms[2]), times[2], 0.02)
    assert out.status is status
    if status is TakeoffStatus.REFUSED_ENGINE:
        assert out.reason == "rotor at 300 rpm after 30 s, needs 800"


@pytest.mark.parametrize(("payload", "ok"), [(0.0, True), (70.0, False)])
def test_takeoff_or_reported_failure(harness: ModuleType, payload: float, ok: bool) -> None:
    f = harness.SimFlight(seed=5, payload=payload)
    f.start_engine()
    result = harness.takeoff(f, 10.0, timeout=40.0)
    last = result.outputs[-1]
    assert result.ok is ok
    if ok:
        assert last.status is TakeoffStatus.DONE
        assert abs(f.truth().position_enu[2] - 10.45) < 2.0
    else:
        assert last.status is TakeoffStatus.FAILED_NO_LIFT and last.reason
        assert f.now < 12.0 + 30.0  # detected, not hanging until the phase timeout
        harness.SimFlight.fly(f, lambda s, now: last.command, 5.0)
        assert f.truth().on_ground
