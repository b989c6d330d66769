"""The node's image decoding: rgb8 / mono16 with padded rows and either byte order; bad sizes."""

from __future__ import annotations

import numpy as np
import pytest
from sensor_msgs.msg import Image

from hdrc3_perception.node import image_array

RGB = np.arange(4 * 5 * 3, dtype=np.uint8).reshape(4, 5, 3)
MONO = (np.arange(4 * 5, dtype=np.uint16) * 1000 + 29000).reshape(4, 5)


def msg(data: bytes, encoding: str, width: int, height: int, step: int, big: bool = False) -> Image:
    m = Image()
    m.width, m.height, m.step, m.encoding, m.is_bigendian = width, height, step, encoding, big
    m.data = data
    return m


def padded(array: np.ndarray, pad: int) -> bytes:
    rows = array.reshape(array.shape[0], -1).view(np.uint8)
    return np.hstack([rows, np.zeros((rows.shape[0], pad), np.uint8)]).tobytes()


@pytest.mark.parametrize(
    ("image", "expected"),
    [
        (msg(RGB.tobytes(), "rgb8", 5, 4, 15), RGB),
        (msg(padded(RGB, 3), "rgb8", 5, 4, 18), RGB),
        (msg(MONO.tobytes(), "mono16", 5, 4, 10), MONO),
        (msg(MONO.byteswap().tobytes(), "mono16", 5, 4, 10, big=True), MONO),
        (msg(padded(MONO, 6), "mono16", 5, 4, 16), MONO),
    ],
)
def test_decoding(image: Image, expected: np.ndarray) -> None:
    got = image_array(image)
    assert isinstance(got, np.ndarray)
    assert got.dtype == expected.dtype and np.array_equal(got, expected)


@pytest.mark.parametrize(
    "image",
    [
        msg(RGB.tobytes()[:-1], "rgb8", 5, 4, 15),  # truncated
        msg(RGB.tobytes(), "rgb8", 5, 4, 12),  # step shorter than a row
        msg(b"", "rgb8", 0, 0, 0),
        msg(RGB.tobytes(), "bgr8", 5, 4, 15),
    ],
)
def test_bad_images_say_why(image: Image) -> None:
    assert isinstance(image_array(image), str)
