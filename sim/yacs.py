"""Emulation of the Yamaha Attitude Control System (YACS): the RMAX's own 200 Hz inner loop.

The flight computer (control kernel, 50 Hz) talks to the helicopter through YACS commands: roll
and pitch attitude, yaw rate, and either a vertical rate or a direct collective (§4.2, §5.3). With
the RC mode switch at MANUAL the safety pilot's sticks are the command source instead; a lost RC
link in manual mode makes YACS level the aircraft and descend slowly.

Control law per axis (roll shown; pitch alike, all gains in ``YacsGains``)::

    p_cmd = k_att * (phi_cmd - phi)                 (clipped to max_rate)
    tilt  = tau_f * p_cmd + k_rate * (p_cmd - p) + integral
    servo = tilt / cyclic_max

``tau_f * p_cmd`` is the disc tilt that sustains the commanded rate against the rotor's flap lag;
the rate term damps the rotor-fuselage mode; the integral (only in the air) trims out tail-rotor
side force, CG offsets and wind. Gains were tuned on this flight model for about 0.35-0.5 s rise
time and < 15 % overshoot to a 10 degree attitude step.

The measurements (``YacsInput``) come from the aircraft's sensors through the YAS front end
(:mod:`sim.yas`): filtered, noisy, biased and faulty like the sensors. While the attitude sensor
is lost (``attitude_ok`` False) the loops fly the gyro-coasted attitude with the roll/pitch
integrators frozen, since that estimate drifts with the gyro bias and integrating its error
would walk the trim away; the servos stay on the trim they had.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from sim.flight_model import ServoCommand
from sim.rc_transmitter import FlightModeSwitch, RcState
from sim.rmax_params import RmaxParams


class VerticalMode(enum.Enum):
    """How ``YacsCommand.vertical`` is interpreted."""

    VERTICAL_RATE = "vertical_rate"
    """m/s, climb positive; YACS closes the loop on the collective."""
    COLLECTIVE = "collective"
    """Normalised collective 0 .. 1, passed straight to the servo."""


@dataclass(frozen=True, slots=True)
class YacsCommand:
    """One command of the flight computer to the YACS."""

    roll: float = 0.0
    """Roll attitude, rad, right positive."""
    pitch: float = 0.0
    """Pitch attitude, rad, nose up positive."""
    yaw_rate: float = 0.0
    """Yaw rate, rad/s, nose right positive."""
    vertical: float = 0.0
    """Vertical rate (m/s, up) or collective (0 .. 1), see ``vertical_mode``."""
    vertical_mode: VerticalMode = VerticalMode.VERTICAL_RATE
    engine_off: bool = False
    """Stop the engine (honoured only while the computer has authority: autonomous mode)."""

    def __post_init__(self) -> None:
        """Reject non-finite values and collectives outside the servo travel."""
        values = (self.roll, self.pitch, self.yaw_rate, self.vertical)
        if not all(math.isfinite(v) for v in values):
            raise ConfigError(f"YACS command must be finite, got {values}")
        if self.vertical_mode is VerticalMode.COLLECTIVE and not 0.0 <= self.vertical <= 1.0:
            raise ConfigError(f"collective {self.vertical} outside [0, 1]")


class CommandSource(enum.Enum):
    """Where the YACS took its command from in the last step."""

    COMPUTER = "computer"
    PILOT = "pilot"
    FAILSAFE = "failsafe"


@dataclass(frozen=True, slots=True)
class YacsGains:
    """Inner-loop gains and limits (tuned on the simulated RMAX; see tests/unit/sim)."""

    k_att: float = 4.0
    """Attitude error -> rate command, 1/s."""
    max_rate: float = 1.2
    """Roll/pitch rate command limit, rad/s."""
    max_attitude: float = math.radians(30.0)
    """Roll/pitch command limit, rad."""
    k_rate: float = 0.5
    """Roll/pitch rate error -> disc tilt, s."""
    k_int: float = 0.3
    """Attitude error integral -> disc tilt, 1/s."""
    k_yaw: float = 0.6
    """Yaw-rate error -> pedal, per rad/s."""
    k_yaw_int: float = 1.5
    """Yaw-rate error integral -> pedal, per rad."""
    max_yaw_rate: float = 1.5
    """Yaw-rate command limit, rad/s."""
    k_vz: float = 0.08
    """Vertical-rate error -> collective, per m/s."""
    k_vz_int: float = 0.08
    """Vertical-rate error integral -> collective, per m."""
    collective_start: float = 0.35
    """Collective integrator start value on the ground (below lift-off), 0 .. 1."""
    max_climb: float = 3.0
    """Vertical-rate command limit, m/s."""
    pilot_attitude: float = math.radians(20.0)
    """Attitude at full manual stick, rad."""
    pilot_yaw_rate: float = 1.0
    """Yaw rate at full manual stick, rad/s."""
    failsafe_descent: float = 0.5
    """Descent rate in the lost-link failsafe, m/s."""


@dataclass(frozen=True, slots=True)
class YacsInput:
    """The attitude-sensor (YAS) measurements the YACS works on."""

    roll: float
    pitch: float
    p: float
    q: float
    r: float
    climb_rate: float
    """m/s, up positive."""
    on_ground: bool
    attitude_ok: bool = True
    """False while the attitude sensor is lost and roll/pitch are coasted on the gyros."""


def _clip(value: float, limit: float) -> float:
    return -limit if value < -limit else limit if value > limit else value


class Yacs:
    """The inner-loop controller; call ``step`` once per 200 Hz tick."""

    def __init__(self, params: RmaxParams, dt: float, gains: YacsGains | None = None) -> None:
        """Create the controller for an aircraft with ``params`` stepped every ``dt`` s."""
        self._p = params
        self._g = gains or YacsGains()
        self._dt = dt
        self._command = YacsCommand()
        self.source = CommandSource.PILOT
        """Command source of the last step."""
        self.reset()

    def reset(self) -> None:
        """Forget integrators and filter states."""
        self._int_roll = 0.0
        self._int_pitch = 0.0
        self._int_yaw = 0.0
        self._int_vz = self._g.collective_start

    def command(self, cmd: YacsCommand) -> None:
        """Latch the flight computer's command (used while the RC switch is AUTONOMOUS)."""
        self._command = cmd

    def _select(self, rc: RcState) -> YacsCommand:
        g = self._g
        if rc.mode is FlightModeSwitch.AUTONOMOUS:
            self.source = CommandSource.COMPUTER
            return self._command
        if not rc.link_ok:
            self.source = CommandSource.FAILSAFE
            return YacsCommand(vertical=-g.failsafe_descent)
        self.source = CommandSource.PILOT
        s = rc.sticks
        return YacsCommand(
            roll=s.roll * g.pilot_attitude,
            pitch=-s.pitch * g.pilot_attitude,
            yaw_rate=s.yaw * g.pilot_yaw_rate,
            vertical=s.throttle,
            vertical_mode=VerticalMode.COLLECTIVE,
        )

    def step(self, rc: RcState, meas: YacsInput) -> ServoCommand:
        """One 200 Hz control step: measurements in, servo positions out."""
        g = self._g
        p = self._p
        dt = self._dt
        cmd = self._select(rc)
        tau = p.flap_time_constant
        cyc = p.cyclic_max
        airborne = not meas.on_ground

        # roll / pitch attitude loops; disc tilt forward = nose down = negative pitch
        roll_err = _clip(cmd.roll, g.max_attitude) - meas.roll
        pitch_err = _clip(cmd.pitch, g.max_attitude) - meas.pitch
        p_cmd = _clip(g.k_att * roll_err, g.max_rate)
        q_cmd = _clip(g.k_att * pitch_err, g.max_rate)
        if airborne and meas.attitude_ok:
            self._int_roll = _clip(self._int_roll + g.k_int * roll_err * dt, cyc)
            self._int_pitch = _clip(self._int_pitch + g.k_int * pitch_err * dt, cyc)
        elif not airborne:
            self._int_roll = self._int_pitch = 0.0
        lat = tau * p_cmd + g.k_rate * (p_cmd - meas.p) + self._int_roll
        lon = -(tau * q_cmd + g.k_rate * (q_cmd - meas.q) + self._int_pitch)

        # vertical: rate loop on the collective, integrator runs in the air or when climbing out
        if cmd.vertical_mode is VerticalMode.COLLECTIVE:
            collective = cmd.vertical
            self._int_vz = cmd.vertical
            flying = airborne
        else:
            vz_cmd = _clip(cmd.vertical, g.max_climb)
            vz_err = vz_cmd - meas.climb_rate
            flying = airborne or vz_cmd > 0.0
            if flying:
                self._int_vz = min(1.0, max(0.0, self._int_vz + g.k_vz_int * vz_err * dt))
                collective = self._int_vz + g.k_vz * vz_err
            else:
                self._int_vz = g.collective_start
                collective = 0.0
        collective = min(1.0, max(0.0, collective))

        # yaw-rate loop (the RMAX's rate gyro)
        r_err = _clip(cmd.yaw_rate, g.max_yaw_rate) - meas.r
        if flying:
            self._int_yaw = _clip(self._int_yaw + g.k_yaw_int * r_err * dt, 1.0)
        pedal = g.k_yaw * r_err + self._int_yaw
        return ServoCommand(
            collective=collective,
            longitudinal=_clip(lon / cyc, 1.0),
            lateral=_clip(lat / cyc, 1.0),
            pedal=_clip(pedal, 1.0),
        )
