"""The FCL and PPCL command registry: one frozen spec per command (chapter sections 6.2.2-6.2.3).

Everything the code needs to know about a command that is not behaviour is here, once: its
service type, the request fields that become its arguments (in order, with names and units),
the CLI's words, units and conversions, the DRC automaton's input event, the number of values
its wire event carries, and the payload resource it needs. The node's services,
``fcl_api``/``ppcl_api``, the fakes and ``hdrc3 fcl|ppcl`` are derived from it. The wire event,
every event id and the flight state a command needs come from the DRC automaton
(``automata/drc.hcsm``): the event its transition on the input event SENDs, and that
transition's guard.

Adding a command: a member of ``FclCommand``/``PpclCommand`` (codes.py) and its entry here, its
transitions in ``drc.hcsm`` and the kernel's model, and its ``.srv`` in hdrc3_interfaces.
"""

from __future__ import annotations

import enum
import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from operator import attrgetter
from types import MappingProxyType
from typing import Any

from hdrc3_hcsm.tables import OpCode
from hdrc3_platform_server.codes import FclCommand, PpclCommand, PtuActivity, Resource
from hdrc3_platform_server.drc import load_model


class CliInput(enum.Enum):
    """Where ``hdrc3 fcl|ppcl`` takes an argument's value from."""

    NUMBER = "number"
    """The next positional number."""
    OPTIONAL = "optional"
    """The next positional number, which may be left out (the field keeps its default)."""
    GIVEN = "given"
    """1 when every optional number was given, else 0 (look_at's has_altitude)."""
    CAMERA = "camera"
    """The ``--camera`` option's id."""
    AUTO_MANUAL = "auto_manual"
    """The word ``auto`` (1) or ``manual`` (0)."""


@dataclass(frozen=True, slots=True)
class Argument:
    """One argument: a request field, its name in the checks' reasons, its unit, its CLI word."""

    name: str
    field: str
    """Dotted request field, e.g. ``segment.start_point.x``."""
    unit: str
    cli: str = ""
    """CLI metavar (empty: not a positional word)."""
    source: CliInput = CliInput.NUMBER
    degrees: bool = False
    """The CLI takes degrees, the service radians."""
    mirrors: tuple[str, ...] = ()
    """Further request fields the CLI fills with the same value."""

    def read(self, request: Any) -> float:
        """The argument's value in a service request (flags and ids as floats)."""
        return float(attrgetter(self.field)(request))

    def write(self, request: Any, value: float) -> None:
        """Set the field (and its mirrors) to ``value`` converted to the field's own type."""
        for path in (self.field, *self.mirrors):
            parent, _, attr = path.rpartition(".")
            owner = attrgetter(parent)(request) if parent else request
            setattr(owner, attr, type(getattr(owner, attr))(value))

    def from_cli(self, value: float) -> float:
        """A CLI number in the service's unit."""
        return math.radians(value) if self.degrees else value


@functools.cache
def _always_taken(api_event: str) -> bool:
    """The Flight automaton takes ``api_event`` in every state, unguarded (cancel, brake)."""
    model = load_model()
    flight = model.automata["Flight"]
    index = model.events.index[api_event]
    return all(any(spec.guard is None for spec in row.get(index, ())) for row in flight.table)


@functools.cache
def _sent_on(api_event: str) -> str:
    """The remote event the DRC automaton SENDs when ``api_event`` fires a transition."""
    model = load_model()
    index = model.events.index[api_event]
    sent = {
        action.name
        for automaton in model.automata.values()
        for row in automaton.table
        for spec in row.get(index, ())
        for action in spec.actions
        if action.op is OpCode.SEND and action.remote is not None
    }
    (name,) = sent  # a registry entry without one transition to the kernel is a packaging error
    return name


class _Service:
    """What FCL and PPCL specs share: the service, the DRC input event, the arguments."""

    __slots__ = ()
    service: str
    """Service type name in ``hdrc3_interfaces.srv``."""
    api_event: str
    """Input event of the DRC automaton (posted by the command layer with the payload)."""
    arguments: tuple[Argument, ...]

    @property
    def names(self) -> tuple[str, ...]:
        """Argument names in the order ``submit`` takes them."""
        return tuple(a.name for a in self.arguments)

    @property
    def wire_event(self) -> str:
        """The event the DRC automaton sends the PFC or PPC."""
        return _sent_on(self.api_event)

    def service_type(self) -> Any:
        """The generated service class."""
        import hdrc3_interfaces.srv

        return getattr(hdrc3_interfaces.srv, self.service)

    def values(self, request: Any) -> tuple[float, ...]:
        """The arguments of a service request, in order."""
        return tuple(a.read(request) for a in self.arguments)


