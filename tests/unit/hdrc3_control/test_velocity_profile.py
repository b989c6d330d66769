"""Velocity compatibility V = sqrt(|phi_max g R|), braking distance, profile feasibility."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_control.commands import G
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.velocity_profile import (
    ProfileLimits,
    braking_distance,
    build_profile,
    compatible_speed,
)

S_BEND = PathSegment((70.0, -30.0, 15.0), (20.0, 60.0, 15.0), (0, 1, 0), (-1, -1, 0), 8.0, 0.0)


@pytest.mark.parametrize(
    ("radius", "phi_deg", "expected"),
    [
        (30.0, 15.0, math.sqrt(math.radians(15.0) * G * 30.0)),
        (10.0, 20.0, 5.8508),
        (100.0, 10.0, 13.0827),
    ],
)
def test_compatible_speed(radius: float, phi_deg: float, expected: float) -> None:
    assert compatible_speed(1.0 / radius, math.radians(phi_deg)) == pytest.approx(
        expected, rel=1e-4
    )


def test_compatible_speed_is_unbounded_on_a_straight_line() -> None:
    assert compatible_speed(0.0, 0.3) == math.inf


@pytest.mark.parametrize(("v", "a", "d"), [(8.0, 1.2, 26.6667), (3.0, 1.5, 3.0), (0.0, 1.0, 0.0)])
def test_braking_distance(v: float, a: float, d: float) -> None:
    assert braking_distance(v, a) == pytest.approx(d, rel=1e-4)


@pytest.mark.parametrize("end_speed", [0.0, 3.0])
def test_profile_respects_curvature_target_and_braking(end_speed: float) -> None:
    lim = ProfileLimits()
    prof = build_profile(S_BEND, end_speed, lim)
    assert np.all(prof.speed <= prof.limit + 1e-9)
    assert np.all(prof.speed <= S_BEND.target_velocity + 1e-9)
    assert prof.limit.min() < S_BEND.target_velocity  # the bend forces a slower speed
    assert prof.speed[-1] == pytest.approx(min(end_speed, prof.limit[-1]))
    # every deceleration between samples is within the braking limit
    dv2 = prof.speed[:-1] ** 2 - prof.speed[1:] ** 2
    ds = np.diff(prof.distance)
    assert np.all(dv2 <= 2 * lim.braking_decel * ds + 1e-9)
    assert prof.length == pytest.approx(S_BEND.arc_length(), rel=1e-3)


def test_curvature_lowers_the_speed_below_the_target() -> None:
    prof = build_profile(S_BEND, 8.0)  # leave the bend at cruise speed: only curvature limits
    low = int(np.argmin(prof.limit))
    assert prof.limit[low] < S_BEND.target_velocity - 0.5
    assert prof.speed[low] == pytest.approx(prof.limit[low])
    assert prof.speed[-1] > prof.limit[low] + 1.0  # faster again after the bend


def test_min_speed_ahead_sees_the_coming_reduction() -> None:
    prof = build_profile(S_BEND, 8.0)
    s_low = float(prof.params[int(np.argmin(prof.limit))])
    lead = prof.length * s_low - 5.0
    s_before = float(np.interp(lead, prof.distance, prof.params))
    assert prof.min_speed_ahead(s_before, 10.0) == pytest.approx(prof.limit.min(), abs=0.05)
    assert prof.min_speed_ahead(s_before, 0.0) == pytest.approx(prof.speed_at(s_before))


def test_max_end_speed_caps_the_entry_of_the_next_segment() -> None:
    seg = PathSegment.straight((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 8.0, 8.0)
    assert build_profile(seg, 8.0, max_end_speed=3.0).speed[-1] == pytest.approx(3.0)
