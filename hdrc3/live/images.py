"""Camera images for the live view: ``sensor_msgs/Image`` pixels to a JPEG (OpenCV).

The simulated cameras publish ``rgb8`` (colour) and ``mono16`` (thermal, centi-kelvin); the other
common 8-bit encodings are accepted too. A thermal image is shown "white hot": its values are
stretched from the image's minimum to its maximum, over at least :data:`THERMAL_MIN_SPAN` so that
a scene of one temperature shows its noise as grey, not as full-contrast speckle. Anything else
is a :class:`ImageProblem`, never an exception.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

THERMAL_MIN_SPAN = 1000
"""mono16 values (centi-kelvin: 10 K) a thermal image is stretched over at least."""


class ImageProblem(StrEnum):
    """Why an image cannot be shown."""

    UNKNOWN_ENCODING = "unknown encoding"
    BAD_SIZE = "size does not match the data"
    ENCODER_FAILED = "encoder failed"


@dataclass(frozen=True, slots=True)
class PixelLayout:
    """How one ROS encoding stores a pixel, and how to turn it into BGR / grey for OpenCV."""

    dtype: type[np.uint8] | type[np.uint16]
    channels: int
    to_bgr: int | None
    """``cv2.COLOR_*`` conversion to BGR, None when already BGR or grey."""


LAYOUTS = {
    "rgb8": PixelLayout(np.uint8, 3, cv2.COLOR_RGB2BGR),
    "bgr8": PixelLayout(np.uint8, 3, None),
    "rgba8": PixelLayout(np.uint8, 4, cv2.COLOR_RGBA2BGR),
    "bgra8": PixelLayout(np.uint8, 4, cv2.COLOR_BGRA2BGR),
    "mono8": PixelLayout(np.uint8, 1, None),
    "8UC1": PixelLayout(np.uint8, 1, None),
    "mono16": PixelLayout(np.uint16, 1, None),
    "16UC1": PixelLayout(np.uint16, 1, None),
}


def pixels(msg: Any) -> NDArray[Any] | ImageProblem:
    """The image's pixels (rows x cols [x channels], native byte order), or why not."""
    layout = LAYOUTS.get(str(msg.encoding))
    if layout is None:
        return ImageProblem.UNKNOWN_ENCODING
    height, width, step = int(msg.height), int(msg.width), int(msg.step)
    dtype = np.dtype(layout.dtype)
    row = width * layout.channels * dtype.itemsize
    if width == 0 or height == 0 or step < row or len(msg.data) < step * height:
        return ImageProblem.BAD_SIZE
    raw = np.frombuffer(msg.data, dtype=np.uint8, count=step * height)
    rows = np.ascontiguousarray(raw.reshape(height, step)[:, :row])
    wire = dtype.newbyteorder(">" if msg.is_bigendian else "<")
    values = rows.view(wire).astype(layout.dtype, copy=False)
    return values.reshape(height, width, layout.channels) if layout.channels > 1 else values


def displayable(msg: Any, values: NDArray[Any]) -> NDArray[Any]:
    """8-bit BGR or grey pixels of :func:`pixels`' result (16-bit stretched, see the module)."""
    layout = LAYOUTS[str(msg.encoding)]
    if layout.dtype is np.uint16:
        low = float(values.min())
        span = max(float(values.max()) - low, THERMAL_MIN_SPAN)
        return cv2.convertScaleAbs(values, alpha=255.0 / span, beta=-255.0 * low / span)
    if layout.to_bgr is not None:
        return cv2.cvtColor(values, layout.to_bgr)
    return values


def jpeg(msg: Any, max_width: int, quality: int) -> bytes | ImageProblem:
    """The image as JPEG, shrunk (aspect kept) to at most ``max_width`` pixels wide."""
    values = pixels(msg)
    if isinstance(values, ImageProblem):
        return values
    shown = displayable(msg, values)
    height, width = shown.shape[:2]
    if width > max_width:
        size = (max_width, max(1, round(height * max_width / width)))
        shown = cv2.resize(shown, size, interpolation=cv2.INTER_AREA)
    ok, data = cv2.imencode(".jpg", shown, [cv2.IMWRITE_JPEG_QUALITY, quality])
    return bytes(data) if ok else ImageProblem.ENCODER_FAILED