@dataclass(frozen=True, slots=True)
class FclSpec(_Service):
    """One FCL command."""

    command: FclCommand
    service: str
    api_event: str
    wire_arity: int
    """Numbers after the id in the wire event's payload."""
    arguments: tuple[Argument, ...] = ()

    @property
    def returns_ok(self) -> bool:
        """Its return is FCL_OK (cancel, emergency brake: chapter 6.2.2): nothing to wait for.

        True when the DRC automaton takes its input event in every Flight state, unguarded.
        """
        return _always_taken(self.api_event)


@dataclass(frozen=True, slots=True)
class PpclSpec(_Service):
    """One PPCL mode or parameter command (forwarded to the PPC)."""

    command: PpclCommand
    service: str
    api_event: str
    wire_arity: int
    resource: Resource
    mode: str
    """A newer command of the same mode replaces (cancels) a pending one."""
    per_camera: bool = False
    """The mode is per camera (the first argument is the camera id)."""
    activity: PtuActivity | None = None
    """What ppcl_ptu_activity_info answers once the command is accepted."""
    arguments: tuple[Argument, ...] = ()

    def mode_key(self, values: tuple[float, ...]) -> str:
        """The mode this call occupies (per camera: with the camera id)."""
        return f"{self.mode}{values[0]:g}" if self.per_camera else self.mode


def _heading() -> tuple[Argument, ...]:
    return (Argument("heading", "heading", "rad", "HEADING_DEG", degrees=True),)


def _xyz(name: str, field: str, cli: str) -> tuple[Argument, ...]:
    return tuple(
        Argument(f"{name}_{axis}", f"segment.{field}.{axis}", "m", f"{cli}{axis.upper()}")
        for axis in "xyz"
    )


FCL: dict[FclCommand, FclSpec] = {
    s.command: s
    for s in (
        FclSpec(FclCommand.TAKEOFF, "FclTakeoff", "Api-Takeoff-EV", 0),
        FclSpec(FclCommand.LAND, "FclLand", "Api-Land-EV", 1, arguments=_heading()),
        FclSpec(FclCommand.YAW, "FclYaw", "Api-Yaw-EV", 1, arguments=_heading()),
        FclSpec(
            FclCommand.CLIMB,
            "FclClimb",
            "Api-Climb-EV",
            1,
            arguments=(Argument("altitude", "altitude", "m (WGS84 ellipsoid)", "ALTITUDE_M"),),
        ),
        FclSpec(
            FclCommand.TRAJ3D_FLYTO,
            "FclTraj3dFlyto",
            "Api-Flyto-EV",
            4,
            arguments=(
                Argument("longitude", "longitude", "deg", "LON"),
                Argument("latitude", "latitude", "deg", "LAT"),
                Argument("altitude", "altitude", "m (WGS84 ellipsoid)", "ALT_M"),
                Argument("velocity", "velocity", "m/s", "VELOCITY"),
            ),
        ),
        FclSpec(
            FclCommand.TRAJ3D,
            "FclTraj3d",
            "Api-Traj3D-EV",
            14,
            arguments=(
                *_xyz("start", "start_point", "S"),
                *_xyz("end", "end_point", "E"),
                *_xyz("start_direction", "start_direction", "SD"),
                *_xyz("end_direction", "end_direction", "ED"),
                Argument(
                    "velocity", "velocity", "m/s", "VELOCITY", mirrors=("segment.target_velocity",)
                ),
                Argument(
                    "end_velocity",
                    "end_velocity",
                    "m/s",
                    "END_VELOCITY",
                    mirrors=("segment.end_velocity",),
                ),
            ),
        ),
        FclSpec(FclCommand.TRACK, "FclTrack", "Api-Track-EV", 0),
        FclSpec(FclCommand.EMERGENCY_BRAKE, "FclEmergencyBrake", "Api-Brake-EV", 0),
        FclSpec(FclCommand.CANCEL, "FclCancel", "Api-Cancel-EV", 0),
    )
}
"""Every FCL command, in the order of chapter 6.2.2."""

_CAMERA = Argument("camera_id", "camera_id", "id (0 color, 1 thermal)", source=CliInput.CAMERA)


def _camera_value(name: str, unit: str, cli: str) -> tuple[Argument, ...]:
    return (_CAMERA, Argument(name, "value", unit, cli))


def _laser(name: str, unit: str, cli: str, *, degrees: bool = False) -> tuple[Argument, ...]:
    return (Argument(name, "value", unit, cli, degrees=degrees),)


