"""Algorithm 4 on rendered people: per-stage figures per object, and scans building the map.

For every person, dummy, animal and car of a world (revinge, then ``--worlds N`` generated worlds
with seeds 1..N: ``sim.world_generator``), the real renderer (``sim.render``, moderngl on Mesa)
draws the colour and thermal exposure the RMAX's cameras take straight down, with the cameras'
true poses (``camera_pose``: aircraft pose, PTU mount, pan 0, tilt 90 deg). Every pair goes
through ``SaliencyPipeline.process``; the pipeline sees only the images, the navigation pose and
the PTU angles. The world file's objects are read here only to place the views and to score.

1. Views (per detector): ``--views`` nadir views from ``--height`` m over each object (offsets
   up to 3 m, headings varied). Printed per object kind: views with a thermal candidate, views
   with a classifier positive, objects positive in more than half their views, CPU per pair.
2. Scans (``--scan``, the default detector): over every object a lawn-mower pattern of
   ``--legs`` legs 40 m long at ``--height`` m and 5 m/s, legs spaced by 0.8 of the strip both
   cameras see (as ``scan-area`` plans them), the square's centre up to 5 m off the object,
   ``--rate`` pairs per second, one map for the whole world. Printed: per warm person the frames
   it was in view (T_frame), the frames with a positive (T_body) and the distance of the nearest
   confirmed location; confirmed locations farther than 4 m from every person (false
   positives); the mean geolocation error; the per-view detection rate of warm people; CPU per
   pair (``time.process_time`` of ``process`` alone, rendering excluded).

Run: .venv/bin/python bench/saliency_rendered.py [--height 30] [--views 6] [--worlds 0]
     [--scan] [--rate 5] [--legs 3] [--no-views] [--no-revinge]
"""

from __future__ import annotations

import argparse
import itertools
import math
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

from hdrc3_navigation.coverage import pair_footprint_width
from hdrc3_perception.camera import CameraPose, NavPose
from hdrc3_perception.camera import Intrinsics as PipelineIntrinsics
from hdrc3_perception.classifier import ClassifierParams, Detector
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.pipeline import CameraImage, FramePair, PipelineConfig, SaliencyPipeline
from sim.render.renderer import Renderer
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, camera_intrinsics
from sim.sensors.camera_model import Intrinsics, camera_pose
from sim.truth_state import TruthState
from sim.world import DynamicObject, ObjectKind, World
from sim.world_generator import generated_world
from sim.world_loader import load_world

KINDS = (ObjectKind.PERSON, ObjectKind.DUMMY, ObjectKind.ANIMAL, ObjectKind.CAR)
OFFSETS = ((0.0, 0.0), (2.0, 1.0), (-2.0, 1.0), (1.0, -2.0), (0.0, 3.0), (-3.0, -1.0))
"""Aircraft offsets from the object, m: all within the thermal camera's 13 m x 10 m at 30 m."""
NADIR = math.pi / 2
WARM_C = 27.0
"""Scoring only: a person the world file makes warmer than this is one the thermal step is
meant to find (the cool 'persons' of revinge, 22-24 C, play the chapter's dummies)."""
SPEED = 5.0
LEG_M = 40.0
FOUND_M = 3.0
FALSE_M = 4.0


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


class Camera:
    """Renders the pair of one aircraft pose as the pipeline gets it."""

    def __init__(self, world: World) -> None:
        self.renderer = Renderer(world, seed=0)
        self.renderer.set_objects(world.objects)
        self.ground = Ground(height=world.terrain.height, max_slope=1.0)
        self.ck = camera_intrinsics(COLOR_CAMERA, 0.0)
        self.tk = camera_intrinsics(THERMAL_CAMERA, 0.0)

    def pair(self, t: float, east: float, north: float, height: float, heading: float) -> FramePair:
        """The pair taken at ``t`` s from ``height`` m over (east, north), cameras down."""
        up = self.ground.up(east, north) + height
        truth = hovering(east, north, up, heading)
        stamp = round(t * 1e9)
        color = self.renderer.render_color(
            camera_pose(truth, 0.0, NADIR, COLOR_CAMERA.mount_offset), self.ck, stamp
        )
        thermal = self.renderer.render_thermal(
            camera_pose(truth, 0.0, NADIR, THERMAL_CAMERA.mount_offset), self.tk, stamp
        )
        return FramePair(
            t,
            CameraImage(color, "rgb8", calibration(self.ck)),
            CameraImage(thermal, "mono16", calibration(self.tk)),
            NavPose((east, north, up), 0.0, 0.0, heading),
            0.0,
            NADIR,
        )


