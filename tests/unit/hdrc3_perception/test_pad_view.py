"""The exact pad renderer the pose estimator is tested against."""

from __future__ import annotations

import numpy as np

from hdrc3_perception.pad_view import BLACK, WHITE, look_at, render
from hdrc3_perception.synthetic import COLOR_K


def test_a_nadir_view_shows_the_pattern_centred_on_the_ground() -> None:
    rotation, translation = look_at((0.0, 0.001, 6.0))
    image = render(COLOR_K, rotation, translation, background=110)
    assert image.shape == (COLOR_K.height, COLOR_K.width) and image.dtype == np.uint8
    assert image[0, 0] == 110  # the ground around the pad
    assert image[COLOR_K.height // 2, COLOR_K.width // 2] == WHITE
    assert (image == BLACK).any()
