"""Argument limits of FCL and PPCL commands and their checks (the "bad input" rules).

Every check returns None when the arguments are fine, otherwise a readable reason; the command
layer answers FCL_NOT_ACCEPTED / PPCL_NOT_ACCEPTED with that reason.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from hdrc3_control.ppc_hardware import (
    CAMERAS,
    LASER_ANGULAR_RESOLUTIONS,
    LASER_DISTANCE_RESOLUTIONS,
    LASER_MAX_ROTATION_SPEED,
    SHUTTER_RANGE,
    PtuLimits,
)
from hdrc3_platform_server.geo_frame import WorldFrame


@dataclass(frozen=True)
class FlightLimits:
    """The flight envelope the FCL accepts (RMAX: ~20 m/s cruise at most)."""

    max_velocity: float = 20.0
    """m/s."""
    min_velocity: float = 0.2
    """m/s; slower cruise velocities are refused (a path would never finish)."""
    min_clearance: float = 2.0
    """m above the terrain below the target."""
    max_height: float = 150.0
    """m above the terrain below the target (ceiling)."""
    max_segment_length: float = 5000.0
    """m between the start and end point of one traj3d segment."""


@dataclass(frozen=True)
class Limits:
    """All limits the command layer checks."""

    flight: FlightLimits = field(default_factory=FlightLimits)
    ptu: PtuLimits = field(default_factory=PtuLimits)


HEADING_LIMIT = math.tau
"""rad: headings and rotation angles are accepted within +-one turn (+-360 deg)."""
ALTITUDE_SPAN = 10_000.0
"""m: an altitude (WGS84) is refused more than this far above or below the world's origin."""
MAX_OWNER_LENGTH = 64
"""characters of a PPCL resource owner name."""


def shown(value: float, decimals: int = 1) -> str:
    """A number for a reason: fixed-point, or 4 significant digits beyond a million.

    (``f"{1e308:.1f}"`` prints 310 digits.)
    """
    return f"{value:.{decimals}f}" if abs(value) < 1e6 else f"{value:.4g}"


def finite(**values: float) -> str | None:
    """Reason if any value is NaN or infinite."""
    for name, value in values.items():
        if not math.isfinite(value):
            return f"{name} must be a finite number, got {value}"
    return None


def arguments(
    label: str, names: Sequence[str], args: Sequence[float]
) -> tuple[tuple[float, ...], str | None]:
    """The arguments as finite floats, or a reason (wrong count, not numbers, NaN/inf).

    Runs before any command-specific check, so that none of them ever converts an infinite or
    NaN value (``int(inf)`` raises).
    """
    if len(args) != len(names):
        return (), f"{label} takes {len(names)} argument(s), got {len(args)}"
    try:
        values = tuple(float(x) for x in args)
    except (TypeError, ValueError) as exc:  # not numbers
        return (), f"bad arguments: {exc}"
    return values, finite(**dict(zip(names, values, strict=True)))


def angle(name: str, value: float) -> str | None:
    """A heading or rotation angle within +-one turn."""
    bad = finite(**{name: value})
    if bad:
        return bad
    if abs(value) > HEADING_LIMIT:
        return f"{name} {value:g} rad outside [-2 pi, 2 pi] rad (+-360 deg)"
    return None


def flag(name: str, value: float) -> str | None:
    """A boolean carried as a number: exactly 0 or 1."""
    if value not in (0.0, 1.0):
        return f"{name} must be 0 or 1, got {value:g}"
    return None


def owner(name: str, *, required: bool) -> str | None:
    """A resource owner name: not longer than MAX_OWNER_LENGTH, not blank when ``required``."""
    if required and not name.strip():
        return "an owner name is required"
    if len(name) > MAX_OWNER_LENGTH:
        return f"owner name of {len(name)} characters; at most {MAX_OWNER_LENGTH}"
    return None


def velocity(limits: FlightLimits, value: float, name: str = "velocity") -> str | None:
    """Cruise velocity within the envelope."""
    bad = finite(**{name: value})
    if bad:
        return bad
    if not limits.min_velocity <= value <= limits.max_velocity:
        return (
            f"{name} {value:g} m/s outside the flight envelope "
            f"[{limits.min_velocity:g}, {limits.max_velocity:g}] m/s"
        )
    return None


