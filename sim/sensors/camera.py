"""Colour and thermal cameras on the PTU: zoom state, intrinsics and per-frame pose.

A frame here carries everything the renderer (``sim/render``, node ``world_render``) and the
geolocation of section 11.1.1 need: time, pose, intrinsics, PTU angles and zoom.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.airframe import PTU_MOUNT_FRD
from sim.sensors.camera_model import CameraPose, Intrinsics, camera_pose
from sim.sensors.errors import SensorError
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.ptu import PanTiltUnit
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


class CameraId(enum.Enum):
    """The two cameras of Figure 5 (values match CameraState.msg CAMERA_*)."""

    COLOR = 0
    THERMAL = 1


@dataclass(frozen=True, slots=True)
class CameraParams:
    """Optics and timing of one camera."""

    camera: CameraId
    width: int
    height: int
    hfov_wide: float
    """Horizontal field of view at zoom 0 (fully out), rad."""
    hfov_tele: float
    """Horizontal field of view at zoom 1 (fully in), rad; equal to hfov_wide for fixed optics."""
    rate_hz: float = 25.0
    zoom_rate: float = 0.33
    """Zoom travel per second (full range in ~3 s)."""
    mount_offset: tuple[float, float, float] = PTU_MOUNT_FRD
    """PTU centre relative to the centre of gravity, body FRD, m (``sim.airframe``)."""
    jitter: float = math.radians(0.1)
    """rad, 1 sigma pointing jitter of the spring-isolated platform (section 11.1.1)."""

    def __post_init__(self) -> None:
        """Reject impossible optics."""
        if self.width <= 0 or self.height <= 0:
            raise SensorError("camera resolution must be positive")
        if not (0.0 < self.hfov_tele <= self.hfov_wide < math.pi):
            raise SensorError("need 0 < hfov_tele <= hfov_wide < pi")


COLOR_CAMERA = CameraParams(CameraId.COLOR, 720, 576, math.radians(48.0), math.radians(2.0))
"""Sony FCB-780P-class CCD block camera: PAL frames, ~25x optical zoom (48 deg to 2 deg)."""

THERMAL_CAMERA = CameraParams(CameraId.THERMAL, 160, 120, math.radians(25.0), math.radians(25.0))
"""ThermalEye-3600AS-class uncooled microbolometer: 160x120, fixed lens (FOV assumed 25 deg)."""


def camera_intrinsics(params: CameraParams, zoom: float) -> Intrinsics:
    """Intrinsics of a camera at ``zoom`` (clamped to [0, 1]); focal length is linear in zoom."""
    z = min(max(zoom, 0.0), 1.0)
    f_wide = (params.width / 2.0) / math.tan(params.hfov_wide / 2.0)
    f_tele = (params.width / 2.0) / math.tan(params.hfov_tele / 2.0)
    f = f_wide + z * (f_tele - f_wide)
    return Intrinsics(params.width, params.height, f, f, params.width / 2.0, params.height / 2.0)


CAMERAS = {COLOR_CAMERA.camera: COLOR_CAMERA, THERMAL_CAMERA.camera: THERMAL_CAMERA}
"""Parameters of each camera by id."""


class ZoomStatus(enum.Enum):
    """Outcome of a zoom command."""

    ACCEPTED = "accepted"
    CLAMPED = "clamped"
    REJECTED = "rejected"


@dataclass(frozen=True, slots=True)
class CameraFrame:
    """What one frame's metadata says (``world_render`` renders the image from it)."""

    time: float
    camera: CameraId
    pose: CameraPose
    intrinsics: Intrinsics
    pan: float
    tilt: float
    zoom: float


class Camera(Sensor[CameraFrame]):
    """One camera on the PTU; fields (pan, tilt, zoom) of the rendered view for BIAS."""

    fields = ("pan", "tilt", "zoom")
    biasable = np.array([1.0, 1.0, 0.0])

    def __init__(
        self,
        params: CameraParams,
        ptu: PanTiltUnit,
        seed: int = 0,
        power: PowerManager | None = None,
    ) -> None:
        self.params = params
        self.ptu = ptu
        self.zoom = 0.0
        self.zoom_target = 0.0
        device = (
            PowerDevice.COLOR_CAMERA
            if params.camera is CameraId.COLOR
            else PowerDevice.THERMAL_CAMERA
        )
        super().__init__(
            params.camera.name.lower() + "_camera", params.rate_hz, seed, power, device
        )

    def command_zoom(self, zoom: float) -> ZoomStatus:
        """Drive the zoom towards ``zoom`` in [0, 1] (0 wide, 1 tele)."""
        if not math.isfinite(zoom):
            return ZoomStatus.REJECTED
        self.zoom_target = min(max(zoom, 0.0), 1.0)
        return ZoomStatus.ACCEPTED if self.zoom_target == zoom else ZoomStatus.CLAMPED

    def step(self, dt: float) -> None:
        """Advance the zoom motor by ``dt`` seconds."""
        if dt < 0.0 or not math.isfinite(dt):
            raise SensorError(f"camera step must be finite and >= 0, got {dt}")
        travel = self.params.zoom_rate * dt
        self.zoom += min(max(self.zoom_target - self.zoom, -travel), travel)

    def intrinsics(self, zoom: float | None = None) -> Intrinsics:
        """Intrinsics at ``zoom`` (default: current); see :func:`camera_intrinsics`."""
        return camera_intrinsics(self.params, self.zoom if zoom is None else zoom)

    def pose(
        self, truth: TruthState, pan: float | None = None, tilt: float | None = None
    ) -> CameraPose:
        """Camera pose for the aircraft ``truth`` and PTU angles (default: the PTU's)."""
        return camera_pose(
            truth,
            self.ptu.pan if pan is None else pan,
            self.ptu.tilt if tilt is None else tilt,
            self.params.mount_offset,
        )

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        jitter = scale * self.params.jitter * self.rng.standard_normal(2)
        return np.array([self.ptu.pan + jitter[0], self.ptu.tilt + jitter[1], self.zoom])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> CameraFrame:
        pan, tilt, zoom = float(value[0]), float(value[1]), float(value[2])
        return CameraFrame(
            time,
            self.params.camera,
            self.pose(truth, pan, tilt),
            self.intrinsics(zoom),
            pan,
            tilt,
            zoom,
        )
