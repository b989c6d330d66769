"""Algorithm 4 on rendered people: thermal candidates and classifier positives per object.

For every person, dummy and animal of a world (revinge, then ``--worlds N`` generated worlds with
seeds 1..N: ``sim.world_generator``), the real renderer (``sim.render``, moderngl on Mesa) draws
the colour and thermal exposure the RMAX's cameras would take straight down from ``--height`` m
over the object and from ``--views - 1`` offsets around it (up to 3 m, headings varied), with
the cameras' true poses (``camera_pose``: aircraft pose, PTU mount, pan 0, tilt 90 deg). Each
pair goes through ``SaliencyPipeline.process`` for both detectors; the pipeline sees only the
images, the navigation pose and the PTU angles. Printed per detector and object kind: views
with a thermal candidate, views with a positive, and the objects a map would confirm
(positives in more than half of the views, as p_body > 0.5), plus the time per pair.

Run: .venv/bin/python bench/saliency_rendered.py [--height 30] [--views 6] [--worlds 0]
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from hdrc3_perception.camera import Intrinsics as PipelineIntrinsics
from hdrc3_perception.camera import NavPose
from hdrc3_perception.classifier import ClassifierParams, Detector
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.pipeline import CameraImage, FramePair, PipelineConfig, SaliencyPipeline
from sim.render.renderer import Renderer
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, camera_intrinsics
from sim.sensors.camera_model import Intrinsics, camera_pose
from sim.truth_state import TruthState
from sim.world import ObjectKind, World
from sim.world_generator import generated_world
from sim.world_loader import load_world

KINDS = (ObjectKind.PERSON, ObjectKind.DUMMY, ObjectKind.ANIMAL)
OFFSETS = ((0.0, 0.0), (2.0, 1.0), (-2.0, 1.0), (1.0, -2.0), (0.0, 3.0), (-3.0, -1.0))
"""Aircraft offsets from the object, m: all within the thermal camera's 13 m x 10 m at 30 m."""
NADIR = math.pi / 2


def hovering(east: float, north: float, up: float, heading: float) -> TruthState:
    """The aircraft level over a point (what the cameras' pose needs)."""
    return TruthState(
        0.0, (east, north, up), (0.0, 0.0, 0.0), 0.0, 0.0, heading, (0.0, 0.0, 0.0),
        (0.0, 0.0, -9.81), 1500.0, True, False, up, 95.0,
    )  # fmt: skip


def calibration(k: Intrinsics) -> PipelineIntrinsics:
    """The CameraInfo the node would get, as the pipeline reads it."""
    intrinsics = PipelineIntrinsics.from_k(k.width, k.height, list(k.matrix().ravel()))
    assert intrinsics is not None
    return intrinsics


def evaluate(world: World, height: float, views: int) -> None:
    """Print the figures of one world."""
    renderer = Renderer(world, seed=0)
    renderer.set_objects(world.objects)
    ground = Ground(height=world.terrain.height, max_slope=1.0)
    ck, tk = camera_intrinsics(COLOR_CAMERA, 0.0), camera_intrinsics(THERMAL_CAMERA, 0.0)
    targets = [o for o in world.objects if o.kind in KINDS]
    for detector in Detector:
        config = PipelineConfig(classifier=ClassifierParams(detector))
        pipeline = SaliencyPipeline(ground, config)
        table: dict[ObjectKind, list[tuple[int, int]]] = defaultdict(list)
        cpu, pairs, t = 0.0, 0, 0.0
        for obj in targets:
            candidate_views = positive_views = 0
            for i, (de, dn) in enumerate(OFFSETS[:views]):
                east, north = obj.east + de, obj.north + dn
                up = ground.up(east, north) + height
                truth = hovering(east, north, up, 0.3 * i)
                color = renderer.render_color(
                    camera_pose(truth, 0.0, NADIR, COLOR_CAMERA.mount_offset), ck, i
                )
                thermal = renderer.render_thermal(
                    camera_pose(truth, 0.0, NADIR, THERMAL_CAMERA.mount_offset), tk, i
                )
                t += 1.0
                pair = FramePair(
                    t,
                    CameraImage(color, "rgb8", calibration(ck)),
                    CameraImage(thermal, "mono16", calibration(tk)),
                    NavPose((east, north, up), 0.0, 0.0, 0.3 * i),
                    0.0,
                    NADIR,
                )
                start = time.process_time()
                result = pipeline.process(pair)
                cpu += time.process_time() - start
                pairs += 1
                candidate_views += result.candidates > 0
                positive_views += result.positives > 0
            table[obj.kind].append((candidate_views, positive_views))
        for kind in KINDS:
            rows = table.get(kind, [])
            if not rows:
                continue
            confirmed = sum(p > views / 2 for _, p in rows)
            print(
                f"{world.name:>14} {detector.value:>12} {kind.value:>7}: {len(rows):2d} objects, "
                f"views with a thermal candidate {sum(c for c, _ in rows):3d}/{views * len(rows)}, "
                f"with a positive {sum(p for _, p in rows):3d}, "
                f"confirmed (positive in > half the views) {confirmed}/{len(rows)}",
                flush=True,
            )
        print(
            f"{world.name:>14} {detector.value:>12}: {1000 * cpu / pairs:.1f} ms CPU per pair",
            flush=True,
        )
    renderer.release()


def main() -> None:
    """Print the figures for revinge and the generated worlds."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--height", type=float, default=30.0, help="m above ground")
    parser.add_argument("--views", type=int, default=len(OFFSETS), choices=range(1, 7))
    parser.add_argument("--worlds", type=int, default=0, help="generated worlds (seeds 1..N)")
    args = parser.parse_args()
    print(f"nadir views from {args.height:g} m, {args.views} per object", flush=True)
    evaluate(load_world("revinge"), args.height, args.views)
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.worlds + 1):
            evaluate(generated_world(seed, Path(tmp) / f"gen{seed}.toml"), args.height, args.views)


if __name__ == "__main__":
    main()