def warm_person(obj: DynamicObject) -> bool:
    """Scoring only: a person the thermal step is meant to find."""
    kelvin = obj.temperature if obj.temperature is not None else 0.0
    return obj.kind is ObjectKind.PERSON and kelvin - 273.15 > WARM_C


def label(obj: DynamicObject) -> str:
    """Kind for the tables (persons split warm / cool)."""
    if obj.kind is ObjectKind.PERSON:
        return "person" if warm_person(obj) else "cool person"
    return obj.kind.value


def views(world: World, camera: Camera, height: float, count: int) -> None:
    """Part 1: per-stage figures of ``count`` nadir views of every object, both detectors."""
    targets = [o for o in world.objects if o.kind in KINDS]
    for detector in Detector:
        config = PipelineConfig(classifier=ClassifierParams(detector), detect_frozen=False)
        pipeline = SaliencyPipeline(camera.ground, config)
        table: dict[str, list[tuple[int, int]]] = defaultdict(list)
        cpu, pairs, t = 0.0, 0, 0.0
        for obj in targets:
            candidate_views = positive_views = 0
            for i, (de, dn) in enumerate(OFFSETS[:count]):
                t += 1.0
                pair = camera.pair(t, obj.east + de, obj.north + dn, height, 0.3 * i)
                start = time.process_time()
                result = pipeline.process(pair)
                cpu += time.process_time() - start
                pairs += 1
                near = [
                    d for d in result.detections
                    if math.dist(d.ground[:2], (obj.east, obj.north)) < FOUND_M
                ]  # fmt: skip
                candidate_views += result.candidates > 0
                positive_views += bool(near)
            table[label(obj)].append((candidate_views, positive_views))
        for kind, rows in table.items():
            confirmed = sum(p > count / 2 for _, p in rows)
            print(
                f"{world.name:>14} {detector.value:>12} {kind:>11}: {len(rows):2d} objects, "
                f"views with a thermal candidate {sum(c for c, _ in rows):3d}/{count * len(rows)}, "
                f"with a positive on it {sum(p for _, p in rows):3d}, "
                f"positive in > half the views {confirmed}/{len(rows)}",
                flush=True,
            )
        print(
            f"{world.name:>14} {detector.value:>12}: {1000 * cpu / pairs:.1f} ms CPU per pair",
            flush=True,
        )


def lawn_mower(centre: tuple[float, float], legs: int, along_north: bool) -> list[list[float]]:
    """Waypoints (east, north) of ``legs`` legs of LEG_M m centred on ``centre``."""
    spacing = 0.8 * pair_footprint_width(30.0)
    points = []
    for k in range(legs):
        across = (k - (legs - 1) / 2.0) * spacing
        a, b = -LEG_M / 2.0, LEG_M / 2.0
        if k % 2:
            a, b = b, a
        for s in (a, b):
            e, n = (across, s) if along_north else (s, across)
            points.append([centre[0] + e, centre[1] + n])
    return points


