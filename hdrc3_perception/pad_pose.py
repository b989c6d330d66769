"""Pose of the landing pad from one camera image (chapter §5.4, "Vision System").

1. Black blobs with one white hole (``cv2.findContours`` two-level hierarchy on an Otsu
   threshold), an ellipse fitted to each boundary (``cv2.fitEllipse``); the hole's size over the
   blob's gives the inner ratio, which names the circle's code (:mod:`sim.landing_pattern`).
2. Triplets: three blobs of similar size about four radii apart whose codes form one of the
   pattern's code sets; the order in which they appear (counter-clockwise on the pad) names each
   corner, and the opposite order says the pattern is seen mirrored.
3. Pose: a first guess from the circle centres (``cv2.solveP3P`` for one triplet, picked by the
   ellipses; ``cv2.solvePnP`` SQPnP for more), then, as the chapter does, the reprojection error
   of the centres *and semi-axes* of the ellipses is minimised (``scipy.optimize.least_squares``).
   A circle projects to an exact conic (``H^-T Q H^-1`` with ``H = K [r1 r2 t]``), so the
   residual compares the fitted ellipse with the projected conic: its centre and the 2x2 matrix
   ``R diag(a, b) R^T`` (semi-axes and angle without an angle wrap).

The result is the pad's pose in the camera frame; :attr:`PadPose.camera_in_pad` is the camera's
position on the pad (metres, z up), which the landing mode converts with the PTU angles and the
mount offsets. Why not only ``cv2.solvePnP`` on centres: a projected circle's centre is not the
ellipse's centre (a bias of several centimetres close to the pad), and three points leave up to
four poses; the semi-axes carry the range and attitude information the chapter relies on.
"""

from __future__ import annotations

import enum
import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from hdrc3_perception.camera import Intrinsics
from sim.landing_pattern import CIRCLES, CODES, INNER_RATIOS, PadCircle, triplet_of_codes

MIN_SEMI_AXIS_PX = 4.0
"""Smaller blobs cannot tell their inner ratio (a 1 px error is a quarter of the hole)."""
RATIO_TOLERANCE = 0.06
"""Half the spacing of :data:`INNER_RATIOS`, less a margin."""
MAX_RMS_PX = 1.5
"""A pose whose ellipses are reprojected worse than this (RMS pixels) is not believed."""


class PoseStatus(enum.Enum):
    """What the image gave."""

    OK = "ok"
    BAD_IMAGE = "bad_image"  # not a 2-D 8-bit image, or no calibration
    NO_PATTERN = "no_pattern"  # no complete triplet identified
    MIRRORED = "mirrored"  # triplets found, but only in mirrored order
    NOT_CONVERGED = "not_converged"  # the refinement did not explain the ellipses


@dataclass(frozen=True, slots=True)
class Ellipse:
    """A fitted ellipse: centre (px), semi-axes a >= b (px), angle of a (rad, image frame)."""

    u: float
    v: float
    a: float
    b: float
    angle: float

    def shape(self) -> NDArray[np.float64]:
        """``R diag(a, b) R^T``: size and orientation as a symmetric 2x2 matrix."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        rot = np.array([[c, -s], [s, c]])
        shape: NDArray[np.float64] = rot @ np.diag([self.a, self.b]) @ rot.T
        return shape


@dataclass(frozen=True, slots=True)
class Blob:
    """A black circle candidate: its outer ellipse and the inner ratio of its hole."""

    outer: Ellipse
    ratio: float

    def code(self) -> int | None:
        """The index into INNER_RATIOS this blob's hole matches (None: between two)."""
        best = min(range(len(INNER_RATIOS)), key=lambda i: abs(INNER_RATIOS[i] - self.ratio))
        return best if abs(INNER_RATIOS[best] - self.ratio) <= RATIO_TOLERANCE else None


