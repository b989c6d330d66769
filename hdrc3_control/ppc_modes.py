"""Pan-tilt control modes of the PPC (chapter section 5.2): turn-to and look-at-GPS-coordinate.

Angles follow the PTU's convention (sim/sensors/ptu.py): pan about the body z axis, positive to
the right; tilt about the panned y axis, positive looking down; pan = tilt = 0 looks along the
body x axis (forward). The aircraft attitude is roll, pitch, heading (3-2-1, heading clockwise
from north); positions are local ENU metres.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_control.ppc_hardware import PtuLimits
from sim.airframe import PTU_MOUNT_FRD

Vec3 = tuple[float, float, float]

ON_TARGET_TOLERANCE = math.radians(1.0)
"""rad per axis: the PTU counts as on its set-point within this."""
PTU_MOUNT_OFFSET: Vec3 = PTU_MOUNT_FRD
"""PTU centre relative to the centre of gravity, body FRD, m (``sim.airframe``)."""


class ImageProcessing(enum.IntEnum):
    """Image processing function the PPC has engaged (ppcl_ip_*; ``ppc/image_processing``)."""

    IDLE = 0
    SALIENCY = 1
    """The saliency map pipeline of mission leg I (§11.1.1, Algorithm 4)."""
    STATE_ESTIMATION = 2
    """The landing pad's pose from the colour camera (§5.4, ``hdrc3_perception.pad_pose``)."""
    COLOR_TRACKER = 3
    """Colour tracking from a seed pixel (§6.2.3, ``hdrc3_perception.colour_tracking``)."""


class PadVision(enum.IntEnum):
    """What the PPC can do for a vision landing (latched on ``ppc/pad_vision``, §5.4).

    From the PPC's own view (:func:`pad_vision`): whether a colour camera and the landing pad's
    pose pipeline (the ``pad_node`` node) exist, which image processing function is engaged, and
    whether that pipeline has processed images lately. The PFC's landing plans on it
    (``landing.plan_landing``): it searches for the pattern only when the PPC can see it.
    """

    NONE = 0
    """No colour camera or no pad pose pipeline: no vision fix can come."""
    BUSY = 1
    """Image processing runs another function (saliency, colour tracker), engaged by PPCL."""
    READY = 2
    """Camera and pipeline are up, state estimation is not engaged: a landing engages it."""
    ENGAGED = 3
    """State estimation is engaged, but no image was processed within ``image_timeout``."""
    RUNNING = 4
    """State estimation is engaged and processes images."""

    def describe(self) -> str:
        """Why a landing can or cannot see the pad, for the operator."""
        return _PAD_VISION_TEXT[self]


_PAD_VISION_TEXT = {
    PadVision.NONE: "no vision pipeline (the PPC has no colour camera or pad pose node)",
    PadVision.BUSY: "the PPC's image processing runs another function",
    PadVision.READY: "pad state estimation ready",
    PadVision.ENGAGED: "pad state estimation engaged, no image processed yet",
    PadVision.RUNNING: "pad state estimation running",
}

CAN_SEE_PAD = frozenset({PadVision.READY, PadVision.ENGAGED, PadVision.RUNNING})
"""States in which a landing may search for the pattern."""


def pad_vision(
    camera: bool, pipeline: bool, function: ImageProcessing, image_age: float, timeout: float
) -> PadVision:
    """The PPC's :class:`PadVision` state.

    Args:
        camera: A colour camera publishes images (its image topic has a publisher).
        pipeline: The pad pose pipeline is up (its result topic has a publisher).
        function: The engaged image processing function.
        image_age: Seconds since the pipeline last reported a processed image (inf: never
            since it was engaged).
        timeout: Images older than this no longer count as running, s.
    """
    if not (camera and pipeline):
        return PadVision.NONE
    if function is ImageProcessing.IDLE:
        return PadVision.READY
    if function is not ImageProcessing.STATE_ESTIMATION:
        return PadVision.BUSY
    return PadVision.RUNNING if image_age <= timeout else PadVision.ENGAGED


class PtuMode(enum.Enum):
    """Active pan-tilt control mode (ppcl_ptu_activity_info)."""

    IDLE = "idle"
    TURN_TO = "turn_to"
    LOOK_AT = "look_at"


@dataclass(frozen=True, slots=True)
class Pose:
    """Aircraft pose: ENU position (m) and attitude (rad)."""

    position: Vec3
    roll: float
    pitch: float
    heading: float


