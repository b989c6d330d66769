"""The thermal step keeps body-sized warm ellipses; rejects what is too hot, round, big or cut."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_perception.camera import CameraPose, NavPose
from hdrc3_perception.geolocation import Ground, geolocate
from hdrc3_perception.synthetic import THERMAL_K, Body, render_pair
from hdrc3_perception.thermal import RegionVerdict, ThermalParams, find_regions

NADIR = math.pi / 2


def regions_of(body: Body, altitude: float = 40.0) -> list[RegionVerdict]:
    ground = Ground()
    nav = NavPose((0.0, 0.0, altitude), 0.0, 0.0, 0.0)
    pair = render_pair(0.0, nav, 0.0, NADIR, [body], ground, np.random.default_rng(3))
    pose = CameraPose.of(nav, 0.0, NADIR)

    def range_at(u: float, v: float) -> float | None:
        point = geolocate(pose, THERMAL_K, u, v, ground)
        return None if point is None else float(np.linalg.norm(point - pose.position))

    image = np.asarray(pair.thermal.data, dtype=np.uint16)
    return [r.verdict for r in find_regions(image, THERMAL_K.fx, range_at, ThermalParams())]


@pytest.mark.parametrize(
    ("body", "altitude", "verdicts"),
    [
        (Body(1.0, 2.0, 0.4), 40.0, [RegionVerdict.BODY]),
        (Body(1.0, 2.0, 2.0, kelvin=301.0), 40.0, [RegionVerdict.BODY]),  # a cooler dummy
        (Body(1.0, 2.0, 0.4), 80.0, [RegionVerdict.BODY]),
        (Body(-2.0, 1.0, 1.0, kelvin=330.0, length=1.2), 40.0, []),  # hot engine: thresholded out
        (Body(-2.0, 1.0, 1.0, kelvin=292.0), 40.0, []),  # cold ground
        (Body(0.0, 0.0, 0.0, length=1.2, width=1.2), 40.0, [RegionVerdict.AXIS_RATIO]),
        (Body(0.0, 0.0, 0.0, length=4.5, width=1.6), 40.0, [RegionVerdict.TOO_LARGE]),
        # a warm car bonnet: a body's length and axis ratio, four times its area
        (Body(0.0, 0.0, 0.3, length=2.0, width=1.6), 30.0, [RegionVerdict.TOO_BROAD]),
        (Body(0.0, 0.0, 0.3, length=0.55, width=0.35), 20.0, [RegionVerdict.BODY]),  # sitting
        (Body(0.0, 0.0, 0.0, length=0.45, width=0.2), 20.0, [RegionVerdict.TOO_SMALL]),
        (Body(8.0, 0.0, 0.0), 40.0, [RegionVerdict.AT_BORDER]),  # half out of the image
        (Body(0.0, 0.0, 0.0, length=0.2, width=0.2), 80.0, [RegionVerdict.TOO_FEW_PIXELS]),
    ],
)
def test_verdicts(body: Body, altitude: float, verdicts: list[RegionVerdict]) -> None:
    assert regions_of(body, altitude) == verdicts


def test_the_size_filter_scales_with_range() -> None:
    # the same 1.7 m body is 2x as many pixels long at half the range: both are bodies,
    # while a 4 m warm object at 80 m (as long in pixels as a body at 35 m) is not
    assert regions_of(Body(0.0, 0.0, 0.3), 35.0) == [RegionVerdict.BODY]
    assert regions_of(Body(0.0, 0.0, 0.3), 70.0) == [RegionVerdict.BODY]
    assert regions_of(Body(0.0, 0.0, 0.3, length=4.0, width=1.2), 80.0) == [RegionVerdict.TOO_LARGE]
