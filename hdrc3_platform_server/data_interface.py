"""The Data Interface (chapter section 6.2.4): helicopter and camera state at 25 Hz of sim time.

Field names are exactly the chapter's; :meth:`HelicopterStateData.as_dict` is what
``hdrc3 state`` prints. :class:`RateGate` decides from the data's own sim-time stamps when the
next 25 Hz sample is due, so the rate holds at any simulation speed.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.platform_status import CameraSample, PfcSample

DI_RATE_HZ = 25.0

HELICOPTER_FIELDS = (
    "altitude",
    "latitude",
    "longitude",
    "velocity_north",
    "velocity_east",
    "velocity_up",
    "pitch",
    "roll",
    "heading",
    "rpm",
    "on_ground_flag",
    "auto_flag",
    "drc_minus_pfc_time",
    "ppc_minus_pfc_time",
    "power_status",
    "pfc_time",
    "failsafe",
    "failsafe_reason",
)
CAMERA_FIELDS = ("id", "pan", "tilt", "zoom", "ipc_time")


@dataclass(frozen=True, slots=True)
class HelicopterStateData:
    """§6.2.4 helicopter state (degrees for lat/lon, metres, m/s, radians, seconds)."""

    altitude: float
    latitude: float
    longitude: float
    velocity_north: float
    velocity_east: float
    velocity_up: float
    pitch: float
    roll: float
    heading: float
    rpm: float
    on_ground_flag: bool
    auto_flag: bool
    drc_minus_pfc_time: float
    ppc_minus_pfc_time: float
    power_status: int
    pfc_time: float
    failsafe: int = 0
    """HelicopterState.FAILSAFE_*: the PFC's navigation failsafe (issue 21; not in §6.2.4)."""
    failsafe_reason: str = ""

    def as_dict(self) -> dict[str, Any]:
        """The fields by their chapter names."""
        return asdict(self)


@dataclass(frozen=True, slots=True)
class CameraStateData:
    """§6.2.4 camera state."""

    id: int
    pan: float
    tilt: float
    zoom: float
    ipc_time: float

    def as_dict(self) -> dict[str, Any]:
        """The fields by their chapter names."""
        return asdict(self)


def helicopter_state(
    sample: PfcSample,
    frame: WorldFrame,
    drc_time: float,
    ppc_time: float | None,
    power_status: int,
) -> HelicopterStateData:
    """Convert one PFC report; WGS84 from the PFC, or from its ENU position if it sent none."""
    lat, lon, alt = sample.latitude, sample.longitude, sample.altitude
    if lat == 0.0 and lon == 0.0 and alt == 0.0:
        lon, lat, alt = frame.to_wgs84(*sample.position_enu)
    ve, vn, vu = sample.velocity_enu
    return HelicopterStateData(
        altitude=alt,
        latitude=lat,
        longitude=lon,
        velocity_north=vn,
        velocity_east=ve,
        velocity_up=vu,
        pitch=sample.pitch,
        roll=sample.roll,
        heading=sample.heading % math.tau,
        rpm=sample.rpm,
        on_ground_flag=sample.on_ground,
        auto_flag=sample.auto_flag,
        drc_minus_pfc_time=drc_time - sample.pfc_time,
        ppc_minus_pfc_time=0.0 if ppc_time is None else ppc_time - sample.pfc_time,
        power_status=power_status or sample.power_status,
        pfc_time=sample.pfc_time,
        failsafe=sample.failsafe,
        failsafe_reason=sample.failsafe_reason,
    )


def camera_state(sample: CameraSample) -> CameraStateData:
    """Convert one PPC camera report."""
    return CameraStateData(sample.camera_id, sample.pan, sample.tilt, sample.zoom, sample.ipc_time)


class RateGate:
    """Lets one sample through per period of the samples' own time stamps."""

    def __init__(self, rate_hz: float = DI_RATE_HZ) -> None:
        if not (math.isfinite(rate_hz) and rate_hz > 0.0):
            raise ValueError(f"rate must be > 0, got {rate_hz}")
        self.period = 1.0 / rate_hz
        self._next: float | None = None

    def reset(self) -> None:
        """Forget the schedule (e.g. after a simulation reset)."""
        self._next = None

    def due(self, t: float) -> bool:
        """True if a sample stamped ``t`` is to be published; advances the schedule."""
        eps = 1e-6 * self.period
        if self._next is None or t < self._next - 2.0 * self.period:
            self._next = math.floor(t / self.period + eps) * self.period
        if t + eps < self._next:
            return False
        self._next = (math.floor(t / self.period + eps) + 1) * self.period
        return True
