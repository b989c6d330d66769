"""In-process closed loop: the PFC kernel flying an aircraft of ``sim.world_sim`` (tests, bench).

The same lockstep as the ROS nodes without DDS: every tick the kernel reads the sensor samples
the world produced, answers with one YACS command, and the world advances 20 ms. A DRC endpoint
on a :class:`~hdrc3_hcsm.transport.LoopbackNetwork` sends command events and collects the PFC's
replies, as the Platform Server does over the HCSM ROS transport.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import AttitudeCommand, VerticalMode
from hdrc3_control.event_codec import command_id_of, decode, encode
from hdrc3_control.event_protocol import FINAL, ID_ONLY, WITH_REASON
from hdrc3_control.kernel import PfcKernel, TickResult, load_model
from hdrc3_control.kernel_config import KernelConfig
from hdrc3_control.landing import landing_sites
from hdrc3_control.measurements import (
    AttitudeMeasurement,
    BaroMeasurement,
    GpsMeasurement,
    GroundContactMeasurement,
    ImuMeasurement,
)
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.pfc_state import PlatformStatus, PowerReading
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.trace import TraceRecorder
from hdrc3_hcsm.transport import LoopbackNetwork, LoopbackTransport
from sim import checkpoint as world_checkpoint
from sim.aircraft import Aircraft
from sim.rc_transmitter import FlightModeSwitch, RcSticks
from sim.sensors.suite import SensorReadings
from sim.wind import WindSettings
from sim.world_loader import load_world
from sim.world_sim import SimConfig, WorldSim
from sim.yacs import VerticalMode as YacsVerticalMode
from sim.yacs import YacsCommand

REPLIES = ID_ONLY | WITH_REASON
"""The PFC's replies about a command (they carry its id)."""
CHECKPOINT_TICKS = 25
"""world_sim's default checkpoint period (0.5 s of sim time)."""


def event_id(name: str) -> int:
    """Id of the PFC event ``name``, from the shipped PFC model (docs/realtime_events.md)."""
    return load_model().events.id_of(name)


def to_yacs(cmd: AttitudeCommand) -> YacsCommand:
    """The kernel's command on the sim's YACS interface."""
    mode = (
        YacsVerticalMode.COLLECTIVE
        if cmd.vertical_mode is VerticalMode.COLLECTIVE
        else YacsVerticalMode.VERTICAL_RATE
    )
    return YacsCommand(cmd.roll, cmd.pitch, cmd.yaw_rate, cmd.vertical, mode, cmd.engine_off)


def segment_payload(command_id: int, seg: PathSegment) -> bytes:
    """A Traj3D-EV payload for ``seg``."""
    values = (
        *seg.start,
        *seg.end,
        *seg.start_direction,
        *seg.end_direction,
        seg.target_velocity,
        seg.end_velocity,
    )
    return encode(command_id, values)


def feed_readings(kernel: PfcKernel, readings: list[SensorReadings], origin_alt: float) -> None:
    """Sensor samples of one tick into the kernel (what the node does with the ROS messages)."""
    for r in readings:
        if r.imu is not None:
            kernel.feed(ImuMeasurement(r.imu.time, r.imu.specific_force, r.imu.angular_rate))
        if r.attitude is not None:
            a = r.attitude
            kernel.feed(AttitudeMeasurement(a.time, a.roll, a.pitch, a.heading))
        if r.gps is not None:
            kernel.feed(GpsMeasurement(r.gps.time, r.gps.position_enu, r.gps.velocity_enu))
        if r.barometer is not None:
            kernel.feed(BaroMeasurement(r.barometer.time, r.barometer.altitude - origin_alt))
        if r.ground_contact is not None:
            g = r.ground_contact
            kernel.feed(GroundContactMeasurement(g.time, g.on_ground, 0.0))
        if r.rpm is not None:
            kernel.feed_rpm(r.rpm.rpm)
        if r.power is not None:
            kernel.feed_power(PowerReading(r.power.time, r.power.status))