@dataclass(frozen=True, slots=True)
class PadPose:
    """The pad's pose in the camera frame, or why there is none."""

    status: PoseStatus
    reason: str = ""
    rotation: NDArray[np.float64] | None = None  # pad -> camera
    translation: NDArray[np.float64] | None = None  # pad origin in the camera frame (m)
    triplets: tuple[int, ...] = ()
    rms_px: float = math.nan
    blobs: int = 0
    matched: dict[PadCircle, Ellipse] = field(default_factory=dict)

    @property
    def camera_in_pad(self) -> NDArray[np.float64]:
        """The camera's position in the pad frame (m); only for an OK pose."""
        assert self.rotation is not None and self.translation is not None
        return -self.rotation.T @ self.translation


def _ellipse(box: tuple[Sequence[float], Sequence[float], float]) -> Ellipse:
    (u, v), (w, h), deg = box
    angle = math.radians(deg)
    if w >= h:
        return Ellipse(u, v, w / 2.0, h / 2.0, angle)
    return Ellipse(u, v, h / 2.0, w / 2.0, angle + math.pi / 2.0)


EDGE_PX = 0.3
"""Contours run through the centres of the black boundary pixels, inside the circle's edge and
outside the hole's; the axes are corrected by this much (0.3-0.5 px in theory; 0.3 fitted best
on supersampled renders, bench/pad_pose.py)."""


def _grown(e: Ellipse, by: float) -> Ellipse:
    return Ellipse(e.u, e.v, e.a + by, e.b + by, e.angle)


