"""Rotor aerodynamics: uniform-inflow blade-element/momentum model with inflow and flapping lag.

Pure functions of floats (no JSBSim) so that signs, units and hover power can be unit-tested.

Non-dimensional quantities follow Leishman, *Principles of Helicopter Aerodynamics*: tip speed
``V_t = Omega R``, advance ratio ``mu = V_inplane / V_t``, inflow ``lambda = lambda_i + lambda_c``
(positive down through the disc), thrust coefficient ``C_T = T / (rho A V_t^2)``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from sim.rmax_params import RotorParams

_MIN_TIP_SPEED = 1.0
"""Below this tip speed (m/s) the rotor produces nothing (avoids 0/0 at standstill)."""
_MIN_TOTAL_INFLOW = 0.01
"""Floor on sqrt(mu^2 + lambda^2) in the Glauert inflow law (regularises the hover start)."""


class RotorLoads(NamedTuple):
    """Loads of one rotor at one instant."""

    thrust: float
    """Thrust along the tip-path-plane normal, N (negative: reversed)."""
    power: float
    """Aerodynamic shaft power, W (induced + climb + profile)."""
    torque: float
    """Shaft torque, N m."""
    ct: float
    """Thrust coefficient C_T (before the ground-effect factor)."""
    inflow_target: float
    """Induced inflow lambda_i the momentum balance asks for at this C_T."""
    inflow_time_constant: float
    """Pitt-Peters time constant of the inflow, s."""


def thrust_coefficient(rotor: RotorParams, pitch: float, mu: float, inflow: float) -> float:
    """Blade-element thrust coefficient, clipped at blade stall.

    Args:
        rotor: Rotor parameters.
        pitch: Collective blade pitch at the root, rad.
        mu: Advance ratio.
        inflow: Total inflow ratio lambda (positive down through the disc).

    """
    sigma = rotor.solidity
    ct = (
        0.5
        * sigma
        * rotor.lift_slope
        * (
            pitch * (1.0 / 3.0 + 0.5 * mu * mu)
            + 0.25 * rotor.twist * (1.0 + mu * mu)
            - 0.5 * inflow
        )
    )
    limit = rotor.max_ct_sigma * sigma
    return max(-limit, min(limit, ct))


def power_coefficient(
    rotor: RotorParams, ct: float, induced: float, climb: float, mu: float
) -> float:
    """Power coefficient C_P = kappa lambda_i C_T + lambda_c C_T + sigma Cd0 / 8 (1 + 4.65 mu^2)."""
    profile = rotor.solidity * rotor.profile_drag / 8.0 * (1.0 + 4.65 * mu * mu)
    return rotor.induced_factor * induced * ct + climb * ct + profile


def glauert_inflow(ct: float, mu: float, climb: float, induced: float) -> float:
    """Induced inflow that satisfies C_T = 2 lambda_i sqrt(mu^2 + lambda^2) for the given lambda.

    Args:
        ct: Thrust coefficient.
        mu: Advance ratio.
        climb: Climb inflow lambda_c (axial speed through the disc / tip speed).
        induced: Current induced inflow, used for the total inflow in the denominator.

    """
    total = induced + climb
    root = max(_MIN_TOTAL_INFLOW, math.sqrt(mu * mu + total * total))
    return ct / (2.0 * root)


def steady_inflow(ct: float, mu: float = 0.0, climb: float = 0.0) -> float:
    """Solve the Glauert inflow law for lambda_i by fixed-point/Newton iteration."""
    lam = math.sqrt(abs(ct) / 2.0) if ct else 0.0
    for _ in range(50):
        total = lam + climb
        root = math.sqrt(mu * mu + total * total)
        if root < 1e-9:
            return 0.0
        residual = lam - ct / (2.0 * root)
        derivative = 1.0 + ct * total / (2.0 * root**3)
        step = residual / derivative if abs(derivative) > 1e-6 else residual
        lam -= step
        if abs(step) < 1e-12:
            break
    return lam


def ground_effect_factor(hub_height: float, radius: float) -> float:
    """Cheeseman-Bennett thrust ratio T_IGE / T_OGE at equal power, clipped at z/R = 0.5."""
    z_over_r = max(0.5, hub_height / radius)
    return 1.0 / (1.0 - (0.25 / z_over_r) ** 2)


def rotor_loads(
    rotor: RotorParams,
    pitch: float,
    omega: float,
    rho: float,
    inplane_speed: float,
    climb_speed: float,
    induced: float,
    ground_factor: float = 1.0,
) -> RotorLoads:
    """Thrust, power and inflow dynamics of one rotor for the current lagged inflow.

    Args:
        rotor: Rotor parameters.
        pitch: Collective blade pitch, rad.
        omega: Rotor speed, rad/s.
        rho: Air density, kg/m^3.
        inplane_speed: Air-relative speed in the disc plane, m/s.
        climb_speed: Air-relative speed along the thrust direction, m/s (climb positive).
        induced: Current (lagged) induced inflow ratio lambda_i.
        ground_factor: Thrust multiplier for ground effect (1 out of ground effect).

    """
    tip_speed = omega * rotor.radius
    if tip_speed < _MIN_TIP_SPEED:
        return RotorLoads(0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
    mu = inplane_speed / tip_speed
    climb = climb_speed / tip_speed
    ct = thrust_coefficient(rotor, pitch, mu, induced + climb)
    scale = rho * rotor.disc_area * tip_speed * tip_speed
    cp = power_coefficient(rotor, ct, induced, climb, mu)
    power = cp * scale * tip_speed
    total = max(_MIN_TOTAL_INFLOW, math.sqrt(mu * mu + (induced + climb) ** 2))
    tau = 0.849 / (4.0 * total * omega)
    return RotorLoads(
        thrust=ct * scale * ground_factor,
        power=power,
        torque=power / omega,
        ct=ct,
        inflow_target=ct / (2.0 * total),
        inflow_time_constant=tau,
    )


def lag(value: float, target: float, dt: float, time_constant: float) -> float:
    """Exact first-order lag step towards ``target`` (stable for any dt)."""
    return target + (value - target) * math.exp(-dt / time_constant)


def blowback(rotor_pitch: float, inflow: float, mu: float) -> float:
    """Tip-path-plane flap-back per unit advance ratio, rad (Leishman's a1s / mu, untwisted)."""
    return 2.0 * (4.0 * rotor_pitch / 3.0 - inflow) / max(0.5, 1.0 - 0.5 * mu * mu)


def flap_step(
    tilt: float, demand: float, body_rate: float, dt: float, time_constant: float
) -> float:
    """Advance one tip-path-plane tilt (relative to the shaft) by dt.

    The disc keeps its orientation in inertial space (gyroscope) and relaxes towards the cyclic
    demand with the stabiliser-bar time constant: ``d tilt/dt = body_rate + (demand - tilt)/tau``.
    Pass ``+q`` for the longitudinal (forward-positive) tilt and ``-p`` for the lateral
    (right-positive) tilt.
    """
    target = demand + time_constant * body_rate
    return lag(tilt, target, dt, time_constant)


def momentum_hover_power(thrust: float, rho: float, area: float) -> float:
    """Ideal (momentum-theory) hover power T^1.5 / sqrt(2 rho A), W."""
    return math.pow(thrust, 1.5) / math.sqrt(2.0 * rho * area)


def hover_collective(rotor: RotorParams, ct: float) -> float:
    """Closed-form blade-element/momentum hover collective for a given C_T, rad."""
    inflow = math.sqrt(ct / 2.0)
    return 3.0 * (
        2.0 * ct / (rotor.solidity * rotor.lift_slope) - 0.25 * rotor.twist + 0.5 * inflow
    )


def figure_of_merit(rotor: RotorParams, ct: float) -> float:
    """Hover figure of merit of the model: ideal power over model power at this C_T."""
    ideal = math.pow(ct, 1.5) / math.sqrt(2.0)
    profile = rotor.solidity * rotor.profile_drag / 8.0
    return ideal / (rotor.induced_factor * ideal + profile)
