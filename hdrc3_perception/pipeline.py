"""Algorithm 4 for one colour + thermal pair (§11.1.1).

Thermal regions -> colour regions -> classifier -> geolocation -> saliency map.

:meth:`SaliencyPipeline.process` never raises on bad input: missing calibration, a wrong
encoding or size, a non-finite pose, a frame older than the last one or a frozen thermal image
(the same bytes again) give a :class:`PairStatus` with a reason, and the map is left as it was.
Camera poses come from the aircraft's own navigation solution and PTU readings in the pair.
"""

from __future__ import annotations

import enum
import hashlib
import math
from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import NDArray

from hdrc3_perception.camera import MOUNT_OFFSET, CameraPose, Intrinsics, NavPose, Vec3
from hdrc3_perception.classifier import BodyClassifier, ClassifierParams
from hdrc3_perception.geolocation import Ground, correspond, geolocate
from hdrc3_perception.saliency_map import MapParams, SaliencyMap
from hdrc3_perception.thermal import RegionVerdict, ThermalParams, find_regions

COLOR_ENCODING = "rgb8"
THERMAL_ENCODING = "mono16"


@dataclass(frozen=True, slots=True)
class CameraImage:
    """One image as the node hands it over (``sensor_msgs/Image`` + ``CameraInfo``)."""

    data: NDArray[np.generic]
    encoding: str
    intrinsics: Intrinsics | None
    """None when no (usable) CameraInfo has arrived."""


@dataclass(frozen=True, slots=True)
class FramePair:
    """A colour and a thermal image of one instant with the navigation state and PTU angles."""

    time: float
    color: CameraImage
    thermal: CameraImage
    nav: NavPose
    pan: float
    tilt: float


class PairStatus(enum.Enum):
    """Outcome of processing one pair."""

    PROCESSED = "processed"
    NO_CALIBRATION = "no_calibration"
    BAD_ENCODING = "bad_encoding"
    BAD_SIZE = "bad_size"
    BAD_POSE = "bad_pose"
    STALE = "stale"
    FROZEN = "frozen"


@dataclass(frozen=True, slots=True)
class Detection:
    """A classified region: ground point, colour pixel and classifier hits."""

    ground: tuple[float, float, float]
    color_pixel: tuple[float, float]
    hits: int


@dataclass(frozen=True, slots=True)
class PairResult:
    """What one pair gave, with per-stage counts."""

    status: PairStatus
    reason: str = ""
    warm_regions: int = 0
    candidates: int = 0
    """Regions passing the axis-ratio and size filter."""
    corresponded: int = 0
    """Candidates whose ground point lies in the colour image."""
    positives: int = 0
    added: int = 0
    merged: int = 0
    detections: tuple[Detection, ...] = ()


@dataclass(frozen=True, slots=True)
class PipelineConfig:
    """Everything the pipeline is tuned by."""

    thermal: ThermalParams = field(default_factory=ThermalParams)
    classifier: ClassifierParams = field(default_factory=ClassifierParams)
    map: MapParams = field(default_factory=MapParams)
    color_mount: Vec3 = MOUNT_OFFSET
    thermal_mount: Vec3 = MOUNT_OFFSET
    view_margin_m: float = 1.0
    """A location counts as in view (T_frame) only this far inside both images, m on the
    ground: a body nearer the border than half its length is cut by it, and the thermal step
    rejects cut regions, so such a frame could never count for T_body."""
    detect_frozen: bool = True
    """Reject a thermal image byte-identical to the previous one (a noise-free renderer of a camera
    hovering still would trip it: turn off for such streams)."""


