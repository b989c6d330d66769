"""Algorithm 4, line 8: the human body classifier on the colour region (§11.1.1).

Two real, trained detectors from OpenCV, chosen by :class:`Detector`:

- ``HOG_PEOPLE`` (default): OpenCV's HOG + linear SVM people detector (Dalal-Triggs), searched
  over positions and scales around the expected body size (``detectMultiScale``); overlapping
  windows are grouped and a region is positive when a group of at least
  :attr:`ClassifierParams.hog_group` + 1 windows remains (the weak-classification setting the
  certainty map prunes).
- ``HAAR_KRUPPA``: the seed's choice, the Viola-Jones cascades for full, upper and lower body
  trained by Kruppa et al. (2003) that ship in ``cv2.data.haarcascades``, configured as in the
  chapter (``minNeighbors`` 1, search window grown by 20 % per scale). A region is positive if
  any of the three cascades fires. On the simulator's rendered people seen from 30 m they find
  about as many people and animals as HOG at twice its CPU time (``bench/saliency_rendered.py``),
  so they are not the default.

Both detectors were trained on upright pedestrians; a person lying on the ground seen from above
is a frontal or back view of one (the chapter's argument for the cascades). The classifier
therefore gets upright patches: the colour image around the body's centre, turned so that the
body's major axis (from the thermal ellipse) is vertical, and scaled from the cameras' geometry
(pixels per metre at the body's range, not the thermal blob's length, which blur and cooler
clothing shorten) so that a :data:`BODY_LENGTH_M` body spans :data:`BODY_PIXELS`. The thermal
ellipse's axis is off the body's for spread arms and legs drawn up, and it does not say where
the head is: each region is tried at :attr:`ClassifierParams.turns_deg` about that axis and in
both orientations. Neither detector sees anything but the image.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import Hdrc3Error

BODY_PIXELS = 96
"""Body length in the classifier patch, px (HOG's window is 64x128 for a ~96 px person)."""
BODY_LENGTH_M = 1.75
"""Length of an adult lying stretched out, m: the patch's scale."""
PATCH_SIZE = (96, 160)
"""(width, height) of the upright patch handed to the detectors, px (room to search around
the thermal centre, which the warmer torso pulls off the body's middle)."""
MIN_PART = 0.4
"""Smallest Haar window searched, as a fraction of BODY_PIXELS (upper/lower body ~ half)."""
KRUPPA_CASCADES = (
    "haarcascade_fullbody.xml",
    "haarcascade_upperbody.xml",
    "haarcascade_lowerbody.xml",
)


class Detector(enum.Enum):
    """Which trained body detector runs on the colour region."""

    HAAR_KRUPPA = "haar_kruppa"
    HOG_PEOPLE = "hog_people"


class ClassifierError(Hdrc3Error):
    """A detector could not be loaded (an OpenCV build without its data)."""


@dataclass(frozen=True, slots=True)
class ClassifierParams:
    """Detector settings (chapter: minNeighbors 1, scale step 1.2)."""

    detector: Detector = Detector.HOG_PEOPLE
    min_neighbors: int = 1
    scale_factor: float = 1.2
    hog_threshold: float = 0.0
    """SVM margin a HOG window must exceed."""
    hog_group: int = 2
    """HOG windows are grouped (``groupRectangles``); a group needs more than this many."""
    hog_scale: float = 1.05
    """Step between HOG search scales (from the expected body size up)."""
    turns_deg: tuple[float, ...] = (-15.0, 0.0, 15.0)
    """Turns of the patch about the thermal ellipse's axis, deg."""


class BodyClassifier:
    """One loaded detector; :meth:`hits` counts detections in a patch."""

    def __init__(self, params: ClassifierParams | None = None) -> None:
        self.params = params or ClassifierParams()
        self._cascades: list[tuple[cv2.CascadeClassifier, tuple[int, int]]] = []
        self._hog: cv2.HOGDescriptor | None = None
        if self.params.detector is Detector.HAAR_KRUPPA:
            root = Path(cv2.data.haarcascades)  # type: ignore[attr-defined]  # not in cv2's stubs
            for name in KRUPPA_CASCADES:
                cascade = cv2.CascadeClassifier(str(root / name))
                if cascade.empty():
                    raise ClassifierError(f"cannot load {root / name}")
                # the range fixed the body's scale in the patch: search from MIN_PART of it up
                w, h = cascade.getOriginalWindowSize()
                grow = max(MIN_PART * BODY_PIXELS / h, 1.0)
                self._cascades.append((cascade, (math.ceil(w * grow), math.ceil(h * grow))))
        else:
            self._hog = cv2.HOGDescriptor()
            weights = cv2.HOGDescriptor.getDefaultPeopleDetector()
            self._hog.setSVMDetector(np.asarray(weights, dtype=np.float32))

    def classify(
        self,
        gray: NDArray[np.uint8],
        center: tuple[float, float],
        axis_angle: float,
        pixels_per_metre: float,
    ) -> int:
        """Detections of a body around ``center`` over every turn and both orientations.

        Args:
            gray: Colour image converted to grey.
            center: Body centre in the colour image, px.
            axis_angle: Direction of the body's major axis in the colour image, rad from +x.
            pixels_per_metre: Colour pixels per metre on the ground at the body.
        """
        total = 0
        for turn in self.params.turns_deg:
            patch = upright_patch(gray, center, axis_angle + math.radians(turn), pixels_per_metre)
            total += self.hits(patch)
        return total

    def hits(self, patch: NDArray[np.uint8]) -> int:
        """Detections in an upright grey patch and in the patch turned by 180 degrees.

        The thermal ellipse gives the body's axis but not which end is the head, so both
        orientations are tried.
        """
        turned = np.asarray(cv2.rotate(patch, cv2.ROTATE_180), dtype=np.uint8)
        return self._hits(patch) + self._hits(turned)

    def _hits(self, patch: NDArray[np.uint8]) -> int:
        p = self.params
        if self._hog is not None:
            found, _ = self._hog.detectMultiScale(
                patch,
                hitThreshold=p.hog_threshold,
                winStride=(8, 8),
                padding=(16, 16),
                scale=p.hog_scale,
                groupThreshold=p.hog_group,
            )
            return len(found)
        total = 0
        for cascade, min_size in self._cascades:
            found = cascade.detectMultiScale(
                patch, scaleFactor=p.scale_factor, minNeighbors=p.min_neighbors, minSize=min_size
            )
            total += len(found)
        return total


def upright_patch(
    gray: NDArray[np.uint8],
    center: tuple[float, float],
    axis_angle: float,
    pixels_per_metre: float,
) -> NDArray[np.uint8]:
    """The patch around ``center``: body axis vertical, a BODY_LENGTH_M body BODY_PIXELS long.

    Args:
        gray: Colour image converted to grey.
        center: Body centre in the colour image, px.
        axis_angle: Direction of the body's major axis in the colour image, rad from +x.
        pixels_per_metre: Colour pixels per metre on the ground at the body.
    """
    scale = BODY_PIXELS / max(BODY_LENGTH_M * pixels_per_metre, 1.0)
    # rotate the major axis onto the image's vertical axis, then scale, then centre the patch
    degrees = float(np.degrees(axis_angle)) - 90.0
    matrix = cv2.getRotationMatrix2D(center, degrees, scale)
    matrix[0, 2] += PATCH_SIZE[0] / 2.0 - center[0]
    matrix[1, 2] += PATCH_SIZE[1] / 2.0 - center[1]
    patch = cv2.warpAffine(
        gray, matrix, PATCH_SIZE, flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
    )
    return np.asarray(patch, dtype=np.uint8)
