"""Validated requests to a running world_sim: every request answers a code and a reason.

The ROS services of the node are thin wrappers around :class:`SimServices`; nothing a client
sends (NaN, unknown agents or sensors, positions inside buildings) can raise out of here.
Codes equal the constants of ``hdrc3_interfaces/msg/SimResult.msg``. Every number has a stated
finite range and every string a length limit (the constants below; ``sim/WORLD_SIM.md``,
"Services", lists them per field); a reason quotes at most ``SHOWN`` characters of a string.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass

from sim.geodesy import geodetic_to_enu
from sim.hook import HookFault
from sim.lockstep import LockstepBarrier
from sim.rc_transmitter import FlightModeSwitch, RcSticks
from sim.sensors.fault import FaultMode
from sim.sensors.laser import LaserConfig, LaserConfigStatus, LaserRangeFinder, RangeMode
from sim.sensors.power import ALL_DEVICES, PowerDevice
from sim.sensors.ptu import PtuCommandStatus
from sim.wind import WindSettings
from sim.world import BoxContents, DynamicObject, ObjectKind
from sim.world_loader import DEFAULT_SIZES, ZERO_CELSIUS
from sim.world_sim import WorldSim, finite
from sim.yacs import YacsCommand

HOOK = "hook"
"""SimInjectFault sensor name of the payload hook (its modes are HOOK_MODES)."""
HOOK_MODES = frozenset(int(f) for f in HookFault if f is not HookFault.NONE)
MAX_TELEPORT_HEIGHT = 500.0
"""m above the terrain: higher teleports are rejected."""
ANGLE_LIMIT = math.tau
"""rad: headings and payload angles are accepted within +-one turn."""
MAX_NAME_LENGTH = 64
"""Characters of an agent, sensor, object kind or object id."""
MAX_FAULT_VALUES = 16
"""Values of a fault magnitude (the widest sensor measures 6 fields)."""
MAX_BIAS = 1.0e6
"""Largest fault magnitude value (a bias in the sensor's units: m, m/s, rad, Pa ...)."""
MAX_NOISE_FACTOR = 1000.0
"""Largest NOISE_UP factor on a sensor's noise."""
SHOWN = 40
"""Characters of a rejected string quoted in a reason."""

SPAWN_DEFAULTS: dict[ObjectKind, dict[str, object]] = {
    ObjectKind.PERSON: {"temperature": ZERO_CELSIUS + 33.0},
    ObjectKind.BOX: {"contents": BoxContents.FOOD, "mass": 5.0},
    ObjectKind.CARRIER: {"capacity": 4, "mass": 20.0},
    ObjectKind.DUMMY: {},
    ObjectKind.ANIMAL: {"temperature": ZERO_CELSIUS + 30.0},
    ObjectKind.CAR: {"temperature": ZERO_CELSIUS + 20.0, "mass": 1300.0},
}
"""Kind-specific properties of spawned objects (the service gives only kind, id and pose)."""


class SimCode(enum.IntEnum):
    """Result codes (values of SimResult.msg)."""

    OK = 0
    INVALID_ARGUMENT = 1
    UNKNOWN_AGENT = 2
    UNKNOWN_NAME = 3
    BLOCKED = 4
    DUPLICATE = 5
    WRONG_STATE = 6


@dataclass(frozen=True, slots=True)
class SimResult:
    """Outcome of one request."""

    code: SimCode
    reason: str = ""

    @property
    def ok(self) -> bool:
        """True when the request was carried out."""
        return self.code is SimCode.OK


OK = SimResult(SimCode.OK)


def shown(text: str) -> str:
    """``text`` quoted for a reason, cut to SHOWN characters."""
    return repr(text) if len(text) <= SHOWN else f"{text[:SHOWN]!r}... ({len(text)} characters)"


def invalid(reason: str) -> SimResult:
    """An INVALID_ARGUMENT answer."""
    return SimResult(SimCode.INVALID_ARGUMENT, reason)


def name_problem(what: str, text: str) -> SimResult | None:
    """A name longer than MAX_NAME_LENGTH, or None."""
    if len(text) > MAX_NAME_LENGTH:
        return invalid(f"{what} {shown(text)} longer than {MAX_NAME_LENGTH} characters")
    return None


def angle_problem(what: str, value: float) -> SimResult | None:
    """A NaN/inf angle or one beyond +-ANGLE_LIMIT, or None."""
    if not (math.isfinite(value) and abs(value) <= ANGLE_LIMIT):
        return invalid(f"{what} must be finite, within [-2 pi, 2 pi] rad, got {value:g}")
    return None


class RcSwitch(enum.IntEnum):
    """Values of the SimSetRc.srv switch fields (0 always means: leave as is)."""

    KEEP = 0
    FIRST = 1
    """MODE_MANUAL, ENGINE_ON or LINK_OK."""
    SECOND = 2
    """MODE_AUTONOMOUS, ENGINE_OFF or LINK_LOST."""


@dataclass(frozen=True, slots=True)
class RcRequest:
    """One SimSetRc request, field by field."""

    mode: int = 0
    engine: int = 0
    link: int = 0
    sticks: tuple[float, float, float, float] | None = None
    """(roll, pitch, yaw, throttle) or None to leave the sticks."""


class SimServices:
    """Validation and execution of world_sim requests."""

    def __init__(self, sim: WorldSim, barrier: LockstepBarrier[YacsCommand | None]) -> None:
        """Serve requests against ``sim`` and its lockstep ``barrier``."""
        self.sim = sim
        self.barrier = barrier
        self.paused = False

    def _agent(self, agent: str) -> SimResult | None:
        if agent in self.sim.agents:
            return None
        known = ", ".join(self.sim.agents)
        return SimResult(
            SimCode.UNKNOWN_AGENT, f"unknown agent {shown(agent)} (simulated: {known})"
        )

    def reset(self, agent: str, lockstep_agents: Sequence[str] = ()) -> SimResult:
        """Reset one agent or (agent "") everything, then set the lockstep mode."""
        if agent:
            problem = self._agent(agent)
            if problem is not None:
                return problem
            if lockstep_agents:
                return invalid("lockstep_agents applies to a full reset only")
            # the barrier keeps this tick's answer: the controller must not have to answer twice
            self.sim.reset(agent)
            return OK
        if len(lockstep_agents) > len(self.sim.agents):
            return invalid(
                f"{len(lockstep_agents)} lockstep agents, only {len(self.sim.agents)} simulated"
            )
        for name in lockstep_agents:
            problem = self._agent(name)
            if problem is not None:
                return problem
        self.sim.reset()
        self.barrier.forget()
        self.barrier.set_required(lockstep_agents)
        return OK

    def pause(self, paused: bool) -> SimResult:
        """Stop or resume sim time."""
        self.paused = paused
        return OK

    def teleport(
        self, agent: str, wgs84: bool, x: float, y: float, height: float, heading: float
    ) -> SimResult:
        """Move an agent, at rest and level, to a free spot of the world."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        if not finite(x, y, height, heading):
            return invalid("teleport values must be finite")
        if not 0.0 <= height <= MAX_TELEPORT_HEIGHT:
            return invalid(f"height {height:g} m outside [0, {MAX_TELEPORT_HEIGHT:g}]")
        problem = angle_problem("heading", heading)
        if problem is not None:
            return problem
        if wgs84:
            if not (-90.0 <= x <= 90.0 and -180.0 <= y <= 180.0):
                return invalid(f"({x:g}, {y:g}) is not a latitude/longitude")
            east, north, _ = geodetic_to_enu(
                self.sim.world.origin, x, y, self.sim.world.origin.altitude
            )
        else:
            east, north = x, y
        sim = self.sim
        if not sim.inside_world(east, north):
            return SimResult(SimCode.BLOCKED, f"({east:.6g}, {north:.6g}) is outside the world")
        # the aircraft is about 3.6 m long with its rotor: keep its whole disc clear
        up = sim.world.terrain.height(east, north) + height
        for de, dn in ((0.0, 0.0), (1.8, 0.0), (-1.8, 0.0), (0.0, 1.8), (0.0, -1.8)):
            building = sim.blocked_by(east + de, north + dn, up + 1.0)
            if building is not None:
                return SimResult(
                    SimCode.BLOCKED, f"({east:.6g}, {north:.6g}) is inside building {building}"
                )
        sim.place(agent, east, north, height, heading % math.tau)
        return OK

    def inject_fault(
        self, agent: str, sensor: str, mode: int, magnitude: Sequence[float]
    ) -> SimResult:
        """Set the fault switch of one sensor (mode NONE clears it)."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        if sensor == HOOK:
            return self._hook_fault(agent, mode)
        sensors = self.sim.agents[agent].sensors.sensors()
        target = sensors.get(sensor)
        if target is None:
            known = ", ".join(sorted([*sensors, HOOK]))
            return SimResult(
                SimCode.UNKNOWN_NAME, f"unknown sensor {shown(sensor)} (known: {known})"
            )
        modes = list(FaultMode)
        if not 0 <= mode < len(modes):
            if mode in HOOK_MODES:
                return invalid(f"fault mode {mode} is a fault of the {HOOK!r}, not of a sensor")
            return invalid(f"unknown fault mode {mode}")
        fault = modes[mode]
        if len(magnitude) > MAX_FAULT_VALUES:
            return invalid(f"{len(magnitude)} magnitude values, at most {MAX_FAULT_VALUES}")
        values = tuple(float(m) for m in magnitude) or (0.0,)
        if not (finite(*values) and max(abs(v) for v in values) <= MAX_BIAS):
            return invalid(f"fault magnitude must be finite, within +-{MAX_BIAS:g}")
        if fault is FaultMode.NOISE_UP and (
            len(values) != 1 or not 0.0 <= values[0] <= MAX_NOISE_FACTOR
        ):
            return invalid(f"noise-up needs one factor within [0, {MAX_NOISE_FACTOR:g}]")
        if fault is FaultMode.BIAS:
            sizes = {1} if isinstance(target, LaserRangeFinder) else {1, len(target.fields)}
            if len(values) not in sizes:
                return SimResult(
                    SimCode.INVALID_ARGUMENT,
                    f"bias of {sensor} takes {' or '.join(map(str, sorted(sizes)))} values "
                    f"({', '.join(target.fields)}), got {len(values)}",
                )
        target.fault.set(fault, values)
        return OK

    def _hook_fault(self, agent: str, mode: int) -> SimResult:
        """Release in flight, hook failure, wrong box, or NONE (clears them)."""
        if mode != HookFault.NONE and mode not in HOOK_MODES:
            known = ", ".join(f"{m.value} {m.name.lower()}" for m in HookFault)
            return invalid(f"fault mode {mode} is not a hook fault ({known})")
        fault = HookFault(mode)
        if fault is HookFault.RELEASE and not self.sim.carrying(agent).carrying:
            return SimResult(SimCode.WRONG_STATE, f"the hook of {agent} holds nothing to release")
        self.sim.hook_fault(agent, fault)
        return OK

    def spawn_object(
        self, ident: str, kind: str, east: float, north: float, heading: float
    ) -> SimResult:
        """Add a dynamic object on the ground."""
        if not ident.strip():
            return invalid("object id must not be empty")
        problem = name_problem("object id", ident)
        if problem is not None:
            return problem
        if not ident.isprintable():
            return invalid(f"object id {shown(ident)} contains control characters")
        kinds = {k.value: k for k in ObjectKind}
        found = kinds.get(kind)
        if found is None:
            return SimResult(
                SimCode.UNKNOWN_NAME,
                f"unknown object kind {shown(kind)} (known: {', '.join(kinds)})",
            )
        if not finite(east, north):
            return invalid("object position must be finite")
        problem = angle_problem("heading", heading)
        if problem is not None:
            return problem
        sim = self.sim
        if ident in sim.objects:
            return SimResult(SimCode.DUPLICATE, f"object id {shown(ident)} already exists")
        if not sim.inside_world(east, north):
            return SimResult(SimCode.BLOCKED, f"({east:.6g}, {north:.6g}) is outside the world")
        building = sim.blocked_by(east, north)
        if building is not None:
            return SimResult(
                SimCode.BLOCKED, f"({east:.6g}, {north:.6g}) is inside building {building}"
            )
        extra = SPAWN_DEFAULTS[found]
        sim.spawn(
            DynamicObject(
                ident,
                found,
                east,
                north,
                heading % math.tau,
                DEFAULT_SIZES[found],
                **extra,  # type: ignore[arg-type]
            )
        )
        return OK

    def set_wind(self, mean: tuple[float, float, float], gust_intensity: float) -> SimResult:
        """Change the wind from the next tick on."""
        settings = WindSettings(mean, gust_intensity)
        problem = settings.problem()
        if problem is not None:
            return SimResult(SimCode.INVALID_ARGUMENT, problem)
        self.sim.set_wind(settings)
        return OK

    def set_power(self, agent: str, devices: int, on: bool) -> SimResult:
        """Switch on-board devices of an agent."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        if devices <= 0 or devices & ~int(ALL_DEVICES):
            return SimResult(
                SimCode.UNKNOWN_NAME,
                f"device bits {devices:#x} not within the known devices {int(ALL_DEVICES):#x}",
            )
        self.sim.agents[agent].sensors.power.switch(PowerDevice(devices), on)
        return OK

    def set_rc(self, agent: str, request: RcRequest) -> SimResult:
        """Move the safety pilot's switches and sticks."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        for name in ("mode", "engine", "link"):
            if getattr(request, name) not in tuple(RcSwitch):
                return invalid(f"rc {name} must be 0, 1 or 2")
        sticks: RcSticks | None = None
        if request.sticks is not None:
            roll, pitch, yaw, throttle = request.sticks
            if not (
                finite(roll, pitch, yaw, throttle) and max(abs(roll), abs(pitch), abs(yaw)) <= 1.0
            ):
                return invalid("sticks must be finite, within [-1, 1]")
            if not 0.0 <= throttle <= 1.0:
                return invalid("throttle must be within [0, 1]")
            sticks = RcSticks(roll, pitch, yaw, throttle)
        rc = self.sim.agents[agent].aircraft.rc
        if request.mode:
            manual = request.mode == RcSwitch.FIRST
            rc.set_mode(FlightModeSwitch.MANUAL if manual else FlightModeSwitch.AUTONOMOUS)
        if request.engine:
            rc.set_engine(request.engine == RcSwitch.FIRST)
            if request.engine == RcSwitch.FIRST:
                self.sim.agents[agent].aircraft.restart_engine()
        if request.link:
            rc.set_link(request.link == RcSwitch.FIRST)
        if sticks is not None:
            rc.set_sticks(sticks)
        return OK

    # ------------------------------------------------- payload (PPC) commands
    def hook_command(self, agent: str, cable_length: float, magnet: bool) -> SimResult:
        """Winch length (m, within the drum's cable) and magnet switch of the payload hook."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        top = self.sim.payload.params.max_cable
        if not (math.isfinite(cable_length) and 0.0 <= cable_length <= top):
            return invalid(
                f"cable length must be finite, within [0, {top:g}] m, got {cable_length:g}"
            )
        self.sim.hook_command(agent, cable_length, bool(magnet))
        return OK

    def ptu_command(self, agent: str, pan: float, tilt: float) -> SimResult:
        """Pan-tilt set-point within +-one turn (then clamped to the PTU's limits)."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        problem = angle_problem("pan", pan) or angle_problem("tilt", tilt)
        if problem is not None:
            return problem
        result = self.sim.agents[agent].sensors.ptu.command(pan, tilt)
        if result.status is PtuCommandStatus.UNPOWERED:
            return SimResult(SimCode.WRONG_STATE, "the PTU is switched off")
        return OK

    def camera_command(self, agent: str, camera_id: int, zoom: float) -> SimResult:
        """Zoom of one camera (0 wide .. 1 tele)."""
        problem = self._agent(agent)
        if problem is not None:
            return problem
        sensors = self.sim.agents[agent].sensors
        cameras = {0: sensors.color_camera, 1: sensors.thermal_camera}
        camera = cameras.get(camera_id)
        if camera is None:
            return SimResult(
                SimCode.UNKNOWN_NAME, f"unknown camera id {camera_id} (0 color, 1 thermal)"
            )
        if not (math.isfinite(zoom) and 0.0 <= zoom <= 1.0):
            return invalid(f"zoom must be finite, within [0, 1], got {zoom:g}")
        camera.command_zoom(zoom)
        return OK

    def laser_command(
        self,
        agent: str,
        angular_resolution: float,
        distance_resolution: float,
        rotation_speed: float,
        hold_angle: bool,
        rotation_angle: float,
        power: bool | None = None,
    ) -> SimResult:
        """Scan configuration and rotation of the laser range finder.

        The field of view follows the angular resolution (0.25 deg is only available with
        100 deg); holding an angle moves the mechanism there at once. ``power`` (the PPC's data
        collection flag) switches the unit on or off; None leaves it as it is.
        """
        problem = self._agent(agent)
        if problem is not None:
            return problem
        if not finite(angular_resolution, distance_resolution, rotation_speed, rotation_angle):
            return invalid("laser command values must be finite")
        laser = self.sim.agents[agent].sensors.laser
        top = laser.params.max_rotation_speed
        if abs(rotation_speed) > top:
            return invalid(f"rotation speed {rotation_speed:g} rad/s beyond +-{top:.3f} rad/s")
        problem = angle_problem("rotation angle", rotation_angle)
        if problem is not None:
            return problem
        modes = {m.resolution: m for m in RangeMode}
        mode = modes.get(distance_resolution)
        if mode is None:
            known = " or ".join(str(r) for r in modes)
            return invalid(f"distance resolution must be {known} m, got {distance_resolution:g}")
        fov = 100.0 if angular_resolution == 0.25 else laser.config.fov_deg
        config = LaserConfig(fov, angular_resolution, mode)
        if config != laser.config:
            status, reason = laser.configure(config)
            if status is LaserConfigStatus.REJECTED:
                return invalid(reason)
        laser.set_rotation_speed(0.0 if hold_angle else rotation_speed)
        if hold_angle:
            laser.rotation_angle = rotation_angle % math.tau
        if power is not None:
            self.sim.agents[agent].sensors.power.switch(PowerDevice.LASER, power)
        return OK
