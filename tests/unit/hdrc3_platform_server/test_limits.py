"""Argument checks: None when fine, otherwise a reason naming the problem."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

from hdrc3_control.ppc_hardware import PtuLimits
from hdrc3_platform_server import limits as check
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.limits import FlightLimits

FLIGHT = FlightLimits()
FRAME = WorldFrame(55.7, 13.47, 95.0, bounds=(-300.0, -200.0, 300.0, 200.0), margin=100.0)


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: check.velocity(FLIGHT, 8.0), None),
        (lambda: check.velocity(FLIGHT, 25.0), "flight envelope"),
        (lambda: check.velocity(FLIGHT, math.nan), "finite"),
        (lambda: check.position(FRAME, FLIGHT, 0.0, 0.0, 30.0, "t"), None),
        (lambda: check.position(FRAME, FLIGHT, 500.0, 0.0, 30.0, "t"), "far outside"),
        (lambda: check.position(FRAME, FLIGHT, 0.0, 0.0, 1.0, "t"), "below the ground"),
        (lambda: check.position(FRAME, FLIGHT, 0.0, 0.0, 151.0, "t"), "ceiling"),
        (lambda: check.wgs84(13.47, 55.7), None),
        (lambda: check.wgs84(13.47, 95.0), "WGS84"),
        (lambda: check.pan_tilt(PtuLimits(), 0.0, math.pi / 2), None),
        (lambda: check.pan_tilt(PtuLimits(), 0.0, math.pi), "PTU limits"),
        (lambda: check.camera(0), None),
        (lambda: check.camera(3), "unknown camera"),
        (lambda: check.unit_interval("zoom", 1.0), None),
        (lambda: check.unit_interval("zoom", 1.01), "outside [0, 1]"),
        (lambda: check.shutter(0.01), None),
        (lambda: check.shutter(0.0), "shutter"),
        (lambda: check.laser_angular(0.25), None),
        (lambda: check.laser_angular(math.inf), "angular resolution"),
        (lambda: check.laser_distance(0.01), None),
        (lambda: check.laser_distance(0.005), "distance resolution"),
        (lambda: check.laser_speed(-math.pi), None),
        (lambda: check.laser_speed(4.0), "rotation speed"),
        (lambda: check.pixel(719.0, 575.0), None),
        (lambda: check.pixel(720.0, 0.0), "outside"),
    ],
)
def test_checks(call: Callable[[], str | None], words: str | None) -> None:
    reason = call()
    if words is None:
        assert reason is None
    else:
        assert reason is not None and words in reason
