"""Every physical parameter of the simulated Yamaha RMAX, with where each number comes from.

Source keys used in the field notes below:

- [seed] the HDRC3 chapter §4.1: empty weight 61 kg, max take-off weight 95 kg, 21 HP two-stroke,
  about 2.7 x 0.7 m, 3.6 m long with rotor.
- [issue] the hdrc3 issue text: rotor diameter 3.115 m, 2 blades, ~850 rpm governed main rotor.
- [spec] Yamaha's public RMAX data: tail rotor diameter 0.545 m, fuselage width 0.72 m, height
  1.08 m, 6 l fuel tank.
- [text] textbook helicopter values (Leishman, *Principles of Helicopter Aerodynamics*; Padfield,
  *Helicopter Flight Dynamics*): lift-curve slope, profile drag, induced-power factor, Pitt-Peters
  inflow time constant, Cheeseman-Bennett ground effect.
- [est] our engineering estimate, chosen to be plausible for a 60-95 kg single-rotor helicopter with
  a stabiliser bar; not measured on an RMAX. Change them here only.

The table in ``sim/RMAX_MODEL.md`` lists the same numbers with their derived values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from hdrc3_base.errors import ConfigError

RPM_TO_RAD_S = 2.0 * math.pi / 60.0


@dataclass(frozen=True, slots=True)
class RotorParams:
    """Geometry and aerodynamics of one rotor (uniform-inflow blade-element model)."""

    radius: float
    """Blade tip radius, m."""
    blades: int
    """Number of blades."""
    chord: float
    """Blade chord, m (rectangular blade)."""
    lift_slope: float = 5.7
    """Section lift-curve slope a, 1/rad [text]."""
    profile_drag: float = 0.010
    """Mean profile drag coefficient Cd0 [text]."""
    induced_factor: float = 1.15
    """Induced-power factor kappa (non-uniform inflow, tip losses) [text]."""
    twist: float = 0.0
    """Linear blade twist, rad (tip minus root) [est: untwisted]."""
    max_ct_sigma: float = 0.14
    """Blade-loading limit C_T/sigma where the blades stall [text]."""

    @property
    def disc_area(self) -> float:
        """Rotor disc area, m^2."""
        return math.pi * self.radius * self.radius

    @property
    def solidity(self) -> float:
        """Rotor solidity sigma = b c / (pi R)."""
        return self.blades * self.chord / (math.pi * self.radius)


@dataclass(frozen=True, slots=True)
class RmaxParams:
    """The complete parameter set of the simulated RMAX (SI units, radians)."""

    # --- masses [seed] and configurable loading
    empty_mass: float = 61.0
    """Empty mass, kg [seed]."""
    max_takeoff_mass: float = 95.0
    """Certified maximum take-off mass, kg [seed] (not enforced: overweight simply cannot fly)."""
    fuel_capacity: float = 4.4
    """Fuel tank capacity, kg: 6 l [spec] of two-stroke mix at 0.74 kg/l."""
    inertia: tuple[float, float, float] = (8.0, 24.0, 20.0)
    """Ixx, Iyy, Izz of the empty aircraft about its CG, kg m^2 [est: slender-body sums]."""

    # --- rotors
    main_rotor: RotorParams = field(
        default_factory=lambda: RotorParams(radius=1.5575, blades=2, chord=0.17)
    )
    """Main rotor: radius, blades [issue]; chord [est] (gives C_T/sigma = 0.075 at 95 kg)."""
    tail_rotor: RotorParams = field(
        default_factory=lambda: RotorParams(radius=0.2725, blades=2, chord=0.055)
    )
    """Tail rotor: radius [spec], blades [spec], chord [est]."""
    rotor_rpm: float = 850.0
    """Governed main rotor speed, rpm [issue]."""
    tail_gear_ratio: float = 5.3
    """Tail/main rotor speed ratio [est: similar tip speeds, ~130 m/s]."""
    main_rotor_ccw: bool = True
    """Main rotor turns counter-clockwise seen from above [est]; torque yaws the nose right."""

    # --- geometry relative to the CG (body FRD, m)
    hub_height: float = 0.55
    """Main rotor hub above the CG, m [est: 1.08 m overall height [spec]]."""
    tail_arm: float = 1.88
    """Tail rotor hub behind the CG, m [est: R + r_tail + 0.05 m clearance]."""
    tail_height: float = 0.30
    """Tail rotor hub above the CG, m [est]."""
    fin_arm: float = 1.6
    """Vertical fin centre of pressure behind the CG, m [est]."""
    skid_height: float = 0.45
    """CG above the skid bottoms on the ground, m [est]; must equal the XML CG z."""

    # --- control ranges (blade pitch, rad) [est]
    collective_min: float = math.radians(-2.0)
    """Main rotor collective at stick bottom, rad [est]."""
    collective_max: float = math.radians(12.0)
    """Main rotor collective at stick top, rad [est]."""
    cyclic_max: float = math.radians(8.0)
    """Tip-path-plane tilt demanded by full cyclic, rad [est]."""
    tail_pitch_min: float = math.radians(-10.0)
    """Tail rotor pitch at full left pedal, rad [est]."""
    tail_pitch_max: float = math.radians(25.0)
    """Tail rotor pitch at full right pedal, rad [est]."""

    # --- rotor dynamics
    flap_time_constant: float = 0.12
    """Tip-path-plane (rotor + stabiliser bar) lag, s [est: flybar rotors 0.1-0.35 s]."""
    hub_stiffness: float = 120.0
    """Effective hub spring of the teetering rotor, N m/rad [est]."""
    blowback_gain: float = 1.0
    """Scale on the textbook flap-back with advance ratio [text; est scale]."""
    min_inflow_time_constant: float = 0.02
    """Floor on the Pitt-Peters inflow time constant, s (numerical, >= 4 FDM steps)."""

    # --- powertrain
    engine_power: float = 15.66
    """Maximum engine shaft power, kW: 21 HP [seed]."""
    transmission_efficiency: float = 0.90
    """Power reaching the rotors / engine power [est]."""
    rotor_inertia: float = 4.0
    """Polar inertia of rotor, bar and drive train about the main shaft, kg m^2 [est]."""
    spinup_time: float = 10.0
    """Governor ramps the rpm set point from 0 to governed speed in this time, s [est]."""
    governor_kp: float = 0.08
    """Governor proportional gain, throttle per (rad/s) of rotor-speed error [est]."""
    governor_ki: float = 0.15
    """Governor integral gain, throttle per (rad/s * s) [est]."""
    drag_torque: float = 3.0
    """Drive-train friction torque when the rotor turns, N m [est]."""
    bsfc: float = 0.5
    """Brake specific fuel consumption, kg/kWh [est: two-stroke] (about 1 h endurance)."""

    # --- fuselage flat-plate drag areas (CdA), m^2 [est]
    drag_area_x: float = 0.45
    """Frontal CdA, m^2 [est]."""
    drag_area_y: float = 1.2
    """Side CdA of the fuselage, m^2 [est]."""
    drag_area_z: float = 1.0
    """Vertical CdA of the fuselage, m^2 [est]."""
    fin_area: float = 0.12
    """Vertical fin CdA acting at ``fin_arm`` (weathercock and yaw damping), m^2 [est]."""

    def __post_init__(self) -> None:
        """Reject parameter sets that cannot describe a flying helicopter."""
        positives = {
            "empty_mass": self.empty_mass,
            "rotor_rpm": self.rotor_rpm,
            "flap_time_constant": self.flap_time_constant,
            "engine_power": self.engine_power,
            "rotor_inertia": self.rotor_inertia,
            "spinup_time": self.spinup_time,
        }
        for name, value in positives.items():
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"RMAX parameter {name} must be positive, got {value}")
        if not self.collective_min < self.collective_max:
            raise ConfigError("collective_min must be below collective_max")
        if not 0.0 < self.transmission_efficiency <= 1.0:
            raise ConfigError("transmission_efficiency must be in (0, 1]")

    @property
    def omega(self) -> float:
        """Governed main rotor speed, rad/s."""
        return self.rotor_rpm * RPM_TO_RAD_S

    @property
    def max_engine_torque(self) -> float:
        """Engine torque referred to the main shaft, N m (constant-torque engine at rated rpm)."""
        return self.engine_power * 1000.0 / self.omega
