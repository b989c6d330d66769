"""Algorithm 4, line 4: human-body-sized warm regions in a thermal image (§11.1.1).

The thermal image (``mono16``, centi-kelvin) is thresholded to the temperatures of a human body
seen from above, the connected regions are found (OpenCV contours) and an ellipse is fitted to
each (``cv2.fitEllipse``). A region is kept when the ratio of its minor to major axis is that of
a body and its size matches a body at the region's range: the expected length in pixels is the
body length times the focal length over the range, so the filter tightens as the aircraft climbs;
the ellipse's area on the ground must be a body's too (a car's warm bonnet has a body's length
and axis ratio but four times its area).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

CENTI_KELVIN = 100.0
"""Thermal pixel units per kelvin (the renderer's ``mono16`` contract)."""


@dataclass(frozen=True, slots=True)
class ThermalParams:
    """Thresholds of the thermal step."""

    min_kelvin: float = 300.0
    """Coolest surface accepted (clothed bodies and dummies seen from above are ~27-36 C)."""
    max_kelvin: float = 313.0
    """Warmest surface accepted (hotter regions are engines, roofs in the sun)."""
    min_axis_ratio: float = 0.15
    max_axis_ratio: float = 0.9
    """Minor/major axis ratio of a body's ellipse (a round blob is no person lying down)."""
    min_length_m: float = 0.5
    max_length_m: float = 2.6
    """Major axis on the ground, m: a person sitting (seen from above the warm region is the
    torso and thighs, ~0.55-0.6 m after blur) to a person lying with arms out."""
    max_area_m2: float = 1.6
    """Ellipse area on the ground, m^2: a person lying with arms out is ~0.4 (95 % < 1.1 on the
    rendered people); a car's warm bonnet, ~2.4, is not a body."""
    min_pixels: int = 4
    """Regions smaller than this are noise whatever the range."""


class RegionVerdict(enum.Enum):
    """Why a thermal region was kept or rejected."""

    BODY = "body"
    TOO_FEW_PIXELS = "too_few_pixels"
    AT_BORDER = "at_border"
    """Cut by the image border: its ellipse (and so its ground point) would be wrong."""
    NO_RANGE = "no_range"
    AXIS_RATIO = "axis_ratio"
    TOO_SMALL = "too_small"
    TOO_LARGE = "too_large"
    TOO_BROAD = "too_broad"
    """Ellipse area on the ground above a body's."""


@dataclass(frozen=True, slots=True)
class ThermalRegion:
    """A thresholded region with its fitted ellipse (thermal pixels)."""

    center: tuple[float, float]
    major: float
    """Full major axis length, px."""
    minor: float
    angle: float
    """Direction of the major axis in the image, rad from the image x axis (towards +y)."""
    pixels: int
    verdict: RegionVerdict
    range_m: float = math.nan

    def axis_end(self, sign: float) -> tuple[float, float]:
        """One end of the major axis (``sign`` +1 or -1)."""
        half = sign * self.major / 2.0
        return (
            self.center[0] + half * math.cos(self.angle),
            self.center[1] + half * math.sin(self.angle),
        )


RangeFn = Callable[[float, float], float | None]
"""Range (m) from the camera to the ground at a thermal pixel, None if the ray meets no ground."""


def warm_mask(image: NDArray[np.uint16], params: ThermalParams) -> NDArray[np.uint8]:
    """255 where the temperature is in the body band, else 0."""
    low = round(params.min_kelvin * CENTI_KELVIN)
    high = round(params.max_kelvin * CENTI_KELVIN)
    return np.asarray(cv2.inRange(image, low, high), dtype=np.uint8)


def find_regions(
    image: NDArray[np.uint16], focal: float, range_at: RangeFn, params: ThermalParams
) -> list[ThermalRegion]:
    """Every warm region with its verdict; :attr:`RegionVerdict.BODY` ones are candidates.

    Args:
        image: Thermal image, centi-kelvin.
        focal: Thermal focal length, px (mean of fx and fy).
        range_at: Range to the ground at a pixel (geolocation).
        params: Thresholds.
    """
    contours, _ = cv2.findContours(
        warm_mask(image, params), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE
    )
    regions: list[ThermalRegion] = []
    rows, cols = image.shape[:2]
    for contour in contours:
        # contourArea runs through the boundary pixels' centres: add half the boundary back
        pixels = int(cv2.contourArea(contour)) + len(contour) // 2 + 1
        if len(contour) < 5 or pixels < params.min_pixels:
            x, y, w, h = cv2.boundingRect(contour)
            centre = (x + w / 2.0, y + h / 2.0)
            regions.append(
                ThermalRegion(
                    centre, max(w, h), min(w, h), 0.0, pixels, RegionVerdict.TOO_FEW_PIXELS
                )
            )
            continue
        x, y, w, h = cv2.boundingRect(contour)
        if x == 0 or y == 0 or x + w == cols or y + h == rows:
            centre = (x + w / 2.0, y + h / 2.0)
            regions.append(
                ThermalRegion(centre, max(w, h), min(w, h), 0.0, pixels, RegionVerdict.AT_BORDER)
            )
            continue
        (cx, cy), (d0, d1), degrees = cv2.fitEllipse(contour)
        major, minor = max(d0, d1), min(d0, d1)
        # fitEllipse's angle turns the first axis (d0) from the image x axis.
        angle = math.radians(degrees) + (0.0 if d0 >= d1 else math.pi / 2.0)
        centre = (float(cx), float(cy))
        distance = range_at(*centre)
        verdict = _verdict(major, minor, distance, focal, params)
        regions.append(
            ThermalRegion(
                centre,
                float(major),
                float(minor),
                angle,
                pixels,
                verdict,
                math.nan if distance is None else distance,
            )
        )
    return regions


def _verdict(
    major: float, minor: float, distance: float | None, focal: float, params: ThermalParams
) -> RegionVerdict:
    if distance is None or not math.isfinite(distance) or distance <= 0.0:
        return RegionVerdict.NO_RANGE
    ratio = minor / major if major > 0 else 0.0
    if not params.min_axis_ratio <= ratio <= params.max_axis_ratio:
        return RegionVerdict.AXIS_RATIO
    length_m = major * distance / focal
    if length_m < params.min_length_m:
        return RegionVerdict.TOO_SMALL
    if length_m > params.max_length_m:
        return RegionVerdict.TOO_LARGE
    metres_per_px = distance / focal
    if math.pi / 4.0 * major * minor * metres_per_px**2 > params.max_area_m2:
        return RegionVerdict.TOO_BROAD
    return RegionVerdict.BODY
