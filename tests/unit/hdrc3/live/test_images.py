from __future__ import annotations

import cv2
import numpy as np
import pytest
from sensor_msgs.msg import Image

from hdrc3.live.images import THERMAL_MIN_SPAN, ImageProblem, displayable, jpeg, pixels


def image(encoding: str, values: np.ndarray, big_endian: bool = False) -> Image:
    height, width = values.shape[:2]
    wire = values.astype(values.dtype.newbyteorder(">" if big_endian else "<"))
    data = wire.tobytes()
    return Image(
        height=height, width=width, encoding=encoding, is_bigendian=int(big_endian),
        step=len(data) // height, data=data,
    )  # fmt: skip


RGB = np.zeros((4, 6, 3), np.uint8)
RGB[..., 0] = 200  # red


@pytest.mark.parametrize(
    ("encoding", "values", "bgr"),
    [
        ("rgb8", RGB, (0, 0, 200)),
        ("bgr8", RGB, (200, 0, 0)),
        ("rgba8", np.dstack([RGB, np.full((4, 6), 255, np.uint8)]), (0, 0, 200)),
        ("mono8", np.full((4, 6), 77, np.uint8), 77),
    ],
)
def test_eight_bit_encodings_become_bgr_or_grey(encoding, values, bgr):
    msg = image(encoding, values)
    shown = displayable(msg, pixels(msg))
    assert shown.dtype == np.uint8 and shown.shape[:2] == (4, 6)
    assert np.all(shown[0, 0] == bgr)


@pytest.mark.parametrize("big_endian", [False, True])
def test_thermal_is_stretched_white_hot_over_at_least_the_minimum_span(big_endian):
    cold, warm = 29_000, 29_000 + 2 * THERMAL_MIN_SPAN
    values = np.full((4, 6), cold, np.uint16)
    values[1, 1] = warm
    msg = image("mono16", values, big_endian)
    shown = displayable(msg, pixels(msg))
    assert (shown[0, 0], shown[1, 1]) == (0, 255)
    flat = image("mono16", np.full((4, 6), cold, np.uint16) + np.eye(4, 6, dtype=np.uint16) * 100)
    assert abs(int(displayable(flat, pixels(flat)).max()) - 255 * 100 / THERMAL_MIN_SPAN) <= 1


@pytest.mark.parametrize(
    ("change", "problem"),
    [
        ({"encoding": "yuv422"}, ImageProblem.UNKNOWN_ENCODING),
        ({"encoding": ""}, ImageProblem.UNKNOWN_ENCODING),
        ({"width": 0}, ImageProblem.BAD_SIZE),
        ({"step": 5}, ImageProblem.BAD_SIZE),  # shorter than a row
        ({"height": 5}, ImageProblem.BAD_SIZE),  # more rows than data
    ],
)
def test_images_that_cannot_be_shown_name_the_problem(change, problem):
    msg = image("rgb8", RGB)
    for field, value in change.items():
        setattr(msg, field, value)
    assert pixels(msg) == problem
    assert jpeg(msg, 640, 75) == problem


def test_a_padded_step_is_cropped():
    msg = image("mono8", np.full((2, 3), 9, np.uint8))
    msg.step, msg.data = 4, bytes([9, 9, 9, 0, 9, 9, 9, 0])
    assert pixels(msg).tolist() == [[9, 9, 9], [9, 9, 9]]


@pytest.mark.parametrize(("max_width", "size"), [(640, (6, 4)), (3, (3, 2))])
def test_jpeg_keeps_small_images_and_shrinks_wide_ones(max_width, size):
    data = jpeg(image("rgb8", RGB), max_width, 75)
    assert isinstance(data, bytes) and data[:2] == b"\xff\xd8"
    decoded = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    assert (decoded.shape[1], decoded.shape[0]) == size
    assert abs(int(decoded[0, 0, 2]) - 200) < 10  # still red
