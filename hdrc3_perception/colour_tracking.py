"""Colour tracking of a moving object from a seed pixel (chapter §6.1, §6.2.3).

§6.1 lists "vision-based object tracking: provides an estimate of the relative position to a
moving object based on the color ... image streams", used by the reactive car-following mode;
§6.2.3's PPCL command ``ppcl_ip_color_tracker(x, y)`` gives the "coordinates of a center of a
object to track". This module is that function's pure core:

- :meth:`ColourTracker.seed` learns the target's colour from the region around the seed pixel:
  the median hue, saturation and value of a small window say whether the pixel has a usable
  colour at all (grey or dark pixels have no stable hue: refused), then the pixels of that hue
  connected to the seed (a flood fill by ``cv2.inRange`` + ``cv2.connectedComponentsWithStats``)
  form the region; its circular hue mean and spread and its low saturation/value percentiles
  become the :class:`ColourModel`. A region larger than a fraction of the image (a field, a
  lawn, the sky) is no object and is refused too.
- :meth:`ColourTracker.update` thresholds each image with the model (``cv2.cvtColor`` to HSV
  after a median blur against sensor noise; one or two ``cv2.inRange`` hue intervals, two when
  the hue interval crosses 0/180 as red does), cleans the mask (``cv2.morphologyEx``: open
  removes speckle, close fills the target's highlights and dark parts) and takes the connected
  components as candidates. The candidate nearest the constant-velocity prediction is the target
  if it lies within a gate (a multiple of the target's size, widening with every image it was
  not found in) and its area is within a factor of the last one; otherwise the target is
  ``LOST`` and the prediction coasts, clamped to the image, so a target that comes back where it
  left or where it was heading is found again. With the camera's orientation at each image
  (:class:`CameraView`: the PTU servoes on the target, the helicopter turns) the prediction is
  made in the world: the target's direction and its smoothed rate of change, projected into the
  new image, so the camera's own motion does not look like the target's. Without it, the
  smoothed image velocity of the last detections predicts.

Why these pieces and not ``cv2.calcBackProject`` + ``cv2.CamShift``: CamShift climbs the
back-projection from the last window and always returns some window, so it neither says when the
target is gone nor chooses between two blobs of the colour; explicit components give every
candidate with its area and box, which the gate and the LOST status need. The colour model is not
adapted after the seed, so it cannot drift onto the background.

:func:`locate` turns a tracked pixel into the optical-frame direction
(:meth:`camera.Intrinsics.direction`) and the ground point (camera pose from the aircraft's own
navigation solution and the PTU, :class:`camera.CameraPose`; ray onto the terrain,
:func:`geolocation.geolocate`), as the saliency pipeline locates bodies.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from hdrc3_perception.camera import MOUNT_OFFSET, CameraPose, Intrinsics, NavPose, Vec3
from hdrc3_perception.geolocation import Ground, geolocate

HUE_RANGE = 180
"""OpenCV's 8-bit hue runs over 0..179 (degrees / 2)."""
NAN = math.nan
Box = tuple[int, int, int, int]
"""Pixel box: left column, top row, width, height."""


class TrackStatus(enum.IntEnum):
    """The tracker's answer for one image (values of ``ColorTrack.STATUS_*``)."""

    TRACKING = 1
    LOST = 2
    BAD_SEED = 3