class KernelFlight:
    """One aircraft of the Revinge world flown by a :class:`PfcKernel`, with a DRC endpoint."""

    def __init__(
        self,
        config: KernelConfig | None = None,
        seed: int = 3,
        agent: str = "uav0",
        payload: float = 0.0,
        wind: WindSettings | None = None,
        world: str = "revinge",
    ) -> None:
        self.world = load_world(world)
        settings = wind or WindSettings()
        self.sim = WorldSim(SimConfig(self.world, (agent,), seed, settings, payload=payload))
        self.agent = agent
        self.network = LoopbackNetwork()
        self.drc: LoopbackTransport = self.network.endpoint("DRC")
        self.trace = TraceRecorder(capacity=200_000)
        self.kernel = PfcKernel(
            config,
            terrain=self.world.terrain.height,
            landing_sites=landing_sites(self.world.pads, self.world.terrain.height),
            transport=self.network.endpoint("PFC"),
            trace=self.trace,
            start_time=self.sim.time,
        )
        self.replies: list[WireEvent] = []
        self.results: list[TickResult] = []
        self.readings: list[SensorReadings] = []
        """The sensor samples the last tick fed the kernel (the payload's too)."""
        self._ids = itertools.count(1)

    @property
    def aircraft(self) -> Aircraft:
        """The simulated aircraft."""
        return self.sim.agents[self.agent].aircraft

    def tick(self) -> TickResult:
        """One lockstep tick: readings -> kernel -> command -> world advances."""
        sim = self.sim
        self.readings = sim.take_readings()[self.agent]
        feed_readings(self.kernel, self.readings, self.world.origin.altitude)
        st = sim.status(self.agent)
        self.kernel.feed_status(
            PlatformStatus(
                sim.time,
                st.mode is FlightModeSwitch.AUTONOMOUS,
                st.rc_link_ok,
                st.engine_running,
                st.rotor_rpm,
            )
        )
        result = self.kernel.tick(sim.time)
        self.results.append(result)
        sim.command(self.agent, to_yacs(result.command))
        sim.advance()
        self.replies += self.drc.receive()
        return result

    def checkpoint(self) -> bytes:
        """The world's checkpoint now (what world_sim writes every ``checkpoint_period``)."""
        run = world_checkpoint.RunState("harness")
        return world_checkpoint.encode(self.sim, run, CHECKPOINT_TICKS)

    def resume(self, checkpoint: bytes) -> None:
        """A restarted simulator: a new world resumes ``checkpoint``, as world_sim does.

        Its clock moves on by the checkpoint period after the checkpoint's tick (sim time never
        goes back, ``sim/WORLD_SIM.md``); the aircraft continue from the checkpoint's state.
        """
        sim = WorldSim(self.sim.config)
        state = world_checkpoint.decode(checkpoint, sim).state
        if state is None:
            raise ConfigError("the checkpoint cannot be resumed")
        sim.resume(state.tick, state.agents, state.wind, state.objects, state.period_ticks)
        self.sim = sim

    def run(self, seconds: float) -> None:
        """Tick for ``seconds`` of sim time."""
        for _ in range(round(seconds / 0.02)):
            self.tick()

    def run_until(self, done: Callable[[], bool], timeout: float) -> bool:
        """Tick until ``done()`` or ``timeout`` s of sim time; True if done."""
        for _ in range(round(timeout / 0.02)):
            if done():
                return True
            self.tick()
        return done()

    def send(self, name: str, values: tuple[float, ...] = (), data: bytes | None = None) -> int:
        """Send a DRC command event; returns its command id."""
        cid = next(self._ids)
        payload = encode(cid, values) if data is None else data
        self.drc.send(WireEvent(event_id(name), name, payload, "DRC", "PFC"))
        return command_id_of(payload)

    def send_segment(self, seg: PathSegment) -> int:
        """Send one Traj3D-EV segment."""
        cid = next(self._ids)
        payload = segment_payload(cid, seg)
        self.drc.send(WireEvent(event_id("Traj3D-EV"), "Traj3D-EV", payload, "DRC", "PFC"))
        return cid

    def answers(self, command_id: int) -> list[tuple[str, str]]:
        """(event, reason) of every reply about command ``command_id``, in order."""
        return [
            (e.name, decode(e.data, 0, with_reason=True).reason)
            for e in self.replies
            if e.name in REPLIES and command_id_of(e.data) == command_id
        ]

    def finished(self, command_id: int) -> bool:
        """True once command ``command_id`` got its final reply."""
        return any(name in FINAL for name, _ in self.answers(command_id))

    def reply(self, name: str, command_id: int | None = None) -> WireEvent | None:
        """First reply named ``name`` (for ``command_id`` if given)."""
        for e in self.replies:
            if e.name == name and (command_id is None or command_id_of(e.data) == command_id):
                return e
        return None

    def engine_on(self, autonomous: bool) -> None:
        """Safety pilot: engine on and the mode switch."""
        rc = self.aircraft.rc
        rc.set_engine(True)
        rc.set_mode(FlightModeSwitch.AUTONOMOUS if autonomous else FlightModeSwitch.MANUAL)

    def set_mode(self, autonomous: bool) -> None:
        """Safety pilot: flip the mode switch."""
        mode = FlightModeSwitch.AUTONOMOUS if autonomous else FlightModeSwitch.MANUAL
        self.aircraft.rc.set_mode(mode)

    def sticks(self, throttle: float, pitch: float = 0.0) -> None:
        """Safety pilot: stick positions."""
        self.aircraft.rc.set_sticks(RcSticks(pitch=pitch, throttle=throttle))
