"""Engine, governor, fuel and rotor-speed dynamics of the RMAX drive train."""

from __future__ import annotations

from sim.rmax_params import RmaxParams


class Powertrain:
    """Two-stroke engine with an rpm governor driving the main and tail rotors.

    The rotor speed obeys ``J dOmega/dt = eta Q_engine - Q_rotors - Q_friction``; the governor is a
    PI loop on rotor speed whose set point ramps from 0 to the governed speed over
    ``spinup_time`` after the engine starts (soft start). Engine torque is limited to the rated
    torque, so available power falls with rotor droop: an overloaded rotor slows down and loses
    thrust instead of producing power the engine does not have.
    """

    def __init__(self, params: RmaxParams, fuel: float) -> None:
        """Create a stopped drive train with ``fuel`` kg in the tank."""
        self._p = params
        self._omega_rated = params.omega
        self._max_torque = params.max_engine_torque
        self.omega = 0.0
        """Main rotor speed, rad/s."""
        self.fuel = fuel
        """Fuel left, kg."""
        self.running = False
        """True while the engine runs."""
        self.setpoint = 0.0
        """Governor rotor-speed set point, rad/s."""
        self.throttle = 0.0
        """Throttle in [0, 1]."""
        self.engine_power = 0.0
        """Engine shaft power, W."""
        self._integral = 0.0

    def step(self, dt: float, engine_switch_on: bool, rotor_torque: float) -> None:
        """Advance by dt.

        Args:
            dt: Time step, s.
            engine_switch_on: The RC engine switch (on = run / start, off = stop).
            rotor_torque: Aerodynamic torque of both rotors referred to the main shaft, N m
                (negative when the air drives the rotor).

        """
        p = self._p
        self.running = engine_switch_on and self.fuel > 0.0
        if self.running:
            self.setpoint = min(
                self._omega_rated, self.setpoint + dt * self._omega_rated / p.spinup_time
            )
            error = self.setpoint - self.omega
            command = p.governor_kp * error + self._integral
            saturated_high = command >= 1.0 and error > 0.0
            saturated_low = command <= 0.0 and error < 0.0
            if not (saturated_high or saturated_low):
                # conditional integration: no wind-up while the throttle is at a stop
                self._integral += p.governor_ki * error * dt
            self._integral = max(0.0, min(1.0, self._integral))
            self.throttle = max(0.0, min(1.0, command))
        else:
            self.setpoint = 0.0
            self._integral = 0.0
            self.throttle = 0.0
        engine_torque = self.throttle * self._max_torque
        self.engine_power = engine_torque * self.omega
        friction = p.drag_torque if self.omega > 0.0 else 0.0
        accel = (
            p.transmission_efficiency * engine_torque - rotor_torque - friction
        ) / p.rotor_inertia
        self.omega = max(0.0, self.omega + accel * dt)
        if self.running:
            self.fuel = max(0.0, self.fuel - p.bsfc * self.engine_power / 3.6e6 * dt)