def scans(world: World, camera: Camera, height: float, rate: float, legs: int) -> None:
    """Part 2: a lawn-mower scan over every object, one map; the figures of leg I."""
    config = PipelineConfig(detect_frozen=False)
    pipeline = SaliencyPipeline(camera.ground, config)
    rng = np.random.default_rng(7)
    people = [o for o in world.objects if warm_person(o)]
    in_view: dict[str, int] = defaultdict(int)
    positive: dict[str, int] = defaultdict(int)
    cpu, pairs, t = 0.0, 0, 0.0
    for k, obj in enumerate(o for o in world.objects if o.kind in KINDS):
        centre = (obj.east + rng.uniform(-5.0, 5.0), obj.north + rng.uniform(-5.0, 5.0))
        route = lawn_mower(centre, legs, along_north=bool(k % 2))
        for (e0, n0), (e1, n1) in itertools.pairwise(route):
            length = math.hypot(e1 - e0, n1 - n0)
            heading = math.atan2(e1 - e0, n1 - n0)  # clockwise from north
            for j in range(max(int(length / SPEED * rate), 1)):
                f = j / (length / SPEED * rate)
                t += 1.0 / rate
                pair = camera.pair(t, e0 + f * (e1 - e0), n0 + f * (n1 - n0), height, heading)
                start = time.process_time()
                result = pipeline.process(pair)
                cpu += time.process_time() - start
                pairs += 1
                seen = visible_people(pipeline, pair, people)
                for person in seen:
                    in_view[person.id] += 1
                    if any(
                        math.dist(d.ground[:2], (person.east, person.north)) < FOUND_M
                        for d in result.detections
                    ):
                        positive[person.id] += 1
    confirmed = pipeline.map.confirmed()
    errors = []
    for person in people:
        d = min(
            (math.dist((c.east, c.north), (person.east, person.north)) for c in confirmed),
            default=math.inf,
        )
        errors.append(d)
        print(
            f"{world.name:>14} {person.id:>10}: in view {in_view[person.id]:3d} pairs, "
            f"positive {positive[person.id]:3d}, nearest confirmed {d:5.2f} m",
            flush=True,
        )
    false = [
        c for c in confirmed
        if min((math.dist((c.east, c.north), (p.east, p.north)) for p in people),
               default=math.inf) > FALSE_M
    ]  # fmt: skip
    for c in false:
        near = min(world.objects, key=lambda o: math.dist((o.east, o.north), (c.east, c.north)))
        print(
            f"{world.name:>14} false positive at ({c.east:.1f}, {c.north:.1f}) p_body "
            f"{c.p_body:.2f} T_frame {c.t_frame}: nearest object {near.id}",
            flush=True,
        )
    found = [e for e in errors if e <= FOUND_M]
    seen_pairs = sum(in_view.values())
    print(
        f"{world.name:>14} scan ({legs} legs x {LEG_M:g} m at {height:g} m, {SPEED:g} m/s, "
        f"{rate:g} pairs/s, {pairs} pairs): warm people confirmed {len(found)}/{len(people)}, "
        f"false positives {len(false)}, mean geolocation error "
        f"{(sum(found) / len(found)) if found else math.nan:.2f} m, detection rate per view "
        f"{sum(positive.values()) / max(seen_pairs, 1):.2f} ({seen_pairs} person views), "
        f"{1000 * cpu / pairs:.1f} ms CPU per pair",
        flush=True,
    )


def visible_people(
    pipeline: SaliencyPipeline, pair: FramePair, people: list[DynamicObject]
) -> list[DynamicObject]:
    """Scoring only: the people in both views as the map counts them (T_frame's margin)."""
    if not people:
        return []
    points = np.array([(p.east, p.north, pipeline.ground.up(p.east, p.north)) for p in people])
    cfg = pipeline.config
    color = CameraPose.of(pair.nav, pair.pan, pair.tilt, cfg.color_mount)
    thermal = CameraPose.of(pair.nav, pair.pan, pair.tilt, cfg.thermal_mount)
    ck, tk = pair.color.intrinsics, pair.thermal.intrinsics
    assert ck is not None and tk is not None
    mask = color.sees(ck, points, cfg.view_margin_m) & thermal.sees(tk, points, cfg.view_margin_m)
    return [p for p, m in zip(people, mask, strict=True) if m]


def evaluate(world: World, args: argparse.Namespace) -> None:
    """Print the figures of one world."""
    camera = Camera(world)
    if not args.no_views:
        views(world, camera, args.height, args.views)
    if args.scan:
        scans(world, camera, args.height, args.rate, args.legs)
    camera.renderer.release()


def main() -> None:
    """Print the figures for revinge and the generated worlds."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--height", type=float, default=30.0, help="m above ground")
    parser.add_argument("--views", type=int, default=len(OFFSETS), choices=range(1, 7))
    parser.add_argument("--worlds", type=int, default=0, help="generated worlds (seeds 1..N)")
    parser.add_argument("--scan", action="store_true", help="also fly scans (part 2)")
    parser.add_argument("--no-views", action="store_true", help="skip part 1")
    parser.add_argument("--rate", type=float, default=5.0, help="pairs per second in scans")
    parser.add_argument("--legs", type=int, default=3, help="legs per scan")
    parser.add_argument("--no-revinge", action="store_true", help="generated worlds only")
    args = parser.parse_args()
    print(f"nadir views from {args.height:g} m, {args.views} per object", flush=True)
    if not args.no_revinge:
        evaluate(load_world("revinge"), args)
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.worlds + 1):
            evaluate(generated_world(seed, Path(tmp) / f"gen{seed}.toml"), args)


if __name__ == "__main__":
    main()