@dataclass(frozen=True, slots=True)
class TrackerConfig:
    """Thresholds of the seed and of the tracking (hue in OpenCV units 0..179, s/v 0..255)."""

    blur: int = 5
    """Median blur kernel (odd) before the conversion to HSV."""
    seed_window: int = 2
    """Half size of the window around the seed whose median is the seed's colour."""
    min_saturation: int = 60
    """Below this saturation a pixel is grey: its hue is noise."""
    min_value: int = 40
    """Below this value a pixel is too dark for its hue to mean anything."""
    grow_hue_tol: int = 10
    """Hue tolerance when growing the seed region."""
    hue_tol: tuple[int, int] = (6, 18)
    """Bounds of the learned hue tolerance."""
    hue_sigmas: float = 3.0
    """Learned hue tolerance in standard deviations of the region's hue."""
    sv_keep: float = 0.6
    """Learned saturation/value floors: this fraction of the region's 2nd percentile (shade
    lowers the value and, with noise, the saturation of the same paint)."""
    min_area: int = 12
    """Pixels: smaller regions are noise."""
    max_area_fraction: float = 0.2
    """A seed region above this fraction of the image is no object (a field, the sky)."""
    min_gate_px: float = 40.0
    gate_sizes: float = 1.5
    """Gate radius in diagonals of the target's last box (at least ``min_gate_px``)."""
    gate_growth_px: float = 8.0
    """Gate widening per image in which the target was not found."""
    max_gate_fraction: float = 0.25
    """Largest gate radius, as a fraction of the image diagonal."""
    area_ratio: float = 4.0
    """A candidate's area must be within this factor of the target's last area."""
    coast_images: int = 10
    """Images the prediction keeps moving with the last velocity while the target is lost
    (then it stays where it got to; the gate keeps growing)."""
    velocity_gain: float = 0.4
    """Weight of the newest image-to-image velocity in the smoothed one: a pixel of jitter
    over one image period is tens of px/s, and a camera that servoes on the target keeps
    its real image velocity small."""
    max_image_speed: float = 400.0
    """Bound on the smoothed image velocity, px/s (the PTU's swing is not the target's)."""
    search_images: int = 12
    """After this many images without the target, the nearest region of its colour and size
    anywhere in the image is taken: the PTU holds its pointing for a while after a loss, so a
    target that is still there is still in view, wherever the predictions went."""


@dataclass(frozen=True, slots=True)
class TrackResult:
    """The tracker's answer: status, the target's centre pixel, area and box, and why."""

    status: TrackStatus
    reason: str = ""
    x: float = NAN
    """Column of the region's centroid (NaN unless tracking)."""
    y: float = NAN
    """Row of the region's centroid (NaN unless tracking)."""
    area: float = 0.0
    """Pixels of the region."""
    bbox: Box = (0, 0, 0, 0)


@dataclass(frozen=True, slots=True)
class ColourModel:
    """The target's colour: a hue interval (wrapping at 0/180) and saturation/value floors."""

    hue: int
    hue_tol: int
    sat_min: int
    val_min: int

    def intervals(self) -> list[tuple[int, int]]:
        """Inclusive hue intervals: two when the interval crosses 0/180 (red)."""
        lo, hi = self.hue - self.hue_tol, self.hue + self.hue_tol
        if lo < 0:
            return [(0, hi), (HUE_RANGE + lo, HUE_RANGE - 1)]
        if hi >= HUE_RANGE:
            return [(lo, HUE_RANGE - 1), (0, hi - HUE_RANGE)]
        return [(lo, hi)]

    def mask(self, hsv: NDArray[np.uint8]) -> NDArray[np.uint8]:
        """255 where an HSV image has this colour."""
        out: NDArray[np.uint8] = np.zeros(hsv.shape[:2], dtype=np.uint8)
        for lo, hi in self.intervals():
            band = cv2.inRange(hsv, (lo, self.sat_min, self.val_min), (hi, 255, 255))
            out = np.asarray(cv2.bitwise_or(out, band), dtype=np.uint8)
        return out

    def describe(self) -> str:
        """E.g. ``hue 2+-8 (deg 4+-16), s>=90, v>=60``."""
        return (
            f"hue {self.hue}+-{self.hue_tol} (deg {2 * self.hue}+-{2 * self.hue_tol}), "
            f"s>={self.sat_min}, v>={self.val_min}"
        )


@dataclass(frozen=True, slots=True)
class _Region:
    x: float
    y: float
    area: int
    bbox: Box

    @property
    def diagonal(self) -> float:
        return math.hypot(self.bbox[2], self.bbox[3])