def position(
    frame: WorldFrame, limits: FlightLimits, east: float, north: float, up: float, what: str
) -> str | None:
    """A target inside the world, above the terrain clearance and below the ceiling."""
    bad = finite(east=east, north=north, up=up)
    if bad:
        return bad
    if not frame.inside(east, north):
        return (
            f"{what} ({shown(east, 0)} m east, {shown(north, 0)} m north of the origin) is far "
            f"outside the world (extent {frame.bounds} m, margin {frame.margin:g} m)"
        )
    ground = frame.ground_up(east, north)
    if up < ground + limits.min_clearance:
        return (
            f"{what} altitude {shown(up + frame.altitude)} m is below the ground clearance "
            f"({ground + frame.altitude + limits.min_clearance:.1f} m: terrain + "
            f"{limits.min_clearance:g} m)"
        )
    if up > ground + limits.max_height:
        return (
            f"{what} altitude {shown(up + frame.altitude)} m is above the ceiling "
            f"({ground + frame.altitude + limits.max_height:.1f} m: terrain + "
            f"{limits.max_height:g} m)"
        )
    return None


def altitude(frame: WorldFrame, value: float, what: str = "altitude") -> str | None:
    """A WGS84 altitude within ALTITUDE_SPAN of the world's origin (checked before geodesy)."""
    bad = finite(**{what: value})
    if bad:
        return bad
    if abs(value - frame.altitude) > ALTITUDE_SPAN:
        return (
            f"{what} {value:g} m is more than {ALTITUDE_SPAN:g} m from the "
            f"world's origin altitude ({frame.altitude:g} m)"
        )
    return None


def wgs84(longitude: float, latitude: float) -> str | None:
    """Longitude/latitude that exist."""
    bad = finite(longitude=longitude, latitude=latitude)
    if bad:
        return bad
    if not (-180.0 <= longitude <= 180.0 and -90.0 <= latitude <= 90.0):
        return f"longitude {longitude:g} / latitude {latitude:g} are not WGS84 degrees"
    return None


def pan_tilt(limits: PtuLimits, pan: float, tilt: float) -> str | None:
    """Angles within the PTU's settable ranges."""
    bad = finite(pan=pan, tilt=tilt)
    if bad:
        return bad
    if not limits.contains(pan, tilt):
        return (
            f"pan {shown(math.degrees(pan))} deg / tilt {shown(math.degrees(tilt))} deg outside "
            f"the PTU limits pan [{math.degrees(limits.min_pan):.0f}, "
            f"{math.degrees(limits.max_pan):.0f}] deg, tilt [{math.degrees(limits.min_tilt):.0f}, "
            f"{math.degrees(limits.max_tilt):.0f}] deg"
        )
    return None


def camera(camera_id: float) -> str | None:
    """A camera that exists (an integral id)."""
    if not math.isfinite(camera_id) or camera_id != int(camera_id):
        return f"camera id must be an integer, got {camera_id:g}"
    if int(camera_id) not in CAMERAS:
        return f"unknown camera id {camera_id:g} (0 = color, 1 = thermal)"
    return None


def unit_interval(name: str, value: float) -> str | None:
    """A value in [0, 1] (zoom, iris)."""
    bad = finite(**{name: value})
    if bad:
        return bad
    if not 0.0 <= value <= 1.0:
        return f"{name} {value:g} outside [0, 1]"
    return None


def shutter(value: float) -> str | None:
    """An exposure time the cameras support."""
    bad = finite(shutter=value)
    if bad:
        return bad
    lo, hi = SHUTTER_RANGE
    if not lo <= value <= hi:
        return f"shutter {value:g} s outside [{lo:g}, {hi:g}] s"
    return None


def laser_angular(value: float) -> str | None:
    """One of the laser's angular resolutions."""
    if not math.isfinite(value) or value not in LASER_ANGULAR_RESOLUTIONS:
        return f"angular resolution {value:g} deg not one of {LASER_ANGULAR_RESOLUTIONS} deg"
    return None


def laser_distance(value: float) -> str | None:
    """One of the laser's distance resolutions."""
    if not math.isfinite(value) or value not in LASER_DISTANCE_RESOLUTIONS:
        return f"distance resolution {value:g} m not one of {LASER_DISTANCE_RESOLUTIONS} m"
    return None


def laser_speed(value: float) -> str | None:
    """A rotation speed the mechanism can turn."""
    bad = finite(rotation_speed=value)
    if bad:
        return bad
    if abs(value) > LASER_MAX_ROTATION_SPEED:
        return f"rotation speed {value:g} rad/s beyond +-{LASER_MAX_ROTATION_SPEED:.3f} rad/s"
    return None


def pixel(x: float, y: float) -> str | None:
    """A point inside the color image."""
    bad = finite(x=x, y=y)
    if bad:
        return bad
    spec = CAMERAS[0]
    if not (0.0 <= x < spec.width and 0.0 <= y < spec.height):
        return f"pixel ({x:g}, {y:g}) outside the {spec.width}x{spec.height} color image"
    return None
