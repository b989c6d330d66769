"""What the PPC knows about its payload hardware: PTU limits, cameras, laser settings.

The values describe the simulated RMAX payload (the chapter gives no PTU limits; see
sim/sensors/ptu.py, camera.py and laser.py for their sources). The PPC and the Platform Server
both read them from here so that limits the server answers are the ones the PPC enforces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError


@dataclass(frozen=True, slots=True)
class PtuLimits:
    """Settable pan-tilt ranges (rad) and slew rates (rad/s)."""

    min_pan: float = math.radians(-170.0)
    max_pan: float = math.radians(170.0)
    min_tilt: float = math.radians(-10.0)
    max_tilt: float = math.radians(95.0)
    pan_rate: float = math.radians(60.0)
    tilt_rate: float = math.radians(60.0)

    def __post_init__(self) -> None:
        """Reject inverted ranges."""
        if not (self.min_pan < self.max_pan and self.min_tilt < self.max_tilt):
            raise ConfigError("PTU limits must satisfy min < max")

    def contains(self, pan: float, tilt: float) -> bool:
        """True if both angles are settable."""
        return self.min_pan <= pan <= self.max_pan and self.min_tilt <= tilt <= self.max_tilt


@dataclass(frozen=True, slots=True)
class CameraSpec:
    """Optics of one camera: resolution and horizontal field of view at zoom 0 and 1."""

    camera_id: int
    width: int
    height: int
    hfov_wide: float
    hfov_tele: float

    def focal(self, zoom: float) -> float:
        """Focal length in pixels at ``zoom`` (linear in zoom between wide and tele)."""
        z = min(max(zoom, 0.0), 1.0)
        f_wide = (self.width / 2.0) / math.tan(self.hfov_wide / 2.0)
        f_tele = (self.width / 2.0) / math.tan(self.hfov_tele / 2.0)
        return f_wide + z * (f_tele - f_wide)

    def hfov(self, zoom: float) -> float:
        """Horizontal field of view (rad) at ``zoom``."""
        return 2.0 * math.atan((self.width / 2.0) / self.focal(zoom))

    def vfov(self, zoom: float) -> float:
        """Vertical field of view (rad) at ``zoom`` (square pixels: the image's shorter side)."""
        return 2.0 * math.atan((self.height / 2.0) / self.focal(zoom))


COLOR = CameraSpec(0, 720, 576, math.radians(48.0), math.radians(2.0))
THERMAL = CameraSpec(1, 160, 120, math.radians(25.0), math.radians(25.0))
CAMERAS: dict[int, CameraSpec] = {COLOR.camera_id: COLOR, THERMAL.camera_id: THERMAL}

LASER_ANGULAR_RESOLUTIONS = (0.25, 0.5, 1.0)
"""deg, the LMS-291's selectable angular resolutions."""
LASER_DISTANCE_RESOLUTIONS = (0.001, 0.01)
"""m: 1 mm (8 m range) or 1 cm (80 m range)."""
LASER_MAX_ROTATION_SPEED = math.pi
"""rad/s of the rotation mechanism."""
SHUTTER_RANGE = (1e-4, 0.04)
"""s, settable exposure times."""
