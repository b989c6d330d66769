import math

import pytest

from sim.powertrain import Powertrain
from sim.rmax_params import RmaxParams

P = RmaxParams()
DT = 0.005


def run(pt: Powertrain, seconds: float, on: bool, torque: float) -> None:
    for _ in range(round(seconds / DT)):
        pt.step(DT, on, torque)


def test_governor_spins_up_to_850_rpm() -> None:
    pt = Powertrain(P, fuel=4.0)
    run(pt, P.spinup_time + 3.0, True, 60.0)
    assert pt.running
    assert pt.omega * 60 / (2 * math.pi) == pytest.approx(850.0, abs=3.0)


def test_soft_start_follows_ramp() -> None:
    pt = Powertrain(P, fuel=4.0)
    run(pt, P.spinup_time / 2, True, 20.0)
    assert pt.omega == pytest.approx(P.omega / 2, rel=0.1)


def test_engine_off_spins_down() -> None:
    pt = Powertrain(P, fuel=4.0)
    run(pt, 15.0, True, 60.0)
    run(pt, 10.0, False, 60.0)
    assert not pt.running
    assert pt.omega == 0.0


def test_no_fuel_no_engine() -> None:
    pt = Powertrain(P, fuel=0.0)
    run(pt, 5.0, True, 0.0)
    assert not pt.running
    assert pt.omega == 0.0


def test_fuel_burn_matches_bsfc() -> None:
    pt = Powertrain(P, fuel=4.0)
    run(pt, 15.0, True, 80.0)
    before = pt.fuel
    run(pt, 10.0, True, 80.0)
    expected = P.bsfc * pt.engine_power / 3.6e6 * 10.0
    assert before - pt.fuel == pytest.approx(expected, rel=0.02)


def test_overload_droops_rotor() -> None:
    pt = Powertrain(P, fuel=4.0)
    overload = 1.2 * P.max_engine_torque  # more than the engine can give
    run(pt, 15.0, True, overload)
    assert pt.throttle == 1.0
    assert pt.omega < 0.5 * P.omega
