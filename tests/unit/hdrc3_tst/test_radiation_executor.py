"""monitor-radiation: the detector's samples over the interval and the estimate at the target."""

from __future__ import annotations

import math

import pytest

from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import ACTIONS, Capability
from hdrc3_tst.executor import ActionContext, Progress, Stepper
from hdrc3_tst.fake_platform import FakePlatform
from hdrc3_tst.platform_port import DoseSample, PlatformState
from hdrc3_tst.radiation_executor import (
    RADIATION_EXECUTORS,
    DoseEstimate,
    estimate,
)
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS
from sim.world import AIR_ATTENUATION

FRAME = frame_from_world("revinge")
POINTS = {"Reactor": ((190.0, 50.0, 0.0),)}
ABOVE = PlatformState(190.0, 90.0, 30.0, on_ground=False, autonomous=True)
"""40 m north of the target and 30 m up: 50 m from it."""


def _run(duration: float) -> tuple[FakePlatform, Stepper]:
    platform = FakePlatform(sample=ABOVE)
    args: dict[str, float | str] = {"target": "Reactor", "duration": duration}
    spec = ACTIONS["monitor-radiation"]
    ctx = ActionContext("n", "uav0", spec, args, POINTS, platform, FRAME, 0.0)
    return platform, Stepper(RMAX_EXECUTORS["monitor-radiation"](), ctx)


def test_the_action_needs_a_radiation_detector_and_has_an_executor() -> None:
    spec = ACTIONS["monitor-radiation"]
    assert spec.needs == frozenset({Capability.RADIATION})
    assert spec.duration == "duration"
    assert set(RADIATION_EXECUTORS) <= set(RMAX_EXECUTORS)


@pytest.mark.parametrize(
    ("samples", "counts", "mean"),
    [
        # one new sample a second; a sample seen twice counts once
        ((1.0, 1.0, 2.0, 3.0), 1500, 10.0),
        ((4.0,), 500, 10.0),
    ],
)
def test_every_new_sample_counts_once(samples: tuple[float, ...], counts: int, mean: float) -> None:
    platform, stepper = _run(3.0)
    for t, stamp in enumerate(samples):
        platform.dose_sample = DoseSample(10.0, 500, 1.0, stamp)
        assert stepper.step(float(t) * 0.5).progress is Progress.RUNNING
    outcome = stepper.step(3.0)
    assert outcome.progress is Progress.SUCCEEDED
    (note,) = stepper.ctx.notes
    assert note.startswith(f"monitor-radiation: {mean:.3g} uSv/h")
    assert f" s, {counts} counts)" in note
    assert "50.0 m from Reactor" in note


def test_no_sample_in_the_interval_fails_the_node() -> None:
    _, stepper = _run(2.0)
    stepper.step(0.0)
    outcome = stepper.step(2.0)
    assert outcome.progress is Progress.FAILED
    assert outcome.reason == "the radiation detector gave no sample in 2 s"


def test_the_estimate_undoes_the_inverse_square_and_the_air() -> None:
    samples = [(DoseSample(8.0, 400, 1.0, 1.0), 50.0), (DoseSample(12.0, 600, 1.0, 2.0), 50.0)]
    one = estimate(samples)
    assert one == DoseEstimate(2, 1000, 10.0, 50.0)
    assert one.at_one_metre == pytest.approx(10.0 * 2500.0 * math.exp(50.0 * AIR_ATTENUATION))
    assert one.relative_error == pytest.approx(1.0 / math.sqrt(1000.0))
