"""PTU tracking of the landing pad: aiming, slew rates, a moving helicopter, losing the pad."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from hdrc3_control.pad_tracking import PadSighting, PadTracker, aim_at
from hdrc3_control.ppc_hardware import PtuLimits
from hdrc3_perception.camera import CameraPose, NavPose, optical_to_body
from tests.unit.hdrc3_control.test_ppc_kernel import Bench

RATE = math.radians(60.0)


@pytest.mark.parametrize(
    ("direction", "pan", "tilt"),
    [
        ((0.0, 0.0, 1.0), 0.3, 1.2),  # already centred
        ((0.5, 0.0, 4.0), 0.0, math.pi / 2),
        ((-1.0, 2.0, 6.0), -0.7, 0.9),
        ((3.0, -1.0, 5.0), 2.0, 0.1),
    ],
)
def test_aim_puts_the_direction_on_the_optical_axis(
    direction: tuple[float, float, float], pan: float, tilt: float
) -> None:
    body = optical_to_body(pan, tilt) @ np.asarray(direction)
    new_pan, new_tilt = aim_at(direction, pan, tilt)
    axis = optical_to_body(new_pan, new_tilt) @ np.array([0.0, 0.0, 1.0])
    assert np.allclose(axis, body / np.linalg.norm(body), atol=1e-12)


def test_the_set_point_moves_within_the_slew_rates_and_holds_then_lets_go() -> None:
    tracker = PadTracker(PtuLimits(), hold=2.0)
    tracker.reading(0.0, 0.0, 0.0)
    assert tracker.update(0.0) is None  # nothing seen yet
    assert not tracker.see(PadSighting(0.5, (0.0, 0.0, 5.0)))  # no PTU reading of its time
    assert tracker.see(PadSighting(0.0, (0.0, 5.0, 5.0)))  # 45 deg below the axis
    points = [tracker.update(0.04 * k) for k in range(40)]
    steps = [abs(b[1] - a[1]) for a, b in itertools.pairwise(points)]  # type: ignore[index]
    assert max(steps) <= RATE * 0.04 + 1e-12
    assert points[-1] == pytest.approx((0.0, math.pi / 4))
    assert tracker.update(2.0) is not None  # held through a short occlusion
    assert tracker.update(2.1) is None  # lost: back to the commanded mode
    tracker.see(PadSighting(0.0, (0.0, 0.0, -5.0)))  # behind the camera: ignored
    assert tracker.sightings == 1


def test_the_pad_stays_in_view_of_a_moving_helicopter() -> None:
    """An approach at 3 m/s to 1.5 m short of the pad, 12 m up, turning 10 deg/s while it
    hovers; images 0.2 s late at 25 Hz, a PTU at 60 deg/s."""
    pad = np.array([0.0, 0.0, 0.0])
    tracker = PadTracker(PtuLimits())
    pan, tilt = 0.0, math.pi / 2
    images: list[tuple[float, np.ndarray]] = []
    worst = 0.0
    for k in range(int(12.0 / 0.04)):
        t = 0.04 * k
        east = -18.0 + min(3.0 * t, 16.5)
        heading = 0.4 + math.radians(10.0) * max(0.0, t - 6.0)
        nav = NavPose((east, 2.0, 12.0), 0.0, 0.05, heading)
        camera = CameraPose.of(nav, pan, tilt)
        local = camera.rotation.T @ (pad - camera.position)
        off_axis = math.degrees(math.atan2(math.hypot(local[0], local[1]), local[2]))
        worst = max(worst, off_axis) if t > 2.0 else worst
        images.append((t, local))
        tracker.reading(t, pan, tilt)
        while images and images[0][0] <= t - 0.2:
            stamp, seen = images.pop(0)
            tracker.see(PadSighting(stamp, (float(seen[0]), float(seen[1]), float(seen[2]))))
        setpoint = tracker.update(t)
        if setpoint is not None:  # the mechanism at its rate limits
            pan += max(-RATE * 0.04, min(RATE * 0.04, setpoint[0] - pan))
            tilt += max(-RATE * 0.04, min(RATE * 0.04, setpoint[1] - tilt))
    # the colour camera's half field of view is 24 deg horizontally, 19.6 deg vertically
    assert worst < 8.0, worst


def test_the_ppc_tracks_only_while_state_estimation_is_engaged() -> None:
    b = Bench()
    b.kernel.see_pad(PadSighting(0.04, (0.0, 1.0, 5.0)))
    b.run(0.08)
    assert not b.kernel.tracking  # image processing idle: the sighting is dropped
    b.send("PPCL-IP-State-Est-EV", 3)
    b.run(0.08)
    b.kernel.ptu_reading(b.t, b.pan, b.tilt)
    b.kernel.see_pad(PadSighting(b.t, (0.0, 1.0, 5.0)))
    b.run(1.0)
    assert b.kernel.tracking
    assert b.tilt == pytest.approx(math.atan2(1.0, 5.0), abs=1e-6)
    b.send("PPCL-IP-Abort-EV", 4)
    b.run(0.08)
    assert not b.kernel.tracking
