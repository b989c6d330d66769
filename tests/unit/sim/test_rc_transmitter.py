import math

import pytest

from hdrc3_base.errors import ConfigError
from sim.rc_transmitter import FlightModeSwitch, RcSticks, RcTransmitter


@pytest.mark.parametrize(
    "kwargs",
    [{"roll": 1.5}, {"pitch": -2.0}, {"yaw": math.nan}, {"throttle": -0.1}, {"throttle": 1.1}],
)
def test_sticks_outside_travel_rejected(kwargs: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        RcSticks(**kwargs)


def test_starts_manual_engine_off_link_ok() -> None:
    state = RcTransmitter().state
    assert state.mode is FlightModeSwitch.MANUAL
    assert not state.engine_on and state.link_ok
    assert state.sticks == RcSticks()


def test_switches_change_the_snapshot() -> None:
    rc = RcTransmitter()
    before = rc.state
    rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    rc.set_engine(True)
    rc.set_link(False)
    rc.set_sticks(RcSticks(throttle=0.5))
    after = rc.state
    assert before.mode is FlightModeSwitch.MANUAL  # snapshots are immutable
    assert (after.mode, after.engine_on, after.link_ok, after.sticks.throttle) == (
        FlightModeSwitch.AUTONOMOUS,
        True,
        False,
        0.5,
    )