_P = PpclCommand
_PTU, _CAM, _IP, _LASER = Resource.PTU, Resource.CAMERA, Resource.IMAGE_PROCESSING, Resource.LASER
PPCL: dict[PpclCommand, PpclSpec] = {
    s.command: s
    for s in (
        PpclSpec(
            _P.LOOK_AT,
            "PpclLookAt",
            "Api-Pl-Look-At-EV",
            3,
            _PTU,
            "ptu",
            activity=PtuActivity.LOOK_AT_POINT,
            arguments=(
                Argument("longitude", "longitude", "deg", "LON"),
                Argument("latitude", "latitude", "deg", "LAT"),
                Argument("has_altitude", "has_altitude", "0/1", source=CliInput.GIVEN),
                Argument("altitude", "altitude", "m (WGS84 ellipsoid)", "ALT_M", CliInput.OPTIONAL),
            ),
        ),
        PpclSpec(
            _P.TURN_TO,
            "PpclTurnTo",
            "Api-Pl-Turn-To-EV",
            2,
            _PTU,
            "ptu",
            activity=PtuActivity.TURNTO,
            arguments=(
                Argument("pan", "pan", "rad", "PAN_DEG", degrees=True),
                Argument("tilt", "tilt", "rad", "TILT_DEG", degrees=True),
            ),
        ),
        PpclSpec(
            _P.PTU_ABORT,
            "PpclTrigger",
            "Api-Pl-Ptu-Abort-EV",
            0,
            _PTU,
            "ptu",
            activity=PtuActivity.IDLE,
        ),
        PpclSpec(
            _P.IP_COLOR_TRACKER,
            "PpclColorTracker",
            "Api-Pl-IP-Tracker-EV",
            2,
            _IP,
            "ip",
            arguments=(Argument("x", "x", "px", "X_PX"), Argument("y", "y", "px", "Y_PX")),
        ),
        PpclSpec(_P.IP_STATE_ESTIMATION, "PpclTrigger", "Api-Pl-IP-State-Est-EV", 0, _IP, "ip"),
        PpclSpec(_P.IP_ABORT, "PpclTrigger", "Api-Pl-IP-Abort-EV", 0, _IP, "ip"),
        PpclSpec(_P.IP_SALIENCY, "PpclTrigger", "Api-Pl-IP-Saliency-EV", 0, _IP, "ip"),
        PpclSpec(
            _P.ZOOM,
            "PpclZoom",
            "Api-Pl-Zoom-EV",
            2,
            _CAM,
            "zoom",
            arguments=_camera_value("zoom", "0..1", "VALUE_0_1"),
        ),
        PpclSpec(
            _P.EXPOSURE,
            "PpclExposure",
            "Api-Pl-Exposure-EV",
            2,
            _CAM,
            "exposure",
            per_camera=True,
            arguments=(
                _CAMERA,
                Argument(
                    "auto_exposure", "auto_exposure", "0/1", "auto|manual", CliInput.AUTO_MANUAL
                ),
            ),
        ),
        PpclSpec(
            _P.IRIS,
            "PpclCameraValue",
            "Api-Pl-Iris-EV",
            2,
            _CAM,
            "iris",
            per_camera=True,
            arguments=_camera_value("iris", "0..1", "VALUE_0_1"),
        ),
        PpclSpec(
            _P.SHUTTER,
            "PpclCameraValue",
            "Api-Pl-Shutter-EV",
            2,
            _CAM,
            "shutter",
            per_camera=True,
            arguments=_camera_value("shutter", "s", "SECONDS"),
        ),
        PpclSpec(
            _P.LASER_ANGULAR_RESOLUTION,
            "PpclLaserValue",
            "Api-Pl-Laser-Angular-EV",
            1,
            _LASER,
            "laser_angular_resolution",
            arguments=_laser("angular_resolution", "deg (0.25, 0.5, 1)", "DEG"),
        ),
        PpclSpec(
            _P.LASER_DISTANCE_RESOLUTION,
            "PpclLaserValue",
            "Api-Pl-Laser-Distance-EV",
            1,
            _LASER,
            "laser_distance_resolution",
            arguments=_laser("distance_resolution", "m (0.001, 0.01)", "METRES"),
        ),
        PpclSpec(
            _P.LASER_ROTATION_SPEED,
            "PpclLaserValue",
            "Api-Pl-Laser-Speed-EV",
            1,
            _LASER,
            "laser_rotation",
            arguments=_laser("rotation_speed", "rad/s", "RAD_PER_S"),
        ),
        PpclSpec(
            _P.LASER_ROTATION_ANGLE,
            "PpclLaserValue",
            "Api-Pl-Laser-Angle-EV",
            1,
            _LASER,
            "laser_rotation",
            arguments=_laser("rotation_angle", "rad", "DEG", degrees=True),
        ),
        PpclSpec(
            _P.LASER_START_DATA_COLLECTION,
            "PpclTrigger",
            "Api-Pl-Laser-Start-EV",
            0,
            _LASER,
            "laser_collect",
        ),
        PpclSpec(
            _P.LASER_STOP_DATA_COLLECTION,
            "PpclTrigger",
            "Api-Pl-Laser-Stop-EV",
            0,
            _LASER,
            "laser_collect",
        ),
    )
}
"""Every PPCL mode and parameter command, in the order of chapter 6.2.3."""


@functools.cache
def wire_arity() -> Mapping[str, int]:
    """Numbers after the id, per command event the DRC sends the PFC or the PPC."""
    specs: list[FclSpec | PpclSpec] = [*FCL.values(), *PPCL.values()]
    return MappingProxyType({s.wire_event: s.wire_arity for s in specs})
