"""What ``world_render`` does with one camera's metadata: pair it, decide, describe the frame.

world_sim publishes, for every exposure of a camera, its ``CameraState`` (pan, tilt, zoom) and
the exposure's pose (``ground_truth/<camera>_camera_pose``, the pose the frame was exposed at,
stamped with the exposure's sim time). A :class:`CameraFeed` pairs the two by stamp and answers
with a :class:`FrameRequest`: render a new image, or repeat the previous one when the metadata
is unchanged (a frozen camera: world_sim's FREEZE fault repeats the old pose and angles with a
fresh stamp, so the frame is the old image with the new stamp, like every frozen sensor). A
dropped frame has no metadata and so no image.

An :class:`ExposurePairs` holds one agent's requests while both of its cameras have subscribers
(the saliency pipeline pairs a colour and a thermal image of one exposure time): it releases the
two requests of one stamp together, and a request whose partner never came is dropped unrendered
when a newer one of its camera arrives. A renderer that falls behind then spends its time on
pairs, instead of on halves whose partner it skipped.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from sim.sensors.camera import CAMERAS, CameraId, camera_intrinsics
from sim.sensors.camera_model import CameraPose, Intrinsics

MAX_PENDING = 16
"""Unpaired halves kept per camera (older ones are forgotten: the renderer fell behind)."""


class FrameAction(enum.Enum):
    """What to publish for one exposure."""

    RENDER = "render"
    REPEAT = "repeat"


@dataclass(frozen=True, slots=True)
class CameraMeta:
    """The CameraState half of an exposure."""

    pan: float
    tilt: float
    zoom: float


@dataclass(frozen=True, slots=True)
class FrameRequest:
    """One exposure to publish."""

    stamp_ns: int
    camera: CameraId
    pose: CameraPose
    intrinsics: Intrinsics
    meta: CameraMeta
    action: FrameAction


def pose_to_ros(pose: CameraPose) -> tuple[tuple[float, float, float], tuple[float, ...]]:
    """(position, quaternion x, y, z, w) of the optical frame in ENU."""
    quat = Rotation.from_matrix(pose.matrix()).as_quat()
    return pose.position, tuple(float(q) for q in quat)


def pose_from_ros(
    position: tuple[float, float, float], quaternion: tuple[float, float, float, float]
) -> CameraPose | None:
    """Inverse of :func:`pose_to_ros`; None for non-finite values or a quaternion far from unit."""
    values = np.asarray([*position, *quaternion], dtype=np.float64)
    if not np.all(np.isfinite(values)) or abs(np.linalg.norm(values[3:]) - 1.0) > 1e-3:
        return None
    rotation = Rotation.from_quat(values[3:]).as_matrix()
    return CameraPose.of(np.asarray(position, dtype=np.float64), rotation)


def projection_rows(intrinsics: Intrinsics) -> tuple[list[float], list[float]]:
    """CameraInfo ``k`` (3x3) and ``p`` (3x4) row-major for an undistorted pinhole camera."""
    k = [float(v) for v in intrinsics.matrix().ravel()]
    p = [k[0], 0.0, k[2], 0.0, 0.0, k[4], k[5], 0.0, 0.0, 0.0, 1.0, 0.0]
    return k, p


class CameraFeed:
    """Pairs one camera's metadata and pose messages by stamp."""

    def __init__(self, camera: CameraId) -> None:
        self.camera = camera
        self.params = CAMERAS[camera]
        self._meta: dict[int, CameraMeta] = {}
        self._poses: dict[int, CameraPose] = {}
        self._last: tuple[CameraPose, CameraMeta] | None = None

    def on_meta(self, stamp_ns: int, meta: CameraMeta) -> FrameRequest | None:
        """The CameraState of an exposure arrived; a request if its pose is there too.

        Metadata with non-finite angles or a zoom outside [0, 1] is ignored (no frame).
        """
        values = (meta.pan, meta.tilt, meta.zoom)
        if not all(math.isfinite(v) for v in values) or not 0.0 <= meta.zoom <= 1.0:
            return None
        self._meta[stamp_ns] = meta
        return self._pair(stamp_ns)

    def on_pose(self, stamp_ns: int, pose: CameraPose) -> FrameRequest | None:
        """The pose of an exposure arrived; a request if its CameraState is there too."""
        self._poses[stamp_ns] = pose
        return self._pair(stamp_ns)

    def reset(self) -> None:
        """Forget everything (the world restarted: stamps begin again at 0)."""
        self._meta.clear()
        self._poses.clear()
        self._last = None

    def _pair(self, stamp_ns: int) -> FrameRequest | None:
        for pending in (self._meta, self._poses):
            while len(pending) > MAX_PENDING:
                pending.pop(min(pending))
        if stamp_ns not in self._meta or stamp_ns not in self._poses:
            return None
        meta, pose = self._meta.pop(stamp_ns), self._poses.pop(stamp_ns)
        # halves older than a complete pair will never be completed
        for pending in (self._meta, self._poses):
            for old in [s for s in pending if s < stamp_ns]:
                del pending[old]
        action = FrameAction.REPEAT if self._last == (pose, meta) else FrameAction.RENDER
        self._last = (pose, meta)
        return FrameRequest(
            stamp_ns, self.camera, pose, camera_intrinsics(self.params, meta.zoom), meta, action
        )


class ExposurePairs:
    """One agent's colour and thermal requests, released in pairs of one stamp."""

    def __init__(self) -> None:
        self._held: dict[CameraId, FrameRequest] = {}
        self.dropped = 0
        """Requests dropped unrendered: their partner was lost (renderer behind, camera fault)."""

    def offer(self, request: FrameRequest, paired: bool) -> list[FrameRequest]:
        """The requests to render now, given one more (``paired``: both cameras are wanted)."""
        if not paired:
            self._held.pop(request.camera, None)
            return [request]
        if request.camera in self._held:
            self.dropped += 1  # superseded before its partner came
        self._held[request.camera] = request
        if len(self._held) < len(CameraId):
            return []
        stamps = {held.stamp_ns for held in self._held.values()}
        if len(stamps) > 1:
            newest = max(stamps)
            for camera in [c for c, held in self._held.items() if held.stamp_ns < newest]:
                del self._held[camera]
                self.dropped += 1
            return []
        pair = [self._held[camera] for camera in CameraId]
        self._held.clear()
        return pair

    def reset(self) -> None:
        """Forget what is held (the world restarted)."""
        self._held.clear()
