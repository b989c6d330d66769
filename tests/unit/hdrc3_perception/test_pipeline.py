"""Algorithm 4 end to end on synthetic scans: every body confirmed where it lies, distractors
pruned, dropped frames harmless, bad input answered with a status."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hdrc3_perception.camera import Intrinsics, NavPose
from hdrc3_perception.classifier import ClassifierParams, Detector
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.pipeline import (
    FramePair,
    PairStatus,
    PipelineConfig,
    SaliencyPipeline,
)
from hdrc3_perception.synthetic import Body, render_pair

BODIES = [
    Body(-4.0, 5.0, 0.3),
    Body(5.0, 18.0, 2.2, kelvin=301.5),  # a dummy, cooler than a person
    Body(-2.0, 32.0, 4.0),
    Body(3.0, 46.0, 1.2),
]
DISTRACTORS = [
    Body(4.0, 8.0, 0.0, kelvin=335.0, length=1.4, width=1.0),  # a warm engine
    Body(-5.0, 24.0, 0.0, kelvin=306.0, length=1.3, width=1.3),  # a round warm patch
    Body(0.0, 40.0, 0.5, kelvin=309.0, length=4.2, width=1.8),  # a car roof in the sun
]
SLOPE = Ground(height=lambda e, n: 0.15 * n + 0.05 * e, max_slope=0.3)
NADIR = math.pi / 2


def scan(
    ground: Ground,
    detector: Detector = Detector.HOG_PEOPLE,
    keep: int = 1,
    nav_error: tuple[float, float, float] = (0.0, 0.0, 0.0),
    north: tuple[float, float] = (-8.0, 56.0),
) -> SaliencyPipeline:
    """Fly north at 40 m above the ground at 10 m/s, 25 frames/s; process every ``keep``-th."""
    pipeline = SaliencyPipeline(ground, PipelineConfig(classifier=ClassifierParams(detector)))
    rng = np.random.default_rng(42)
    frames = int((north[1] - north[0]) / 0.4)
    for i in range(frames):
        n = north[0] + 0.4 * i
        truth = NavPose((0.0, n, ground.up(0.0, n) + 40.0), 0.01, -0.02, 0.05)
        pair = render_pair(i * 0.04, truth, 0.0, NADIR, BODIES + DISTRACTORS, ground, rng)
        if i % keep:
            continue
        estimate = dataclasses.replace(
            truth,
            position=tuple(np.add(truth.position, nav_error)),  # type: ignore[arg-type]
        )
        result = pipeline.process(dataclasses.replace(pair, nav=estimate))
        assert result.status is PairStatus.PROCESSED, result.reason
    return pipeline


def errors(pipeline: SaliencyPipeline, offset: tuple[float, float] = (0.0, 0.0)) -> list[float]:
    """Distance from each body to the nearest confirmed location (shifted by ``offset``)."""
    found = [(loc.east - offset[0], loc.north - offset[1]) for loc in pipeline.map.confirmed()]
    return [min((math.dist((b.east, b.north), f) for f in found), default=math.inf) for b in BODIES]


def false_positives(pipeline: SaliencyPipeline) -> int:
    return sum(
        min(math.dist((b.east, b.north), (loc.east, loc.north)) for b in BODIES) > 2.0
        for loc in pipeline.map.confirmed()
    )


@pytest.mark.parametrize("ground", [Ground(), SLOPE], ids=["flat", "sloped"])
def test_every_body_is_confirmed_where_it_lies_and_distractors_are_not(ground: Ground) -> None:
    pipeline = scan(ground)
    assert max(errors(pipeline)) < 0.3
    assert false_positives(pipeline) == 0


def test_the_kruppa_cascades_find_the_bodies_too() -> None:
    pipeline = scan(Ground(), Detector.HAAR_KRUPPA, north=(-8.0, 24.0))
    assert max(errors(pipeline)[:2]) < 0.3
    assert false_positives(pipeline) == 0


def test_dropped_frames_keep_the_map_right() -> None:
    pipeline = scan(Ground(), keep=3)
    assert max(errors(pipeline)) < 0.3
    assert false_positives(pipeline) == 0


def test_geolocation_follows_the_aircraft_s_own_navigation_solution() -> None:
    # the aircraft believes it is 1.5 m east and 0.8 m south of where it is: every body is
    # placed that much off, i.e. the pipeline uses the navigation solution, not the truth
    pipeline = scan(Ground(), nav_error=(1.5, -0.8, 0.0))
    assert max(errors(pipeline, offset=(1.5, -0.8))) < 0.3


def reference_pair() -> FramePair:
    nav = NavPose((0.0, 5.0, 40.0), 0.0, 0.0, 0.0)
    return render_pair(1.0, nav, 0.0, NADIR, BODIES, Ground(), np.random.default_rng(1))


def with_thermal(pair: FramePair, **changes: object) -> FramePair:
    return dataclasses.replace(pair, thermal=dataclasses.replace(pair.thermal, **changes))


def with_color(pair: FramePair, **changes: object) -> FramePair:
    return dataclasses.replace(pair, color=dataclasses.replace(pair.color, **changes))


BAD = {
    "no colour camera_info": (lambda p: with_color(p, intrinsics=None), PairStatus.NO_CALIBRATION),
    "no thermal camera_info": (
        lambda p: with_thermal(p, intrinsics=None),
        PairStatus.NO_CALIBRATION,
    ),
    "bgr8": (lambda p: with_color(p, encoding="bgr8"), PairStatus.BAD_ENCODING),
    "mono8 thermal": (
        lambda p: with_thermal(p, data=p.thermal.data.astype(np.uint8)),
        PairStatus.BAD_ENCODING,
    ),
    "wrong size": (
        lambda p: with_thermal(p, intrinsics=Intrinsics.from_fov(320, 240, 0.4)),
        PairStatus.BAD_SIZE,
    ),
    "grey colour": (
        lambda p: with_color(p, data=p.color.data[:, :, 0]),
        PairStatus.BAD_SIZE,
    ),
    "nan position": (
        lambda p: dataclasses.replace(p, nav=NavPose((0.0, math.nan, 40.0), 0.0, 0.0, 0.0)),
        PairStatus.BAD_POSE,
    ),
    "inf tilt": (lambda p: dataclasses.replace(p, tilt=math.inf), PairStatus.BAD_POSE),
    "older than the last": (lambda p: dataclasses.replace(p, time=0.5), PairStatus.STALE),
    "same time": (lambda p: dataclasses.replace(p, time=1.0), PairStatus.STALE),
    "frozen thermal": (lambda p: dataclasses.replace(p, time=1.04), PairStatus.FROZEN),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_gives_a_status_and_leaves_the_map_alone(name: str) -> None:
    change, status = BAD[name]
    pipeline = SaliencyPipeline(Ground())
    pair = reference_pair()
    first = pipeline.process(pair)
    assert first.status is PairStatus.PROCESSED
    before = [dataclasses.astuple(loc) for loc in pipeline.map.locations]
    result = pipeline.process(change(pair))
    assert result.status is status
    assert result.reason
    assert [dataclasses.astuple(loc) for loc in pipeline.map.locations] == before


def test_per_stage_counts() -> None:
    config = PipelineConfig(classifier=ClassifierParams(Detector.HOG_PEOPLE))
    pipeline = SaliencyPipeline(Ground(), config)
    nav = NavPose((0.0, 18.0, 40.0), 0.0, 0.0, 0.0)
    engine = dataclasses.replace(DISTRACTORS[0], east=-4.0, north=16.0)
    patch = dataclasses.replace(DISTRACTORS[1], east=1.0, north=22.0)
    scene = [BODIES[1], engine, patch]
    pair = render_pair(0.0, nav, 0.0, NADIR, scene, Ground(), np.random.default_rng(2))
    result = pipeline.process(pair)
    # engine: not warm in the band; round patch: wrong axis ratio; the dummy: a body
    assert (result.warm_regions, result.candidates, result.corresponded) == (2, 1, 1)
    assert result.positives == 1 and result.added == 1
    (detection,) = result.detections
    assert math.dist(detection.ground[:2], (BODIES[1].east, BODIES[1].north)) < 0.3
