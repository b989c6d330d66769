"""The elementary action registry: one source of truth for every action type (section 6.3).

Each action is called in the language as ``name(TS, TE, p1, p2, ...)`` (Example 6.2): the node's
start and end times first, then the type-specific parameters listed here with their types and
units (SI; headings and PTU angles in degrees at this user-facing edge, as FCL/PPCL take them).
Executors (one per action per platform) are registered against these names, and the resolver
type-checks calls against them. Trailing parameters with a default may be left out.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from hdrc3_control.ppc_hardware import PtuLimits


class ParamType(enum.Enum):
    """Type of a node parameter (its constraint-variable kind)."""

    TIME = "time"
    """A time point in seconds from the start of the mission (T_S, T_E): STN variables."""
    DURATION = "duration"
    SPEED = "speed"
    LENGTH = "length"
    ANGLE = "angle"
    NUMBER = "number"
    AGENT = "agent"
    AREA = "area"
    POINT = "point"
    PATH = "path"

    @property
    def numeric(self) -> bool:
        """Numbers (as opposed to names of agents, areas, points, paths)."""
        return self not in _NAMES  # a tuple: compared by identity, an enum hashes slowly


_NAMES = (ParamType.AGENT, ParamType.AREA, ParamType.POINT, ParamType.PATH)


@dataclass(frozen=True)
class ParamSpec:
    """One type-specific parameter of an action."""

    name: str
    type: ParamType
    unit: str
    default: float | None = None
    minimum: float | None = None
    maximum: float | None = None
    """Bounds the platform imposes (the RMAX flight envelope), added as constraints."""
    preferred: float | None = None
    """The value an executor binds an open parameter to when the network allows it."""


class Capability(enum.Enum):
    """What a platform must have to run an action (a delegation contractor checks it, §10)."""

    FLIGHT = "flight"
    CAMERA = "camera"
    PTU = "ptu"
    HOOK = "hook"
    RADIATION = "radiation"
    LASER = "laser"


_FLY = frozenset({Capability.FLIGHT})


@dataclass(frozen=True)
class ActionSpec:
    """One elementary action type."""

    name: str
    summary: str
    params: tuple[ParamSpec, ...] = ()
    duration: str | None = None
    """Name of a DURATION parameter that fixes ``TE - TS`` (hover, wait)."""
    fcl_or_ppcl: str = ""
    """The Platform Server command the RMAX executor issues (documentation for executors)."""
    needs: frozenset[Capability] = _FLY
    """The platform capabilities the action uses."""

    def param(self, name: str) -> ParamSpec | None:
        """The parameter called ``name``, if any."""
        return next((p for p in self.params if p.name == name), None)

    @property
    def required(self) -> int:
        """How many type-specific arguments must be given (the rest have defaults)."""
        return sum(p.default is None for p in self.params)


_SPEED = ParamSpec("speed", ParamType.SPEED, "m/s", None, 0.5, 15.0, preferred=8.0)
_ALT = ParamSpec("altitude", ParamType.LENGTH, "m above ground", 30.0, 5.0, 150.0)
_DURATION = ParamSpec("duration", ParamType.DURATION, "s", None, 0.0, None)
_PTU = PtuLimits()
MAX_PARTS = 16
"""Most parts a scanned area is split into (one per aircraft)."""
_BOX = ParamSpec("box", ParamType.POINT, "point named by the box's tag, where the box is")
_CARRIER = ParamSpec("carrier", ParamType.POINT, "point named by the carrier's tag, where it is")
_PLACE = ParamSpec("place", ParamType.POINT, "point where the load goes down")
_HOOK = "ppcl hook (lower, attach, raise, release)"
_LIFT = frozenset({Capability.FLIGHT, Capability.HOOK})

ACTIONS: Mapping[str, ActionSpec] = MappingProxyType(
    {
        a.name: a
        for a in (
            ActionSpec(
                "take-off", "take off and hover at the take-off altitude", (), None, "takeoff"
            ),
            ActionSpec(
                "land",
                "land with the given heading",
                (ParamSpec("heading", ParamType.ANGLE, "deg", 0.0, -360.0, 360.0),),
                None,
                "land",
            ),
            ActionSpec("hover", "hover in place", (_DURATION,), "duration", "(hovering)"),
            ActionSpec(
                "fly-to",
                "fly straight to a point",
                (_SPEED, ParamSpec("destination", ParamType.POINT, "point")),
                None,
                "traj3d_flyto",
            ),
            ActionSpec(
                "fly-path",
                "fly along a path of points",
                (_SPEED, ParamSpec("path", ParamType.PATH, "path")),
                None,
                "traj3d",
            ),
            ActionSpec(
                "scan-area",
                "camera coverage of a polygon (or of part PART of PARTS equal bands of it) at an"
                " altitude, the camera straight down and the saliency pipeline running",
                (
                    _SPEED,
                    ParamSpec("area", ParamType.AREA, "area"),
                    _ALT,
                    ParamSpec("part", ParamType.NUMBER, "band, 1..parts", 1.0, 1.0, MAX_PARTS),
                    ParamSpec("parts", ParamType.NUMBER, "bands", 1.0, 1.0, MAX_PARTS),
                ),
                None,
                "traj3d",
                frozenset({Capability.FLIGHT, Capability.CAMERA, Capability.PTU}),
            ),
            ActionSpec(
                "laser-map-area",
                "an elevation map of a polygon with the rotating laser range finder (11.2): set"
                " its resolutions and rotation speed, collect while flying a coverage pattern at"
                " an altitude, stop (the laser_mapper stores the map in the path planner's GIS)",
                (
                    _SPEED,
                    ParamSpec("area", ParamType.AREA, "area"),
                    _ALT,
                    ParamSpec(
                        "rotation", ParamType.NUMBER, "rad/s of the mechanism", 3.0, 0.1, 3.1
                    ),
                ),
                None,
                "ppcl laser_* + traj3d",
                frozenset({Capability.FLIGHT, Capability.LASER}),
            ),
            ActionSpec(
                "look-at",
                "point the camera at a point",
                (ParamSpec("target", ParamType.POINT, "point"),),
                None,
                "ppcl look_at",
                frozenset({Capability.PTU}),
            ),
            ActionSpec(
                "ptu-turn-to",
                "turn the pan-tilt unit to fixed angles",
                (
                    ParamSpec(
                        "pan",
                        ParamType.ANGLE,
                        "deg",
                        None,
                        math.degrees(_PTU.min_pan),
                        math.degrees(_PTU.max_pan),
                    ),
                    ParamSpec(
                        "tilt",
                        ParamType.ANGLE,
                        "deg, positive looks down",
                        None,
                        math.degrees(_PTU.min_tilt),
                        math.degrees(_PTU.max_tilt),
                    ),
                ),
                None,
                "ppcl turn_to",
                frozenset({Capability.PTU}),
            ),
            ActionSpec(
                "camera-zoom",
                "set a camera's zoom",
                (
                    ParamSpec("camera", ParamType.NUMBER, "id (0 color, 1 thermal)", None, 0, 1),
                    ParamSpec("zoom", ParamType.NUMBER, "factor", None, 1.0, 20.0),
                ),
                None,
                "ppcl zoom",
                frozenset({Capability.CAMERA}),
            ),
            ActionSpec("wait", "do nothing for a while", (_DURATION,), "duration", "", frozenset()),
            ActionSpec(
                "monitor-radiation",
                "measure the gamma dose rate for a while and estimate it at 1 m from a target",
                (ParamSpec("target", ParamType.POINT, "point"), _DURATION),
                "duration",
                "(radiation detector, /<agent>/sensors/radiation)",
                frozenset({Capability.RADIATION}),
            ),
            ActionSpec("pick-up-box", "pick a box up onto the hook", (_BOX,), None, _HOOK, _LIFT),
            ActionSpec("drop-box", "put the held box down", (_BOX, _PLACE), None, _HOOK, _LIFT),
            ActionSpec(
                "put-on-carrier",
                "put the held box onto a carrier",
                (_BOX, _PLACE),
                None,
                _HOOK,
                _LIFT,
            ),
            ActionSpec(
                "take-from-carrier", "pick a box up from a carrier", (_BOX,), None, _HOOK, _LIFT
            ),
            ActionSpec(
                "attach-carrier", "pick a carrier up onto the hook", (_CARRIER,), None, _HOOK, _LIFT
            ),
            ActionSpec(
                "detach-carrier",
                "put the held carrier down",
                (_CARRIER, _PLACE),
                None,
                _HOOK,
                _LIFT,
            ),
        )
    }
)
"""Every elementary action type, by its name in the language."""
