import math

import pytest

from sim.aircraft import Aircraft
from sim.flight_model import InitialPlacement
from sim.rc_transmitter import FlightModeSwitch, RcSticks
from sim.yacs import CommandSource, YacsCommand


def started(**kwargs: object) -> Aircraft:
    ac = Aircraft(**kwargs)  # type: ignore[arg-type]
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(11.0)
    return ac


def test_status_reports_rc_and_engine() -> None:
    ac = Aircraft()
    st = ac.status()
    assert (st.mode, st.rc_link_ok, st.engine_running, st.rotor_rpm) == (
        FlightModeSwitch.MANUAL,
        True,
        False,
        0.0,
    )
    ac = started()
    st = ac.status()
    assert st.engine_running and st.rotor_rpm == pytest.approx(850.0, abs=10.0)
    assert st.source is CommandSource.COMPUTER


def test_lift_off_climb_and_land() -> None:
    ac = started(placement=InitialPlacement(east=50.0, north=-20.0, heading=2.0))
    assert ac.truth().on_ground
    ac.command(YacsCommand(vertical=1.0))
    ac.run(6.0)
    s = ac.truth()
    assert not s.on_ground
    assert s.velocity_enu[2] == pytest.approx(1.0, abs=0.15)
    assert s.height_above_ground > 2.0
    ac.command(YacsCommand(vertical=-0.7))
    ac.run(15.0)
    s = ac.truth()
    assert s.on_ground
    assert abs(s.height_above_ground) < 0.05
    assert s.engine_running
    ac.command(YacsCommand(vertical=-0.7))
    ac.rc.set_engine(False)
    ac.run(20.0)
    s = ac.truth()
    assert not s.engine_running and s.rotor_rpm < 425.0 and s.on_ground


def test_manual_pilot_lifts_off_with_throttle() -> None:
    ac = Aircraft()
    ac.rc.set_engine(True)
    ac.run(11.0)
    ac.rc.set_sticks(RcSticks(throttle=0.75))
    ac.run(3.0)
    s = ac.truth()
    assert not s.on_ground and s.velocity_enu[2] > 0.5
    assert abs(s.roll) < math.radians(5.0)


@pytest.mark.parametrize(
    ("mode", "stopped"), [(FlightModeSwitch.AUTONOMOUS, True), (FlightModeSwitch.MANUAL, False)]
)
def test_computer_engine_cut_needs_authority_and_a_pilot_restart(
    mode: FlightModeSwitch, stopped: bool
) -> None:
    ac = started()
    ac.rc.set_mode(mode)
    ac.command(YacsCommand(vertical=-1.0, engine_off=True))
    ac.run(0.1)
    ac.command(YacsCommand(vertical=-1.0))  # the cut latches; no need to keep asking
    ac.run(0.1)
    assert ac.status().engine_running is not stopped
    ac.restart_engine()
    ac.run(0.1)
    assert ac.status().engine_running
