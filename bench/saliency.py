"""CPU time of Algorithm 4 per colour + thermal pair, and multi-platform coverage figures.

Processing: a synthetic scan (``hdrc3_perception.synthetic``: warm ellipses and person
silhouettes projected with exact poses, plus warm distractors) at 40 m, 10 m/s, 25 frames/s over
a field of bodies; the pairs are rendered first, then ``SaliencyPipeline.process`` is timed in
CPU seconds (``time.process_time``) with OpenCV held to one thread, for each detector. Printed:
mean / median / p95 ms per pair and the rate, per-stage counts, and the map's result against
the bodies' positions. Target (issue 14): >= 25 Hz per pair on one core.

Coverage: a 600 m x 400 m rectangle and an L-shape, fleets of 1-3 heterogeneous RMAXes; printed:
makespan, per-platform area share vs sweep-rate share, transit, uncovered fraction, planning time.

Run: .venv/bin/python bench/saliency.py [--frames 300]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import cv2
import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from hdrc3_navigation.coverage import Platform, footprint_width, plan_coverage
from hdrc3_perception.camera import NavPose
from hdrc3_perception.classifier import ClassifierParams, Detector
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.pipeline import FramePair, PairStatus, PipelineConfig, SaliencyPipeline
from hdrc3_perception.synthetic import Body, render_pair


def scene(rng: np.random.Generator, length: float) -> tuple[list[Body], list[Body]]:
    """Bodies every ~6 m along the track (2-3 in view), warm distractors in between."""
    bodies, distractors = [], []
    north = 0.0
    while north < length:
        bodies.append(Body(rng.uniform(-6, 6), north, rng.uniform(0, 2 * math.pi)))
        distractors.append(
            Body(
                rng.uniform(-7, 7),
                north + 3.0,
                0.0,
                kelvin=rng.choice([309.0, 335.0]),
                length=rng.uniform(1.0, 4.5),
                width=1.2,
            )
        )
        north += rng.uniform(5.0, 8.0)
    return bodies, distractors


def pairs(frames: int, ground: Ground) -> tuple[list[FramePair], list[Body]]:
    """The scan's pairs and the bodies in it."""
    rng = np.random.default_rng(14)
    length = frames * 0.4
    bodies, distractors = scene(rng, length)
    out = []
    for i in range(frames):
        nav = NavPose((0.0, -5.0 + 0.4 * i, 40.0), 0.01, -0.02, 0.05)
        out.append(render_pair(i * 0.04, nav, 0.0, math.pi / 2, bodies + distractors, ground, rng))
    return out, bodies


def processing(frames: int) -> None:
    """Time the pipeline per pair for each detector."""
    cv2.setNumThreads(1)
    ground = Ground()
    stream, bodies = pairs(frames, ground)
    seen = [b for b in bodies if -5.0 + 3.0 < b.north < -5.0 + 0.4 * frames - 3.0]
    print(f"{frames} pairs (720x576 rgb8 + 160x120 mono16), {len(seen)} bodies passed", flush=True)
    for detector in Detector:
        pipeline = SaliencyPipeline(ground, PipelineConfig(classifier=ClassifierParams(detector)))
        times, warm, cand, pos = [], 0, 0, 0
        for pair in stream:
            start = time.process_time()
            result = pipeline.process(pair)
            times.append(time.process_time() - start)
            assert result.status is PairStatus.PROCESSED, result.reason
            warm, cand, pos = (
                warm + result.warm_regions,
                cand + result.candidates,
                pos + result.positives,
            )
        ms = sorted(1000.0 * t for t in times)
        mean = statistics.fmean(ms)
        confirmed = pipeline.map.confirmed()
        found = sum(
            any(math.dist((b.east, b.north), (c.east, c.north)) < 2.0 for c in confirmed)
            for b in seen
        )
        false = sum(
            all(math.dist((b.east, b.north), (c.east, c.north)) >= 2.0 for b in bodies)
            for c in confirmed
        )
        errors = [
            min(math.dist((b.east, b.north), (c.east, c.north)) for b in bodies) for c in confirmed
        ]
        print(
            f"{detector.value:12s} CPU/pair mean {mean:6.2f} ms  "
            f"median {statistics.median(ms):6.2f}"
            f"  p95 {ms[int(0.95 * len(ms))]:6.2f}  -> {1000.0 / mean:6.1f} Hz | per pair: warm "
            f"{warm / frames:.2f} candidates {cand / frames:.2f} positives {pos / frames:.2f} | "
            f"map: {found}/{len(seen)} bodies confirmed, {false} false, "
            f"mean error {statistics.fmean(errors) if errors else math.nan:.2f} m",
            flush=True,
        )


FLEET = [
    Platform("uav0", footprint_width(40.0), 8.0, (-100.0, -50.0)),
    Platform("uav1", footprint_width(30.0), 5.0, (700.0, 450.0)),
    Platform("uav2", footprint_width(50.0), 10.0, (300.0, 600.0)),
]
AREAS = {
    "rectangle 600x400": [(0, 0), (600, 0), (600, 400), (0, 400)],
    "L-shape": [(0, 0), (600, 0), (600, 150), (200, 150), (200, 400), (0, 400)],
}


def coverage() -> None:
    """Plan each area for fleets of 1-3 and print the figures."""
    for name, corners in AREAS.items():
        area = Polygon(corners)
        for n in (1, 2, 3):
            fleet = FLEET[:n]
            start = time.perf_counter()
            plan = plan_coverage(corners, fleet, 40.0)
            planning = time.perf_counter() - start
            swept = shapely.union_all(
                [
                    LineString([s.start[:2], s.end[:2]]).buffer(a.platform.footprint / 2)
                    for a in plan.assignments
                    for s in a.segments
                    if np.allclose(s.start_direction, s.end_direction)
                ]
            )
            total = sum(p.sweep_rate for p in fleet)
            parts = "; ".join(
                f"{a.platform.name} share {a.part.area / area.area:.3f} "
                f"(rate {a.platform.sweep_rate / total:.3f})"
                f" transit {a.transit:.0f} m time {a.duration:.0f} s"
                for a in plan.assignments
            )
            print(
                f"{name:18s} n={n} makespan {plan.makespan:6.0f} s  uncovered "
                f"{area.difference(swept).area / area.area:.5f}  "
                f"planned in {planning * 1000:.0f} ms | {parts}",
                flush=True,
            )


def main() -> None:
    """Print the processing and the coverage figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300, help="pairs in the synthetic scan")
    args = parser.parse_args()
    processing(args.frames)
    coverage()


if __name__ == "__main__":
    main()
