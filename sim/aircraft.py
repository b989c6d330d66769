"""One simulated RMAX: flight model + YACS inner loop + the safety pilot's RC transmitter.

With a ``SensorSuite`` the YACS flies on those sensors (through the YAS front end,
:mod:`sim.yas`), the same samples the rest of the simulation publishes. Without one it reads the
true state: ideal sensors, for studies of the airframe and the inner loop alone (the flight-model
unit tests and ``bench/rmax_performance.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from sim.flight_model import FlightModel, InitialPlacement, TerrainHeight, flat_terrain
from sim.rc_transmitter import FlightModeSwitch, RcTransmitter
from sim.rmax_params import RmaxParams
from sim.sensors.suite import SensorReadings, SensorSuite
from sim.truth_state import TruthState
from sim.yacs import CommandSource, Yacs, YacsCommand, YacsGains, YacsInput
from sim.yas import Yas


@dataclass(frozen=True, slots=True)
class YacsStatus:
    """What the flight computer can read from the YACS/RC side (input to the Auto Switch)."""

    mode: FlightModeSwitch
    """RC mode switch position."""
    rc_link_ok: bool
    """True while the RC transmitter's signal is received."""
    engine_running: bool
    rotor_rpm: float
    source: CommandSource
    """Command source the YACS used in the last step."""
    attitude_ok: bool = True
    """False while the YACS's attitude sensor is lost (roll/pitch coasted on the gyros)."""


class Aircraft:
    """One ``FlightModel``, ``Yacs`` and ``RcTransmitter``; ``step()`` is one 200 Hz tick.

    Typical use::

        ac = Aircraft(placement=InitialPlacement(east=10.0, heading=1.57))
        ac.rc.set_engine(True)
        ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
        ac.command(YacsCommand(vertical=1.0))   # climb at 1 m/s
        for _ in range(200):
            ac.step()
        state = ac.truth()
    """

    def __init__(
        self,
        params: RmaxParams | None = None,
        *,
        placement: InitialPlacement | None = None,
        origin: tuple[float, float, float] = (58.4, 15.6, 0.0),
        terrain_height: TerrainHeight = flat_terrain,
        fuel: float | None = None,
        payload: float = 0.0,
        rate_hz: float = 200.0,
        gains: YacsGains | None = None,
        sensors: SensorSuite | None = None,
    ) -> None:
        """Build the aircraft on the ground, engine off, RC in manual mode (see ``FlightModel``).

        ``sensors``: the aircraft's sensor suite, read after every step and flown on by the YACS
        (None: the YACS reads the true state).
        """
        self.model = FlightModel(
            params,
            placement=placement,
            origin=origin,
            terrain_height=terrain_height,
            fuel=fuel,
            payload=payload,
            rate_hz=rate_hz,
        )
        self.yacs = Yacs(self.model.params, self.model.dt, gains)
        self.sensors = sensors
        self.yas = Yas()
        """The YACS's view of ``sensors`` (unused without them)."""
        self.rc = RcTransmitter()
        self._engine_cut = False
        self._cut_requested = False

    def command(self, cmd: YacsCommand) -> None:
        """Send a flight-computer command to the YACS (effective in AUTONOMOUS mode)."""
        self.yacs.command(cmd)
        self._cut_requested = cmd.engine_off

    def restart_engine(self) -> None:
        """The pilot's engine-on: clears a computer engine cut (the switch may already be on)."""
        self._engine_cut = False
        self._cut_requested = False

    def step(self) -> SensorReadings | None:
        """One tick: YACS reads its sensors and the RC, the flight model moves, sensors are read.

        Returns the samples that came due at the new time (None without a sensor suite).
        """
        m = self.model
        rc = self.rc.state
        m.set_servos(self.yacs.step(rc, self._measure()))
        if self._cut_requested and rc.mode is FlightModeSwitch.AUTONOMOUS:
            self._engine_cut = True  # the computer's kill stays until the pilot restarts
        m.engine_switch = rc.engine_on and not self._engine_cut
        m.step()
        return None if self.sensors is None else self.read_sensors(m.dt)

    def read_sensors(self, dt: float) -> SensorReadings:
        """Step the sensor suite by ``dt`` at the current truth; the YAS takes the samples too.

        ConfigError without a sensor suite.
        """
        if self.sensors is None:
            raise ConfigError("this aircraft has no sensor suite")
        readings = self.sensors.step(self.truth(), dt)
        self.yas.observe(readings)
        return readings

    def _measure(self) -> YacsInput:
        if self.sensors is not None:
            return self.yas.measurement()
        m = self.model
        return YacsInput(
            roll=m.roll,
            pitch=m.pitch,
            p=m.p,
            q=m.q,
            r=m.r,
            climb_rate=m.velocity_enu[2],
            on_ground=m.on_ground,
        )

    def run(self, seconds: float) -> None:
        """Step for ``seconds`` of simulated time (rounded to whole steps)."""
        for _ in range(round(seconds / self.model.dt)):
            self.step()

    def shift_time(self, steps: int) -> None:
        """Move the aircraft's clock on by ``steps`` without moving anything else.

        The flight model's step count and every time the YAS and the sensors remember move
        together, so the next step behaves as if no time had passed (a checkpoint resumed later).
        """
        m = self.model
        m.steps += steps
        seconds = steps * m.dt
        self.yas.shift_time(seconds)
        if self.sensors is not None:
            self.sensors.shift_time(seconds)

    def truth(self) -> TruthState:
        """Exact state now."""
        return self.model.truth()

    def status(self) -> YacsStatus:
        """RC/YACS status for the flight computer."""
        rc = self.rc.state
        return YacsStatus(
            mode=rc.mode,
            rc_link_ok=rc.link_ok,
            engine_running=self.model.powertrain.running,
            rotor_rpm=self.model.powertrain.omega * 60.0 / 6.283185307179586,
            source=self.yacs.source,
            attitude_ok=self.sensors is None or self.yas.attitude_ok,
        )
