import math

import pytest

from sim.rmax_params import RmaxParams
from sim.rotor import (
    blowback,
    figure_of_merit,
    flap_step,
    glauert_inflow,
    ground_effect_factor,
    hover_collective,
    lag,
    momentum_hover_power,
    rotor_loads,
    steady_inflow,
    thrust_coefficient,
)

P = RmaxParams()
MAIN = P.main_rotor
RHO = 1.225


def hover_ct(mass: float) -> float:
    tip = P.omega * MAIN.radius
    return mass * 9.80665 / (RHO * MAIN.disc_area * tip * tip)


def test_solidity_and_area_units() -> None:
    assert MAIN.disc_area == pytest.approx(math.pi * 1.5575**2)
    assert MAIN.solidity == pytest.approx(2 * 0.17 / (math.pi * 1.5575))


@pytest.mark.parametrize(
    ("pitch", "inflow", "sign"),
    [(0.1, 0.0, 1), (0.1, 0.05, 1), (-0.1, 0.0, -1), (0.0, 0.05, -1)],
)
def test_thrust_coefficient_sign(pitch: float, inflow: float, sign: int) -> None:
    assert math.copysign(1.0, thrust_coefficient(MAIN, pitch, 0.0, inflow)) == sign


def test_more_inflow_less_thrust_and_stall_limit() -> None:
    assert thrust_coefficient(MAIN, 0.1, 0.0, 0.06) < thrust_coefficient(MAIN, 0.1, 0.0, 0.03)
    assert thrust_coefficient(MAIN, 1.0, 0.0, 0.0) == pytest.approx(
        MAIN.max_ct_sigma * MAIN.solidity
    )


@pytest.mark.parametrize(
    ("ct", "mu", "climb"), [(0.005, 0.0, 0.0), (0.005, 0.1, 0.0), (0.004, 0.0, 0.02)]
)
def test_steady_inflow_satisfies_glauert(ct: float, mu: float, climb: float) -> None:
    lam = steady_inflow(ct, mu, climb)
    assert glauert_inflow(ct, mu, climb, lam) == pytest.approx(lam, rel=1e-9)


def test_hover_inflow_is_momentum_theory() -> None:
    assert steady_inflow(0.005) == pytest.approx(math.sqrt(0.005 / 2.0))


def test_forward_flight_reduces_induced_inflow() -> None:
    assert steady_inflow(0.005, mu=0.1) < 0.5 * steady_inflow(0.005)


@pytest.mark.parametrize("mass", [65.0, 80.0, 95.0])
def test_hover_collective_reproduces_thrust(mass: float) -> None:
    ct = hover_ct(mass)
    pitch = hover_collective(MAIN, ct)
    loads = rotor_loads(MAIN, pitch, P.omega, RHO, 0.0, 0.0, steady_inflow(ct))
    assert loads.thrust == pytest.approx(mass * 9.80665, rel=1e-9)
    # plausible blade pitch for a small untwisted rotor: between 5 and 12 degrees
    assert math.radians(5.0) < pitch < math.radians(12.0)


@pytest.mark.parametrize("mass", [65.0, 80.0, 95.0])
def test_hover_power_versus_momentum_theory(mass: float) -> None:
    ct = hover_ct(mass)
    pitch = hover_collective(MAIN, ct)
    loads = rotor_loads(MAIN, pitch, P.omega, RHO, 0.0, 0.0, steady_inflow(ct))
    ideal = momentum_hover_power(loads.thrust, RHO, MAIN.disc_area)
    fm = figure_of_merit(MAIN, ct)
    assert 0.55 < fm < 0.75  # textbook range for small rotors
    assert loads.power == pytest.approx(ideal / fm, rel=1e-9)
    assert loads.torque == pytest.approx(loads.power / P.omega)


def test_climb_costs_power() -> None:
    ct = hover_ct(80.0)
    pitch = hover_collective(MAIN, ct)
    lam = steady_inflow(ct)
    hover = rotor_loads(MAIN, pitch, P.omega, RHO, 0.0, 0.0, lam)
    climb = rotor_loads(MAIN, pitch + 0.02, P.omega, RHO, 0.0, 2.0, lam)
    assert climb.power > hover.power


def test_stopped_rotor_produces_nothing() -> None:
    loads = rotor_loads(MAIN, 0.1, 0.0, RHO, 5.0, 1.0, 0.0)
    assert (loads.thrust, loads.power, loads.torque) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("height", "expected"), [(100.0, 1.0), (1.5575, 1.0 / (1 - 1 / 16)), (0.1, 1.0 / (1 - 0.25))]
)
def test_ground_effect(height: float, expected: float) -> None:
    assert ground_effect_factor(height, MAIN.radius) == pytest.approx(expected, rel=1e-3)


def test_lag_is_exact_first_order() -> None:
    assert lag(0.0, 1.0, 0.1, 0.1) == pytest.approx(1.0 - math.exp(-1.0))
    assert lag(0.0, 1.0, 10.0, 0.01) == pytest.approx(1.0)


@pytest.mark.parametrize("rate", [-0.5, 0.0, 0.8])
def test_flap_steady_state_lags_body_rate(rate: float) -> None:
    tilt = 0.0
    for _ in range(1000):
        tilt = flap_step(tilt, 0.05, rate, 0.005, 0.12)
    assert tilt == pytest.approx(0.05 + 0.12 * rate, abs=1e-9)


def test_blowback_tilts_disc_back() -> None:
    assert blowback(0.12, 0.05, 0.1) > 0.0