def find_blobs(gray: NDArray[np.uint8]) -> list[Blob]:
    """Black blobs with exactly one concentric white hole, both elliptic, off the image border."""
    height, width = gray.shape
    _, mask = cv2.threshold(gray, 0, 255, cv2.THRESH_BINARY_INV | cv2.THRESH_OTSU)
    contours, hierarchy = cv2.findContours(mask, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    if hierarchy is None:
        return []
    blobs = []
    for i, (_next, _prev, child, parent) in enumerate(hierarchy[0]):
        if parent != -1 or child == -1 or hierarchy[0][child][0] != -1:
            continue  # a hole, a blob without a hole, or one with several holes
        outer, hole = np.asarray(contours[i], np.int32), np.asarray(contours[child], np.int32)
        if len(outer) < 8 or len(hole) < 5:
            continue
        x, y, w, h = cv2.boundingRect(outer)
        if x == 0 or y == 0 or x + w == width or y + h == height:
            continue  # cut by the border (or the ground around the pad, with the pad as hole)
        out_e, in_e = _ellipse(cv2.fitEllipse(outer)), _ellipse(cv2.fitEllipse(hole))
        if out_e.b < MIN_SEMI_AXIS_PX or not _elliptic(outer, out_e):
            continue
        out_e, in_e = _grown(out_e, EDGE_PX), _grown(in_e, -EDGE_PX)
        if math.hypot(out_e.u - in_e.u, out_e.v - in_e.v) > 0.25 * out_e.b:
            continue
        blobs.append(Blob(out_e, math.sqrt((in_e.a * in_e.b) / (out_e.a * out_e.b))))
    return blobs


def _elliptic(contour: NDArray[np.int32], e: Ellipse) -> bool:
    area = cv2.contourArea(contour)
    return abs(area - math.pi * e.a * e.b) <= 0.15 * math.pi * e.a * e.b


@dataclass(frozen=True, slots=True)
class _Triplet:
    triplet: int
    corners: tuple[Blob, Blob, Blob]  # in the pattern's corner order
    mirrored: bool


def find_triplets(blobs: list[Blob]) -> list[_Triplet]:
    """Triples of blobs that are a triplet of the pattern (each blob used at most once)."""
    found: list[_Triplet] = []
    used: set[int] = set()
    candidates = [(i, b) for i, b in enumerate(blobs) if b.code() is not None]
    for (i, p), (j, q), (k, r) in itertools.combinations(candidates, 3):
        if used & {i, j, k}:
            continue
        triple = (p, q, r)
        codes = [b.code() for b in triple]
        if len(set(codes)) < 3 or not _shaped_like_a_triplet(triple):
            continue
        triplet = triplet_of_codes(frozenset(c for c in codes if c is not None))
        if triplet is None:
            continue
        ordered = tuple(triple[codes.index(c)] for c in CODES[triplet])
        a, b, c = (np.array([x.outer.u, x.outer.v]) for x in ordered)
        turn = float((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0])
        # counter-clockwise on the pad seen from above = clockwise in an image (v down) = turn < 0
        found.append(_Triplet(triplet, ordered, mirrored=turn > 0))  # type: ignore[arg-type]
        used |= {i, j, k}
    return found


def _shaped_like_a_triplet(triple: tuple[Blob, Blob, Blob]) -> bool:
    sizes = [math.sqrt(b.outer.a * b.outer.b) for b in triple]
    if max(sizes) > 1.5 * min(sizes):  # neighbouring triplets differ by 2x
        return False
    mean = sum(sizes) / 3.0
    for p, q in itertools.combinations(triple, 2):
        d = math.hypot(p.outer.u - q.outer.u, p.outer.v - q.outer.v)
        if not 2.5 * mean <= d <= 6.0 * mean:  # side = 4 radii; 60 deg off nadir: 2.8 - 5.7
            return False
    return True


def _k(intrinsics: Intrinsics) -> NDArray[np.float64]:
    return np.array(intrinsics.k(), dtype=np.float64).reshape(3, 3)


def _plane_conics(circles: Sequence[PadCircle]) -> NDArray[np.float64]:
    """The circles as 3x3 conics of the pad plane (n x 3 x 3)."""
    q = np.zeros((len(circles), 3, 3))
    for i, c in enumerate(circles):
        q[i] = [[1.0, 0.0, -c.x], [0.0, 1.0, -c.y], [-c.x, -c.y, c.x**2 + c.y**2 - c.radius**2]]
    return q


def project_circles(
    k: NDArray[np.float64],
    rotation: NDArray[np.float64],
    t: NDArray[np.float64],
    conics: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Images of pad circles: ellipse centres (n x 2, px), shape matrices (n x 2 x 2), validity.

    A row is invalid where the conic is not an ellipse in front of the camera.
    """
    h = k @ np.column_stack([rotation[:, 0], rotation[:, 1], t])
    n = len(conics)
    if abs(np.linalg.det(h)) < 1e-12:
        return np.zeros((n, 2)), np.zeros((n, 2, 2)), np.zeros(n, dtype=bool)
    h_inv = np.linalg.inv(h)
    image = np.einsum("ji,njk,kl->nil", h_inv, conics, h_inv)
    a, b, f = image[:, :2, :2], image[:, :2, 2], image[:, 2, 2]
    det = a[:, 0, 0] * a[:, 1, 1] - a[:, 0, 1] * a[:, 1, 0]
    ok = np.abs(det) > 1e-300
    det = np.where(ok, det, 1.0)
    inv_a = np.empty_like(a)
    inv_a[:, 0, 0], inv_a[:, 1, 1] = a[:, 1, 1] / det, a[:, 0, 0] / det
    inv_a[:, 0, 1], inv_a[:, 1, 0] = -a[:, 0, 1] / det, -a[:, 1, 0] / det
    centre = -np.einsum("nij,nj->ni", inv_a, b)
    scale = -np.einsum("ni,ni->n", b, centre) - f  # (x - x0)^T A (x - x0) = scale on the ellipse
    ok &= scale != 0.0
    values, vectors = np.linalg.eigh(a / np.where(ok, scale, 1.0)[:, None, None])
    ok &= np.all(values > 0.0, axis=1)
    root = 1.0 / np.sqrt(np.where(values > 0.0, values, 1.0))
    shape = np.einsum("nij,nj,nkj->nik", vectors, root, vectors)
    return centre, shape, ok


@dataclass(frozen=True, slots=True)
class _Observed:
    """The matched circles as arrays: plane conics, fitted ellipses' centres and shapes."""

    conics: NDArray[np.float64]
    centres: NDArray[np.float64]
    shapes: NDArray[np.float64]

    @staticmethod
    def of(matched: Mapping[PadCircle, Ellipse]) -> _Observed:
        return _Observed(
            _plane_conics(list(matched)),
            np.array([[e.u, e.v] for e in matched.values()]),
            np.array([e.shape() for e in matched.values()]),
        )


def _residuals(
    params: NDArray[np.float64], k: NDArray[np.float64], seen: _Observed
) -> NDArray[np.float64]:
    rotation = np.asarray(cv2.Rodrigues(params[:3])[0], dtype=np.float64)
    centre, shape, ok = project_circles(k, rotation, params[3:], seen.conics)
    diff = shape - seen.shapes
    out = np.column_stack([centre - seen.centres, diff[:, 0, 0], diff[:, 0, 1], diff[:, 1, 1]])
    out[~ok] = 1e3
    return out.ravel()


def _initial(
    k: NDArray[np.float64], matched: dict[PadCircle, Ellipse]
) -> list[NDArray[np.float64]]:
    """Candidate poses (rvec | tvec) from the ellipse centres."""
    obj = np.array([[c.x, c.y, 0.0] for c in matched])
    img = np.array([[e.u, e.v] for e in matched.values()])
    if len(matched) >= 4:
        ok, rvec, tvec = cv2.solvePnP(obj, img, k, None, flags=cv2.SOLVEPNP_SQPNP)
        return [np.concatenate([rvec.ravel(), tvec.ravel()])] if ok else []
    count, rvecs, tvecs = cv2.solveP3P(obj, img, k, None, flags=cv2.SOLVEPNP_P3P)
    return [np.concatenate([r.ravel(), t.ravel()]) for r, t in zip(rvecs, tvecs, strict=True)][
        :count
    ]


def estimate(gray: NDArray[np.generic], intrinsics: Intrinsics | None) -> PadPose:
    """The pad's pose from one grey image of a calibrated camera."""
    if intrinsics is None:
        return PadPose(PoseStatus.BAD_IMAGE, "no camera calibration")
    if gray.ndim != 2 or gray.dtype != np.uint8 or min(gray.shape) < 16:
        return PadPose(
            PoseStatus.BAD_IMAGE, f"need a 2-D uint8 image, got {gray.dtype}{gray.shape}"
        )
    blobs = find_blobs(np.ascontiguousarray(gray))
    triplets = find_triplets(blobs)
    upright = [t for t in triplets if not t.mirrored]
    if not upright:
        if triplets:
            return PadPose(PoseStatus.MIRRORED, "the triplets read clockwise", blobs=len(blobs))
        return PadPose(PoseStatus.NO_PATTERN, f"{len(blobs)} circles, no triplet", blobs=len(blobs))
    matched = {
        c: blob.outer
        for t in upright
        for c, blob in zip((c for c in CIRCLES if c.triplet == t.triplet), t.corners, strict=True)
    }
    k = _k(intrinsics)
    seen = _Observed.of(matched)
    guesses = [g for g in _initial(k, matched) if g[5] > 0.0]  # the pad in front of the camera
    best = None
    if guesses:  # P3P gives up to four: refine the one whose ellipses fit best already
        guess = min(guesses, key=lambda g: float(np.sum(_residuals(g, k, seen) ** 2)))
        best = least_squares(_residuals, guess, args=(k, seen), method="lm")
    used = tuple(sorted(t.triplet for t in upright))
    if best is None:
        return PadPose(PoseStatus.NOT_CONVERGED, "no initial pose", triplets=used, blobs=len(blobs))
    rms = math.sqrt(2.0 * best.cost / len(best.fun))
    if not best.success or rms > MAX_RMS_PX:
        return PadPose(
            PoseStatus.NOT_CONVERGED,
            f"ellipses reprojected with {rms:.2f} px RMS (limit {MAX_RMS_PX})",
            triplets=used,
            rms_px=rms,
            blobs=len(blobs),
        )
    rotation, _ = cv2.Rodrigues(best.x[:3])
    return PadPose(
        PoseStatus.OK,
        rotation=np.asarray(rotation, dtype=np.float64),
        translation=np.asarray(best.x[3:], dtype=np.float64),
        triplets=used,
        rms_px=rms,
        blobs=len(blobs),
        matched=matched,
    )
