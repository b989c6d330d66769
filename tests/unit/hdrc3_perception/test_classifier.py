"""Both trained detectors: silent on grass, firing on a person silhouette in any orientation."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from hdrc3_perception.camera import CameraPose, NavPose
from hdrc3_perception.classifier import (
    BODY_LENGTH_M,
    BODY_PIXELS,
    PATCH_SIZE,
    BodyClassifier,
    ClassifierParams,
    Detector,
    upright_patch,
)
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.synthetic import COLOR_K, Body, render_pair

CLASSIFIERS = {d: BodyClassifier(ClassifierParams(detector=d)) for d in Detector}


def body_view(
    heading: float, altitude: float = 30.0
) -> tuple[np.ndarray, tuple[float, float], float, float]:
    """Grey image of a lying silhouette with its centre, axis angle and pixels per metre."""
    nav = NavPose((0.0, 0.0, altitude), 0.0, 0.0, 0.0)
    body = Body(0.0, 0.3, heading)  # under the camera (the mount is 0.3 m forward)
    pair = render_pair(0.0, nav, 0.0, math.pi / 2, [body], Ground(), np.random.default_rng(5))
    gray = cv2.cvtColor(np.asarray(pair.color.data, dtype=np.uint8), cv2.COLOR_RGB2GRAY)
    pose = CameraPose.of(nav, 0.0, math.pi / 2)
    c, s = math.cos(heading), math.sin(heading)
    ends = np.array([[-0.85 * c, 0.3 - 0.85 * s, 0.0], [0.85 * c, 0.3 + 0.85 * s, 0.0]])
    (u0, v0), (u1, v1) = pose.project(COLOR_K, ends)
    centre = ((u0 + u1) / 2.0, (v0 + v1) / 2.0)
    # the ends are 1.7 m apart: pixels per metre from them (the pipeline takes it from the range)
    return gray, centre, math.atan2(v1 - v0, u1 - u0), math.hypot(u1 - u0, v1 - v0) / 1.7


@pytest.mark.parametrize("detector", list(Detector))
@pytest.mark.parametrize("heading", [0.0, 0.7, 2.0, 3.6, 5.5])
def test_a_lying_person_silhouette_is_classified_a_body(detector: Detector, heading: float) -> None:
    assert CLASSIFIERS[detector].classify(*body_view(heading)) > 0


@pytest.mark.parametrize("detector", list(Detector))
def test_background_patches_are_not_bodies(detector: Detector) -> None:
    # (an elongated dark blob turned upright does fire both: the weak classifier's false
    # positives are what the certainty map prunes)
    rng = np.random.default_rng(11)
    grass = np.clip(rng.normal(110.0, 6.0, (576, 720)), 0, 255).astype(np.uint8)
    for i in range(8):
        for angle in (0.0, 0.5, 1.6):
            centre = (100.0 + 70.0 * i, 80.0 + 50.0 * i)
            assert CLASSIFIERS[detector].classify(grass, centre, angle, 80.0 / BODY_LENGTH_M) == 0


def test_the_patch_puts_the_body_axis_upright_at_the_body_scale() -> None:
    image = np.zeros((576, 720), dtype=np.uint8)
    angle = 0.6
    centre = (300.0, 250.0)
    half = 20.0  # a 40 px bright bar along ``angle``
    a = (centre[0] - half * math.cos(angle), centre[1] - half * math.sin(angle))
    b = (centre[0] + half * math.cos(angle), centre[1] + half * math.sin(angle))
    cv2.line(image, tuple(round(x) for x in a), tuple(round(x) for x in b), 255, 1)
    patch = upright_patch(image, centre, angle, 2 * half / BODY_LENGTH_M)
    assert patch.shape == (PATCH_SIZE[1], PATCH_SIZE[0])
    rows, cols = np.nonzero(patch > 64)
    assert np.ptp(cols) <= 6  # vertical
    assert np.ptp(rows) == pytest.approx(BODY_PIXELS, abs=6)
    assert np.mean(cols) == pytest.approx(PATCH_SIZE[0] / 2, abs=2)
