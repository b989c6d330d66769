"""SICK LMS-291 laser range finder on a continuous rotation mechanism (chapter section 11.2).

The mirror scans one plane (100 or 180 deg field of view, 0.25/0.5/1.0 deg resolution, 53/26/13
ms per scan; 1 cm resolution to 80 m or 1 mm to 8 m). The in-house mechanism turns the whole unit
about its middle beam, so a full half turn sweeps a half sphere in front of the aircraft.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.airframe import LRF_MOUNT_FRD, LRF_MOUNT_TILT, scan_rays
from sim.sensors.errors import SensorError
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState
from sim.world_geometry import WorldGeometry


class RangeMode(enum.Enum):
    """Distance modes of the LMS-291: (maximum range m, resolution m)."""

    CM_80M = (80.0, 0.01)
    MM_8M = (8.0, 0.001)

    @property
    def max_range(self) -> float:
        """Maximum range, m."""
        return self.value[0]

    @property
    def resolution(self) -> float:
        """Range resolution, m."""
        return self.value[1]


RESPONSE_TIME: dict[float, float] = {0.25: 0.053, 0.5: 0.026, 1.0: 0.013}
"""Angular resolution (deg) -> time per scan (s), section 11.2."""


class LaserConfigStatus(enum.Enum):
    """Outcome of a configuration request (PPCL sets resolutions and rotation speed)."""

    ACCEPTED = "accepted"
    REJECTED = "rejected"
    CLAMPED = "clamped"


@dataclass(frozen=True, slots=True)
class LaserConfig:
    """Scan configuration selectable in flight."""

    fov_deg: float = 180.0
    resolution_deg: float = 1.0
    range_mode: RangeMode = RangeMode.CM_80M

    def problem(self) -> str | None:
        """Why this configuration is impossible, or None."""
        if self.fov_deg not in (100.0, 180.0):
            return f"field of view must be 100 or 180 deg, got {self.fov_deg}"
        if self.resolution_deg not in RESPONSE_TIME:
            return f"angular resolution must be 0.25, 0.5 or 1.0 deg, got {self.resolution_deg}"
        if self.resolution_deg == 0.25 and self.fov_deg != 100.0:
            return "0.25 deg resolution is only available with the 100 deg field of view"
        return None

    @property
    def scan_time(self) -> float:
        """Seconds per scan."""
        return RESPONSE_TIME[self.resolution_deg]

    def beam_angles(self) -> NDArray[np.float64]:
        """Beam angles in the scan plane, rad, from -fov/2 to +fov/2."""
        count = round(self.fov_deg / self.resolution_deg) + 1
        return np.radians(np.linspace(-self.fov_deg / 2.0, self.fov_deg / 2.0, count))


@dataclass(frozen=True, slots=True)
class LaserParams:
    """Mounting and error model."""

    mount_offset: tuple[float, float, float] = LRF_MOUNT_FRD
    """Sensor centre relative to the centre of gravity, body FRD, m (front of the fuselage)."""
    mount_tilt: float = LRF_MOUNT_TILT
    """Rotation axis (middle beam) below the body x axis, rad."""
    max_rotation_speed: float = math.pi
    """rad/s of the rotation mechanism (assumed)."""
    range_noise: float = 0.01
    """m, 1 sigma statistical error (LMS-291 class: ~1 cm)."""


@dataclass(frozen=True, slots=True)
class LaserScan:
    """One scan line: ranges per beam (inf where nothing returned within range)."""

    time: float
    rotation_angle: float
    """Angle of the rotation mechanism about the middle beam, rad."""
    beam_angles: tuple[float, ...]
    ranges: tuple[float, ...]


class LaserRangeFinder(Sensor[LaserScan]):
    """LMS-291 on its rotation mechanism, ray cast against a world; fields (rotation, ranges...)."""

    fields = ("rotation_angle", "ranges")

    def __init__(
        self,
        geometry: WorldGeometry,
        params: LaserParams | None = None,
        config: LaserConfig | None = None,
        seed: int = 0,
        power: PowerManager | None = None,
    ) -> None:
        self.geometry = geometry
        self.params = params or LaserParams()
        self.config = config or LaserConfig()
        problem = self.config.problem()
        if problem is not None:
            raise SensorError(problem)
        self.rotation_angle = 0.0
        self.rotation_speed = 0.0
        super().__init__("laser", 1.0 / self.config.scan_time, seed, power, PowerDevice.LASER)

    def configure(self, config: LaserConfig) -> tuple[LaserConfigStatus, str]:
        """Switch field of view, angular resolution and range mode (scan rate follows)."""
        problem = config.problem()
        if problem is not None:
            return LaserConfigStatus.REJECTED, problem
        self.config = config
        self.rate_hz = 1.0 / config.scan_time
        self._start, self._count = None, 0  # restart the scan schedule at the new rate
        return LaserConfigStatus.ACCEPTED, ""

    def set_rotation_speed(self, speed: float) -> LaserConfigStatus:
        """Constant angular speed of the rotation mechanism, rad/s (clamped to the maximum)."""
        if not math.isfinite(speed):
            return LaserConfigStatus.REJECTED
        limit = self.params.max_rotation_speed
        self.rotation_speed = min(max(speed, -limit), limit)
        return (
            LaserConfigStatus.ACCEPTED
            if self.rotation_speed == speed
            else LaserConfigStatus.CLAMPED
        )

    def step(self, dt: float) -> None:
        """Turn the mechanism by ``dt`` seconds (only while powered)."""
        if dt < 0.0 or not math.isfinite(dt):
            raise SensorError(f"laser step must be finite and >= 0, got {dt}")
        if self.powered():
            self.rotation_angle = (self.rotation_angle + self.rotation_speed * dt) % math.tau

    def beams_enu(
        self, truth: TruthState, rotation_angle: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Sensor origin (ENU) and unit beam directions (N x 3, ENU) for a rotation angle."""
        return scan_rays(
            truth.position_enu,
            (truth.roll, truth.pitch, truth.heading),
            rotation_angle,
            self.config.beam_angles(),
            self.params.mount_offset,
            self.params.mount_tilt,
        )

    def _bias_mask(self, size: int) -> NDArray[np.float64]:
        mask = np.ones(size)
        mask[0] = 0.0
        return mask

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        mode = self.config.range_mode
        origin, directions = self.beams_enu(truth, self.rotation_angle)
        start = (float(origin[0]), float(origin[1]), float(origin[2]))
        ranges = self.geometry.ray_cast_many(start, directions, mode.max_range)
        noise = scale * self.params.range_noise * self.rng.standard_normal(len(ranges))
        ranges = np.round((ranges + noise) / mode.resolution) * mode.resolution
        return np.concatenate([[self.rotation_angle], ranges])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> LaserScan:
        beams = tuple(float(a) for a in self.config.beam_angles())
        ranges = tuple(float(r) for r in value[1:])
        return LaserScan(time, float(value[0]), beams, ranges)
