"""Pure simulation core of the world_sim node: N aircraft in one world, ticked at 50 Hz.

One *tick* is one control period of 20 ms (the control kernel's 50 Hz, chapter section 5.2):
the latest YACS command of every agent is applied, then every aircraft takes four 200 Hz flight
model steps and its sensors are read after each step. Everything random derives from one seed,
nothing reads a wall clock, so the same seed and the same commands give the same trajectory.

Mutators here are *unchecked* (they assume valid arguments); :mod:`sim.sim_services` validates
requests and turns them into result codes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from hdrc3_base.errors import ConfigError
from sim.aircraft import Aircraft, YacsStatus
from sim.drive import DrivePlan
from sim.flight_model import InitialPlacement
from sim.hook import HookFault, HookReading
from sim.hook_camera import observe
from sim.payload import PayloadPose, PayloadWorld
from sim.sensors.power import PowerDevice
from sim.sensors.suite import SensorReadings, SensorSuite
from sim.truth_state import TruthState
from sim.wind import Wind, WindSettings
from sim.world import DynamicObject, LandingPad, World
from sim.world_geometry import WorldGeometry
from sim.yacs import YacsCommand

TICK_RATE_HZ = 50
FDM_RATE_HZ = 200
STEPS_PER_TICK = FDM_RATE_HZ // TICK_RATE_HZ
TICK_NS = 1_000_000_000 // TICK_RATE_HZ
TICK_S = 1.0 / TICK_RATE_HZ

OFF_AT_START = PowerDevice.LASER
"""Devices switched off when an agent starts: the laser scanner is a mission payload (section
11.2) and ray casting it costs ~100x the rest of the sensor suite; switch it on when needed."""


@dataclass(frozen=True, slots=True)
class SimConfig:
    """What a world_sim run is made of."""

    world: World
    agents: tuple[str, ...]
    seed: int = 0
    wind: WindSettings = field(default_factory=WindSettings)
    fuel: float | None = None
    """Fuel per aircraft, kg (None: full tank)."""
    payload: float = 0.0
    """Payload per aircraft, kg."""


class SimAgent:
    """One aircraft of the world with its sensors and start pad."""

    def __init__(self, name: str, pad: LandingPad, seed: int) -> None:
        """Bookkeeping only; :meth:`WorldSim._build` creates aircraft and sensors."""
        self.name = name
        self.pad = pad
        self.seed = seed
        self.aircraft: Aircraft
        self.sensors: SensorSuite
        self.command = YacsCommand()
        """Latest YACS command (re-applied when the aircraft is rebuilt by a teleport)."""
        self.rejected_commands = 0


EXTRA_SPACING = 10.0
"""m east of a pad per extra agent that has no pad of its own."""


def start_pads(world: World, agents: tuple[str, ...]) -> tuple[LandingPad, ...]:
    """Pads the agents start on, in order (H1, H2, ...); a pad with the landing pattern is none.

    Agents beyond the number of pads start beside a pad: agent ``i`` uses pad ``i mod n``,
    ``EXTRA_SPACING`` m further east for each round (``H1+1`` is 10 m east of H1); the spot must
    lie in the world, clear of buildings and at least ``EXTRA_SPACING`` m from every other start
    spot, else ConfigError.
    """
    if not agents:
        raise ConfigError("world_sim needs at least one agent")
    if len(set(agents)) != len(agents):
        raise ConfigError(f"agent listed twice in {', '.join(agents)}")
    starts = [pad for pad in world.pads if not pad.pattern]  # the vision pad is kept clear
    if not starts:
        raise ConfigError(f"world '{world.name}' has no start pads (pads without a pattern)")
    pads = starts[: len(agents)]
    geometry: WorldGeometry | None = None
    for i in range(len(starts), len(agents)):
        base = starts[i % len(starts)]
        rounds = i // len(starts)
        east = base.east + EXTRA_SPACING * rounds
        geometry = geometry or WorldGeometry(world)
        problem = _spot_problem(world, geometry, pads, east, base.north)
        if problem is not None:
            raise ConfigError(
                f"no start spot for agent {agents[i]}: {EXTRA_SPACING * rounds:.0f} m east of "
                f"pad {base.name} is {problem}"
            )
        pads.append(replace(base, name=f"{base.name}+{rounds}", east=east))
    return tuple(pads)


def _spot_problem(
    world: World, geometry: WorldGeometry, taken: list[LandingPad], east: float, north: float
) -> str | None:
    """Why an extra start spot is unusable, or None."""
    building = geometry.point_in_building(east, north)
    if building is not None:
        return f"inside building {building}"
    e0, n0, e1, n1 = world.bounds
    if not (e0 <= east <= e1 and n0 <= north <= n1):
        return "outside the world"
    for pad in taken:
        if math.hypot(pad.east - east, pad.north - north) < EXTRA_SPACING - 0.01:
            return f"too close to {pad.name}"
    return None


class WorldSim:
    """The aircraft, wind and dynamic objects of one world, advanced tick by tick."""

    def __init__(self, config: SimConfig) -> None:
        """Place every agent on its pad (engine off, RC manual) at sim time 0."""
        self.config = config
        self.world = config.world
        self.geometry = WorldGeometry(config.world)
        pads = start_pads(config.world, config.agents)
        seeds = np.random.SeedSequence(config.seed).spawn(len(pads) + 1)
        self._wind_seed = int(seeds[0].generate_state(1)[0])
        self.wind = Wind(self._wind_seed, config.wind)
        self.agents: dict[str, SimAgent] = {
            name: SimAgent(name, pad, int(seq.generate_state(1)[0]))
            for name, pad, seq in zip(config.agents, pads, seeds[1:], strict=True)
        }
        self.tick = 0
        self.objects: dict[str, DynamicObject] = {}
        self._drives: dict[str, DrivePlan] = {}
        """Solved drives of the driving cars (a car's pose is a function of sim time)."""
        self._readings: dict[str, list[SensorReadings]] = {}
        self.payload: PayloadWorld
        """Boxes, carriers and hooks (rebuilt by a full reset)."""
        self.reset()

    # ------------------------------------------------------------------ time
    @property
    def time_ns(self) -> int:
        """Sim time of the current tick, integer nanoseconds."""
        return self.tick * TICK_NS

    @property
    def time(self) -> float:
        """Sim time of the current tick, s."""
        return self.tick * TICK_S

    # ---------------------------------------------------------------- resets
    def reset(self, agent: str | None = None) -> None:
        """Agent (or everything) back to the start: see ``SimReset.srv`` for the semantics."""
        if agent is not None:
            self._build(self.agents[agent])
            self.payload.reset_hook(agent, self.agents[agent].aircraft.model.hook_anchor())
            return
        self.tick = 0
        self.wind.reset(self._wind_seed)
        self.wind.set(self.config.wind)
        self.objects = {o.id: o for o in self.world.objects}
        self._plan_drives()
        for sim_agent in self.agents.values():
            self._build(sim_agent)
        self.payload = PayloadWorld(
            self.world.terrain,
            list(self.world.objects),
            {name: a.aircraft.model.hook_anchor() for name, a in self.agents.items()},
        )

    def resume(
        self,
        tick: int,
        agents: dict[str, SimAgent],
        wind: Wind,
        objects: dict[str, DynamicObject],
        skip: int = 0,
        payload: PayloadWorld | None = None,
    ) -> None:
        """Take over a checkpointed world state of ``tick``, its clock moved on by ``skip`` ticks.

        Nothing moves during the skipped ticks: the world is as if paused with its clock running
        (every clock in the state moves along, driving cars depart ``skip`` ticks later), so
        that the clock of a restarted simulator never goes back behind a tick its predecessor
        may have published.
        """
        if set(agents) != set(self.agents):
            raise ConfigError(f"the state is of agents {sorted(agents)}, not {sorted(self.agents)}")
        self.tick = tick + skip
        self.agents = {name: agents[name] for name in self.agents}
        for agent in self.agents.values():
            agent.aircraft.shift_time(skip * STEPS_PER_TICK)
        self.wind = wind
        self.objects = {oid: _delayed(obj, skip * TICK_S) for oid, obj in objects.items()}
        self._plan_drives()
        if payload is not None:
            self.payload = payload
        self._readings = {name: [] for name in self.agents}

    def _plan_drives(self) -> None:
        self._drives = {
            oid: DrivePlan.of(obj.drive) for oid, obj in self.objects.items() if obj.drive
        }

    def _origin(self) -> tuple[float, float, float]:
        o = self.world.origin
        return (o.latitude, o.longitude, o.altitude)

    def _build(self, agent: SimAgent) -> None:
        pad = agent.pad
        agent.sensors = SensorSuite(self.world, agent.seed, self.geometry)
        agent.sensors.power.switch(OFF_AT_START, False)
        agent.aircraft = self._new_aircraft(
            InitialPlacement(pad.east, pad.north, pad.heading), agent.sensors
        )
        agent.rejected_commands = 0
        agent.command = YacsCommand()
        self._readings[agent.name] = [agent.aircraft.read_sensors(0.0)]

    def _new_aircraft(
        self,
        placement: InitialPlacement,
        sensors: SensorSuite,
        fuel: float | None = None,
        payload: float | None = None,
    ) -> Aircraft:
        aircraft = Aircraft(
            placement=placement,
            origin=self._origin(),
            terrain_height=self.world.terrain.height,
            fuel=self.config.fuel if fuel is None else fuel,
            payload=self.config.payload if payload is None else payload,
            rate_hz=FDM_RATE_HZ,
            sensors=sensors,
        )
        # all aircraft share the world's clock (sensors schedule on truth.time)
        aircraft.model.steps = self.tick * STEPS_PER_TICK
        wind = self.wind
        aircraft.model.set_wind(wind.mean, wind.gust)
        return aircraft

    def place(self, agent: str, east: float, north: float, height: float, heading: float) -> None:
        """Teleport: same aircraft state of engine, rotor, fuel, payload and RC; at rest, level.

        The sensors are the same (same noise streams, faults and power switches); the YACS and
        its YAS estimate start afresh (level, at rest) like the rest of the rebuilt aircraft.
        """
        old = self.agents[agent].aircraft
        new = self._new_aircraft(
            InitialPlacement(east, north, heading, height),
            self.agents[agent].sensors,
            fuel=old.model.powertrain.fuel,
            payload=old.model.payload,
        )
        new.model.powertrain = old.model.powertrain
        new.model.engine_switch = old.model.engine_switch
        new.rc = old.rc
        sim_agent = self.agents[agent]
        new.command(sim_agent.command)
        sim_agent.aircraft = new
        self.payload.reset_hook(agent, new.model.hook_anchor())

    # ---------------------------------------------------------------- inputs
    def command(self, agent: str, cmd: YacsCommand) -> None:
        """Latch ``agent``'s YACS command for the next tick."""
        sim_agent = self.agents[agent]
        sim_agent.command = cmd
        sim_agent.aircraft.command(cmd)

    def set_wind(self, settings: WindSettings) -> None:
        """Change mean wind and gust intensity (ConfigError if impossible)."""
        self.wind.set(settings)

    def spawn(self, obj: DynamicObject) -> None:
        """Add a dynamic object (unchecked; boxes and carriers come from the world file)."""
        self.objects[obj.id] = obj
        if obj.drive is not None:
            self._drives[obj.id] = DrivePlan.of(obj.drive)

    def hook_command(self, agent: str, cable_length: float, magnet: bool) -> None:
        """Winch and magnet set-point of ``agent``'s hook (unchecked)."""
        self.payload.command(agent, cable_length, magnet)

    def hook_fault(self, agent: str, fault: HookFault) -> None:
        """Inject a hook fault (unchecked)."""
        self.payload.inject(agent, fault)

    def carrying(self, agent: str) -> HookReading:
        """``agent``'s carrying sensor now."""
        return self.payload.reading(agent)

    def hook_camera(self, agent: str) -> list[tuple[str, tuple[float, float, float]]]:
        """What ``agent``'s hook camera sees now: tags and offsets from the winch (ENU m)."""
        payload = self.payload
        targets = []
        for oid, obj in payload.objects.items():
            pose = payload.pose(oid)
            if pose.held_by:
                continue
            targets.append((oid, (pose.east, pose.north, pose.up + obj.size[2])))
        winch = self.agents[agent].aircraft.model.hook_anchor()
        return observe(winch, targets, (self.agents[agent].seed, self.tick))

    def object_poses(self) -> dict[str, PayloadPose]:
        """Poses now of the objects that move: boxes and carriers (rigid bodies), driving cars."""
        poses = self.payload.poses()
        height = self.world.terrain.height
        t = self.time
        for oid, plan in self._drives.items():
            p = plan.pose(t)
            poses[oid] = PayloadPose(
                p.east, p.north, height(p.east, p.north), p.heading, "", p.speed
            )
        return poses

    # ------------------------------------------------------------------ step
    def advance(self) -> None:
        """One tick: wind, then STEPS_PER_TICK flight-model steps with sensor reads after each."""
        gust = self.wind.step(TICK_S)
        mean = self.wind.mean
        for agent in self.agents.values():
            agent.aircraft.model.set_wind(mean, gust)
        payload = self.payload
        dt = 1.0 / FDM_RATE_HZ
        for _ in range(STEPS_PER_TICK):
            anchors = {}
            for agent in self.agents.values():
                aircraft = agent.aircraft
                readings = aircraft.step()
                if readings is not None:  # every world_sim aircraft has its suite
                    self._readings[agent.name].append(readings)
                anchors[agent.name] = aircraft.model.hook_anchor()
            payload.step(dt, anchors)
            for agent in self.agents.values():
                agent.aircraft.model.set_hook_force(payload.cable_force(agent.name))
        self.tick += 1

    def take_readings(self) -> dict[str, list[SensorReadings]]:
        """Sensor readings since the last call, per agent, in time order (then forgotten)."""
        taken = self._readings
        self._readings = {name: [] for name in self.agents}
        return taken

    # ---------------------------------------------------------------- output
    def truth(self, agent: str) -> TruthState:
        """Ground truth of ``agent`` now."""
        return self.agents[agent].aircraft.truth()

    def status(self, agent: str) -> YacsStatus:
        """YACS/RC status of ``agent`` now."""
        return self.agents[agent].aircraft.status()

    def inside_world(self, east: float, north: float) -> bool:
        """True when the point lies on the world's terrain grid."""
        e0, n0, e1, n1 = self.world.bounds
        return e0 <= east <= e1 and n0 <= north <= n1

    def blocked_by(self, east: float, north: float, up: float | None = None) -> str | None:
        """Building occupying the point (any height if ``up`` is None), else None."""
        return self.geometry.point_in_building(east, north, up)


def _delayed(obj: DynamicObject, seconds: float) -> DynamicObject:
    """``obj``, a driving car departing ``seconds`` later (the same object otherwise)."""
    if obj.drive is None or seconds == 0.0:
        return obj
    return replace(obj, drive=replace(obj.drive, depart=obj.drive.depart + seconds))


def finite(*values: float) -> bool:
    """True when every value is a finite number."""
    return all(math.isfinite(v) for v in values)