@dataclass(frozen=True, slots=True)
class CameraView:
    """The camera an image was taken with: its calibration and its pose in the world."""

    intrinsics: Intrinsics
    pose: CameraPose

    @staticmethod
    def of(intrinsics: Intrinsics, pose: CameraPose) -> CameraView:
        """The view of a camera pose."""
        return CameraView(intrinsics, pose)

    @staticmethod
    def at(
        intrinsics: Intrinsics,
        nav: NavPose | None,
        ptu: tuple[float, float] | None,
        mount: Vec3 = MOUNT_OFFSET,
    ) -> CameraView | str:
        """The camera on the PTU at an image's time, or why it is unknown.

        Args:
            intrinsics: The colour camera's calibration.
            nav: The aircraft's navigation solution at the image's time (None if unknown).
            ptu: (pan, tilt) at the image's time, rad (None if unknown).
            mount: The camera's mount point on the airframe (body FRD, m).
        """
        if nav is None or not nav.is_finite():
            return "no finite helicopter_state at the image's time"
        if ptu is None or not all(math.isfinite(a) for a in ptu):
            return "no PTU reading at the image's time"
        return CameraView(intrinsics, CameraPose.of(nav, ptu[0], ptu[1], mount))

    def direction(self, u: float, v: float) -> NDArray[np.float64]:
        """World unit vector through pixel (u, v)."""
        return self.pose.ray(self.intrinsics, u, v)

    def pixel(self, direction: NDArray[np.float64]) -> tuple[float, float] | None:
        """Where a world direction appears in the image (None behind the camera)."""
        point = self.pose.position + direction
        u, v = self.pose.project(self.intrinsics, point[None, :])[0]
        return None if math.isnan(u) else (float(u), float(v))


@dataclass(slots=True)
class _Track:
    """The bounded state of one target: its last detection, velocity and misses."""

    time: float
    x: float
    y: float
    vx: float
    vy: float
    area: int
    diagonal: float
    misses: int = 0
    direction: NDArray[np.float64] | None = None
    """World direction of the last detection (with a :class:`CameraView`)."""
    rate: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    """Smoothed change of ``direction`` per second."""


def image_problem(image: object) -> str | None:
    """Why ``image`` is no RGB image (H x W x 3, uint8), or None."""
    if not isinstance(image, np.ndarray):
        return f"not an array but {type(image).__name__}"
    if image.ndim != 3 or image.shape[2] != 3 or image.shape[0] < 1 or image.shape[1] < 1:
        return f"shape {image.shape}: not rows x columns x 3"
    if image.dtype != np.uint8:
        return f"dtype {image.dtype}: not uint8"
    return None


def hue_statistics(hues: NDArray[np.uint8]) -> tuple[int, float]:
    """Circular mean (0..179) and standard deviation (hue units) of OpenCV hues."""
    angles = hues.astype(np.float64) * (2.0 * math.pi / HUE_RANGE)
    mean = math.atan2(float(np.sin(angles).mean()), float(np.cos(angles).mean()))
    centre = round(mean * HUE_RANGE / (2.0 * math.pi)) % HUE_RANGE
    offsets = (hues.astype(np.float64) - centre + HUE_RANGE / 2) % HUE_RANGE - HUE_RANGE / 2
    return centre, float(np.sqrt(np.mean(offsets**2)))