class SaliencyPipeline:
    """Algorithm 4 over a stream of pairs; the map is :attr:`map`."""

    def __init__(self, ground: Ground, config: PipelineConfig | None = None) -> None:
        self.config = config or PipelineConfig()
        self.ground = ground
        self.classifier = BodyClassifier(self.config.classifier)
        self.map = SaliencyMap(self.config.map)
        self._last_thermal: bytes | None = None

    def process(self, pair: FramePair) -> PairResult:
        """Run Algorithm 4's loop body on one pair; bad input gives a status, never a raise."""
        problem = self._check(pair)
        if problem is not None:
            return problem
        color_k, thermal_k = pair.color.intrinsics, pair.thermal.intrinsics
        assert color_k is not None and thermal_k is not None  # _check
        cfg = self.config
        color_pose = CameraPose.of(pair.nav, pair.pan, pair.tilt, cfg.color_mount)
        thermal_pose = CameraPose.of(pair.nav, pair.pan, pair.tilt, cfg.thermal_mount)

        def range_at(u: float, v: float) -> float | None:
            point = geolocate(thermal_pose, thermal_k, u, v, self.ground)
            return None if point is None else float(np.linalg.norm(point - thermal_pose.position))

        focal = (thermal_k.fx + thermal_k.fy) / 2.0
        thermal_img = np.asarray(pair.thermal.data, dtype=np.uint16)
        regions = find_regions(thermal_img, focal, range_at, cfg.thermal)
        candidates = [r for r in regions if r.verdict is RegionVerdict.BODY]
        gray: NDArray[np.uint8] | None = None
        detections: list[Detection] = []
        corresponded = 0
        for region in candidates:
            centre = correspond(
                thermal_pose, thermal_k, color_pose, color_k, region.center, self.ground
            )
            if centre is None:
                continue
            corresponded += 1
            ends = [
                correspond(
                    thermal_pose, thermal_k, color_pose, color_k, region.axis_end(s), self.ground
                )
                for s in (-1.0, 1.0)
            ]
            if ends[0] is None or ends[1] is None:
                continue
            (u0, v0), (u1, v1) = ends[0].color_pixel, ends[1].color_pixel
            if gray is None:
                rgb = np.asarray(pair.color.data, dtype=np.uint8)
                gray = np.asarray(cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY), dtype=np.uint8)
            distance = float(np.linalg.norm(centre.ground - color_pose.position))
            hits = self.classifier.classify(
                gray,
                centre.color_pixel,
                math.atan2(v1 - v0, u1 - u0),
                (color_k.fx + color_k.fy) / 2.0 / max(distance, 1e-6),
            )
            if hits > 0:
                g = centre.ground
                detections.append(
                    Detection((float(g[0]), float(g[1]), float(g[2])), centre.color_pixel, hits)
                )

        def visible(points: NDArray[np.float64]) -> NDArray[np.bool_]:
            margin = cfg.view_margin_m
            both: NDArray[np.bool_] = color_pose.sees(color_k, points, margin) & thermal_pose.sees(
                thermal_k, points, margin
            )
            return both

        update = self.map.update(pair.time, visible, [np.array(d.ground) for d in detections])
        return PairResult(
            PairStatus.PROCESSED,
            "",
            len(regions),
            len(candidates),
            corresponded,
            len(detections),
            update.added,
            update.merged,
            tuple(detections),
        )

    def _check(self, pair: FramePair) -> PairResult | None:
        """A result for input the pipeline must not process, else None."""
        color, thermal = pair.color, pair.thermal
        if color.intrinsics is None or thermal.intrinsics is None:
            which = "colour" if color.intrinsics is None else "thermal"
            return PairResult(PairStatus.NO_CALIBRATION, f"no usable {which} camera_info")
        if color.encoding != COLOR_ENCODING or thermal.encoding != THERMAL_ENCODING:
            return PairResult(
                PairStatus.BAD_ENCODING,
                f"need {COLOR_ENCODING}/{THERMAL_ENCODING}, "
                f"got {color.encoding}/{thermal.encoding}",
            )
        if color.data.dtype != np.uint8 or thermal.data.dtype != np.uint16:
            return PairResult(
                PairStatus.BAD_ENCODING,
                f"need uint8/uint16 pixels, got {color.data.dtype}/{thermal.data.dtype}",
            )
        ck, tk = color.intrinsics, thermal.intrinsics
        shapes = (color.data.shape, thermal.data.shape)
        if shapes != ((ck.height, ck.width, 3), (tk.height, tk.width)):
            return PairResult(
                PairStatus.BAD_SIZE,
                f"images {shapes} do not match camera_info {ck.width}x{ck.height}, "
                f"{tk.width}x{tk.height}",
            )
        numbers = (pair.time, pair.pan, pair.tilt)
        if not (pair.nav.is_finite() and all(math.isfinite(v) for v in numbers)):
            return PairResult(PairStatus.BAD_POSE, "non-finite time, navigation state or PTU")
        if not pair.time > self.map.last_time:
            return PairResult(
                PairStatus.STALE, f"frame at {pair.time} s, last at {self.map.last_time} s"
            )
        if not self.config.detect_frozen:
            return None
        digest = hashlib.blake2b(np.ascontiguousarray(thermal.data).tobytes()).digest()
        if digest == self._last_thermal:
            return PairResult(PairStatus.FROZEN, "thermal image identical to the previous one")
        self._last_thermal = digest
        return None