def _ned_to_body(v: Vec3, roll: float, pitch: float, yaw: float) -> Vec3:
    """Rotate a NED vector into body FRD axes (inverse of the 3-2-1 body-to-NED rotation)."""
    n, e, d = v
    cy, sy = math.cos(yaw), math.sin(yaw)
    x1, y1, z1 = cy * n + sy * e, -sy * n + cy * e, d
    cp, sp = math.cos(pitch), math.sin(pitch)
    x2, y2, z2 = cp * x1 - sp * z1, y1, sp * x1 + cp * z1
    cr, sr = math.cos(roll), math.sin(roll)
    return (x2, cr * y2 + sr * z2, -sr * y2 + cr * z2)


def _body_to_ned(v: Vec3, roll: float, pitch: float, yaw: float) -> Vec3:
    x, y, z = v
    cr, sr = math.cos(roll), math.sin(roll)
    x1, y1, z1 = x, cr * y - sr * z, sr * y + cr * z
    cp, sp = math.cos(pitch), math.sin(pitch)
    x2, y2, z2 = cp * x1 + sp * z1, y1, -sp * x1 + cp * z1
    cy, sy = math.cos(yaw), math.sin(yaw)
    return (cy * x2 - sy * y2, sy * x2 + cy * y2, z2)


def look_at_angles(pose: Pose, target: Vec3, mount: Vec3 = PTU_MOUNT_OFFSET) -> tuple[float, float]:
    """Pan and tilt (rad) that point the camera at an ENU ``target`` from ``pose``."""
    mn, me, md = _body_to_ned(mount, pose.roll, pose.pitch, pose.heading)
    east = pose.position[0] + me
    north = pose.position[1] + mn
    up = pose.position[2] - md
    d_ned = (target[1] - north, target[0] - east, -(target[2] - up))
    x, y, z = _ned_to_body(d_ned, pose.roll, pose.pitch, pose.heading)
    return math.atan2(y, x), math.atan2(z, math.hypot(x, y))


def clamp(limits: PtuLimits, pan: float, tilt: float) -> tuple[float, float]:
    """Nearest settable angles."""
    return (
        min(max(pan, limits.min_pan), limits.max_pan),
        min(max(tilt, limits.min_tilt), limits.max_tilt),
    )


def on_target(measured: tuple[float, float], target: tuple[float, float]) -> bool:
    """Both axes within :data:`ON_TARGET_TOLERANCE` of the set-point."""
    return (
        abs(measured[0] - target[0]) <= ON_TARGET_TOLERANCE
        and abs(measured[1] - target[1]) <= ON_TARGET_TOLERANCE
    )


class PtuController:
    """The pan-tilt mode in force and its current set-point (reset()/update() style)."""

    def __init__(self, limits: PtuLimits | None = None) -> None:
        self.limits = limits or PtuLimits()
        self.mode = PtuMode.IDLE
        self.angles: tuple[float, float] | None = None
        self.point: Vec3 | None = None
        self.setpoint: tuple[float, float] | None = None
        self.reachable = True

    def reset(self) -> None:
        """Back to idle: no set-point (the PTU holds where it is)."""
        self.mode = PtuMode.IDLE
        self.angles = self.point = self.setpoint = None
        self.reachable = True

    def turn_to(self, pan: float, tilt: float) -> None:
        """Engage the turn-to mode (PTU axis angles)."""
        self.mode, self.angles, self.point = PtuMode.TURN_TO, (pan, tilt), None

    def look_at(self, target: Vec3) -> None:
        """Engage the look-at mode (ENU point)."""
        self.mode, self.point, self.angles = PtuMode.LOOK_AT, target, None

    def update(self, pose: Pose | None) -> tuple[float, float] | None:
        """Set-point for this iteration (None when idle, or look-at without a pose)."""
        if self.mode is PtuMode.TURN_TO and self.angles is not None:
            self.setpoint = clamp(self.limits, *self.angles)
        elif self.mode is PtuMode.LOOK_AT and self.point is not None and pose is not None:
            raw = look_at_angles(pose, self.point)
            self.setpoint = clamp(self.limits, *raw)
            self.reachable = self.setpoint == raw
        elif self.mode is PtuMode.IDLE:
            self.setpoint = None
        return self.setpoint