class ColourTracker:
    """Follows one coloured object through an image stream from a seed pixel."""

    def __init__(self, config: TrackerConfig | None = None) -> None:
        """A tracker without a target (:meth:`seed` gives it one)."""
        self.config = config or TrackerConfig()
        self._model: ColourModel | None = None
        self._track: _Track | None = None
        self._refusal: TrackResult | None = None
        self._images = 0

    @property
    def model(self) -> ColourModel | None:
        """The target's colour, learned at the seed (None without an accepted seed)."""
        return self._model

    def reset(self) -> None:
        """Forget the target."""
        self._model = None
        self._track = None
        self._refusal = None
        self._images = 0

    def _time(self, time: float | None) -> float:
        self._images += 1
        return float(self._images) if time is None else time

    def _hsv(self, image: NDArray[np.uint8]) -> NDArray[np.uint8]:
        k = self.config.blur
        smooth = cv2.medianBlur(np.ascontiguousarray(image), k) if k > 1 else image
        return np.asarray(cv2.cvtColor(smooth, cv2.COLOR_RGB2HSV), dtype=np.uint8)

    @staticmethod
    def _clean(mask: NDArray[np.uint8]) -> NDArray[np.uint8]:
        opened = cv2.morphologyEx(mask, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
        closed = cv2.morphologyEx(opened, cv2.MORPH_CLOSE, np.ones((5, 5), np.uint8))
        return np.asarray(closed, dtype=np.uint8)

    def seed(
        self,
        x: float,
        y: float,
        image_rgb: NDArray[np.uint8],
        time: float | None = None,
        view: CameraView | None = None,
    ) -> TrackResult:
        """Start tracking the object whose centre is near pixel (x, y) of ``image_rgb``.

        A refused seed (``BAD_SEED``) leaves the tracker without a target; :meth:`update`
        repeats the refusal until the next seed.

        Args:
            x: Column of the seed pixel.
            y: Row of the seed pixel.
            image_rgb: The image the seed refers to (rows x columns x 3, uint8, RGB).
            time: The image's time (s); None counts images instead.
            view: The camera the image was taken with (None: predict in the image).
        """
        self.reset()
        result = self._seed(x, y, image_rgb, time, view)
        if result.status is TrackStatus.BAD_SEED:
            self._model, self._track, self._refusal = None, None, result
        return result

    def _seed(
        self,
        x: float,
        y: float,
        image: NDArray[np.uint8],
        time: float | None,
        view: CameraView | None,
    ) -> TrackResult:
        cfg = self.config
        problem = image_problem(image)
        if problem is not None:
            return TrackResult(TrackStatus.BAD_SEED, f"bad image: {problem}")
        if time is not None and not math.isfinite(time):
            return TrackResult(TrackStatus.BAD_SEED, f"time {time} is not finite")
        rows, cols = image.shape[:2]
        if not (math.isfinite(x) and math.isfinite(y) and 0 <= x < cols and 0 <= y < rows):
            return TrackResult(
                TrackStatus.BAD_SEED, f"seed ({x}, {y}) is outside the {cols} x {rows} image"
            )
        col, row = int(x), int(y)
        hsv = self._hsv(image)
        w = cfg.seed_window
        window = hsv[max(0, row - w) : row + w + 1, max(0, col - w) : col + w + 1].reshape(-1, 3)
        hue, _ = hue_statistics(window[:, 0])
        sat, val = (int(np.median(window[:, i])) for i in (1, 2))
        where = f"seed ({x:.0f}, {y:.0f})"
        if val < cfg.min_value:
            return TrackResult(
                TrackStatus.BAD_SEED,
                f"{where} is too dark (value {val} < {cfg.min_value}): no colour to track",
            )
        if sat < cfg.min_saturation:
            return TrackResult(
                TrackStatus.BAD_SEED,
                f"{where} is grey (saturation {sat} < {cfg.min_saturation}): no colour to track",
            )
        grow = ColourModel(
            hue,
            cfg.grow_hue_tol,
            max(cfg.min_saturation, sat // 2),
            max(cfg.min_value, val // 2),
        )
        region = self._seed_region(grow, hsv, col, row)
        if region is None:
            return TrackResult(TrackStatus.BAD_SEED, f"{where}: no region of its colour there")
        _, labels = region
        pixels = hsv[labels]
        centre, spread = hue_statistics(pixels[:, 0])
        low, high = cfg.hue_tol
        model = ColourModel(
            centre,
            int(min(high, max(low, math.ceil(cfg.hue_sigmas * spread) + 2))),
            max(cfg.min_saturation, int(cfg.sv_keep * np.percentile(pixels[:, 1], 2))),
            max(cfg.min_value, int(cfg.sv_keep * np.percentile(pixels[:, 2], 2))),
        )
        refined = self._seed_region(model, hsv, col, row)
        if refined is None:
            return TrackResult(TrackStatus.BAD_SEED, f"{where}: no region of its colour there")
        found, _ = refined
        if found.area < cfg.min_area:
            return TrackResult(
                TrackStatus.BAD_SEED,
                f"{where}: its region has {found.area} pixels (< {cfg.min_area})",
            )
        fraction = found.area / float(rows * cols)
        if fraction > cfg.max_area_fraction:
            return TrackResult(
                TrackStatus.BAD_SEED,
                f"{where}: its colour region covers {100 * fraction:.0f} % of the image "
                f"(> {100 * cfg.max_area_fraction:.0f} %): background, not an object",
            )
        self._model = model
        self._track = _Track(
            self._time(time), found.x, found.y, 0.0, 0.0, found.area, found.diagonal
        )
        if view is not None:
            self._track.direction = view.direction(found.x, found.y)
        return TrackResult(
            TrackStatus.TRACKING,
            f"seeded: {model.describe()}",
            found.x,
            found.y,
            float(found.area),
            found.bbox,
        )

    def _seed_region(
        self, model: ColourModel, hsv: NDArray[np.uint8], col: int, row: int
    ) -> tuple[_Region, NDArray[np.bool_]] | None:
        """The component of ``model``'s colour at (col, row) or nearest to it in the window."""
        mask = self._clean(model.mask(hsv))
        _, labels, stats, centroids = cv2.connectedComponentsWithStats(mask, connectivity=8)
        w = self.config.seed_window + 2
        r0, c0 = max(0, row - w), max(0, col - w)
        near = labels[r0 : row + w + 1, c0 : col + w + 1]
        if labels[row, col] > 0:
            label = int(labels[row, col])
        elif near.any():
            rr, cc = np.nonzero(near)
            i = int(np.argmin((rr + r0 - row) ** 2 + (cc + c0 - col) ** 2))
            label = int(near[rr[i], cc[i]])
        else:
            return None
        return _region(stats, centroids, label), labels == label

    def update(
        self,
        image_rgb: NDArray[np.uint8],
        time: float | None = None,
        view: CameraView | None = None,
    ) -> TrackResult:
        """Find the target in the next image.

        Args:
            image_rgb: Rows x columns x 3, uint8, RGB.
            time: The image's time (s); None counts images (as :meth:`seed` must have).
            view: The camera the image was taken with (None: predict in the image).
        """
        if self._refusal is not None:
            return self._refusal
        if self._model is None or self._track is None:
            return TrackResult(TrackStatus.LOST, "no seed: ppcl_ip_color_tracker(x, y) gives one")
        problem = image_problem(image_rgb)
        if problem is not None:
            return TrackResult(TrackStatus.LOST, f"bad image: {problem}")
        if time is not None and not math.isfinite(time):
            return TrackResult(TrackStatus.LOST, f"time {time} is not finite")
        track, cfg = self._track, self.config
        now = self._time(time)
        rows, cols = image_rgb.shape[:2]
        mask = self._clean(self._model.mask(self._hsv(image_rgb)))
        count, _, stats, centroids = cv2.connectedComponentsWithStats(mask, connectivity=8)
        predictions = self._predict(now, cols, rows, view)
        px, py = predictions[0]
        gate = min(
            max(cfg.min_gate_px, cfg.gate_sizes * track.diagonal)
            + cfg.gate_growth_px * track.misses,
            cfg.max_gate_fraction * math.hypot(cols, rows),
        )
        best: _Region | None = None
        best_distance = math.inf
        sized = 0
        for label in range(1, count):
            region = _region(stats, centroids, label)
            ratio = region.area / float(track.area)
            if region.area < cfg.min_area or not 1 / cfg.area_ratio <= ratio <= cfg.area_ratio:
                continue
            sized += 1
            distance = min(math.hypot(region.x - x, region.y - y) for x, y in predictions)
            if distance < best_distance:
                best, best_distance = region, distance
        nearest: _Region | None = None
        if best is not None and best_distance > gate and track.misses < cfg.search_images:
            nearest, best = best, None
        if best is None:
            track.misses += 1
            if track.misses >= cfg.coast_images:  # stop moving the prediction
                track.x, track.y, track.vx, track.vy, track.time = px, py, 0.0, 0.0, now
                if view is not None:
                    track.direction, track.rate = view.direction(px, py), np.zeros(3)
            elsewhere = (
                f"; {sized} of its size elsewhere, the nearest at ({nearest.x:.0f},"
                f" {nearest.y:.0f})"
                if nearest is not None
                else ""
            )
            return TrackResult(
                TrackStatus.LOST,
                f"no region of the target's colour within {gate:.0f} px of ({px:.0f}, {py:.0f})"
                f" for {track.misses} image(s){elsewhere}",
            )
        gain = cfg.velocity_gain
        if now > track.time:
            track.vx += gain * ((best.x - track.x) / (now - track.time) - track.vx)
            track.vy += gain * ((best.y - track.y) / (now - track.time) - track.vy)
            speed = math.hypot(track.vx, track.vy)
            if speed > cfg.max_image_speed:
                track.vx, track.vy = (v * cfg.max_image_speed / speed for v in (track.vx, track.vy))
        if view is None:
            track.direction, track.rate = None, np.zeros(3)
        else:
            direction = view.direction(best.x, best.y)
            if track.direction is not None and now > track.time:
                seen = (direction - track.direction) / (now - track.time)
                track.rate = track.rate + gain * (seen - track.rate)
            track.direction = direction
        track.time, track.x, track.y = now, best.x, best.y
        track.area, track.diagonal, track.misses = best.area, best.diagonal, 0
        return TrackResult(
            TrackStatus.TRACKING,
            f"{best_distance:.1f} px from the prediction",
            best.x,
            best.y,
            float(best.area),
            best.bbox,
        )

    def _predict(
        self, now: float, cols: int, rows: int, view: CameraView | None
    ) -> list[tuple[float, float]]:
        """Constant-velocity predictions clamped to the image: in the world first, and the image's.

        The world's (with a view) comes first and is the one a LOST result reports. A
        candidate near either counts: the world's holds while the camera swings, the image's
        while the view's angles are off (a PTU read-out late on a loaded machine puts the
        world's prediction where the servo has just turned away from).
        """
        assert self._track is not None
        t = self._track
        dt = now - t.time
        found = [(t.x + t.vx * dt, t.y + t.vy * dt)]
        if view is not None and t.direction is not None:
            ahead = t.direction + t.rate * dt
            seen = view.pixel(ahead / np.linalg.norm(ahead))
            if seen is not None:
                found.insert(0, seen)
        return [(min(max(x, 0.0), cols - 1.0), min(max(y, 0.0), rows - 1.0)) for x, y in found]


def _region(stats: NDArray[Any], centroids: NDArray[Any], label: int) -> _Region:
    """One component of ``cv2.connectedComponentsWithStats``."""
    left, top, width, height, area = (int(v) for v in stats[label])
    return _Region(
        float(centroids[label][0]),
        float(centroids[label][1]),
        area,
        (left, top, width, height),
    )


@dataclass(frozen=True, slots=True)
class TargetFix:
    """Where a tracked pixel points: optical-frame direction and, if found, the ground point."""

    direction: NDArray[np.float64]
    """Unit vector, optical frame (x right, y down, z forward)."""
    position: NDArray[np.float64] | None
    """ENU ground point (m), None if not located."""
    reason: str = ""
    """Why not located."""


def locate(
    intrinsics: Intrinsics, u: float, v: float, view: CameraView | str, ground: Ground
) -> TargetFix:
    """Direction of pixel (u, v) and its ground point seen from ``view``.

    Args:
        intrinsics: The colour camera's calibration (the direction needs no pose).
        u: Pixel column.
        v: Pixel row.
        view: The camera at the image's time, or why it is unknown (:meth:`CameraView.at`).
        ground: The terrain the ray meets.
    """
    direction = intrinsics.direction(u, v)
    if isinstance(view, str):
        return TargetFix(direction, None, view)
    point = geolocate(view.pose, intrinsics, u, v, ground)
    if point is None:
        return TargetFix(direction, None, "the ray meets no ground")
    return TargetFix(direction, point)
