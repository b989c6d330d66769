"""Helicopter fixes from the landing pad (chapter §5.4) on the simulator's renderer, against truth.

Draws ``--views`` helicopter poses in the landing mode's 20 m hemisphere over revinge's vision
pad L1 (distance camera - pad uniform in ``--min`` .. 20 m, elevation 30 .. 90 deg, heading
uniform, roll and pitch within +-5 deg), points the PTU at the pad (``look_at_angles``, the
PPC's own geometry), renders the colour camera with the simulator's renderer (moderngl,
``sim.render``) exactly as world_render does, with the camera platform's pointing jitter
(0.1 deg, ``sim.sensors.camera``) in the rendered angles and the PTU encoder noise (0.05 deg,
``sim.sensors.ptu``) in the angles the stack reads. Then ``pad_pose.estimate`` and
``pad_fix.helicopter_fix`` (pad from the world file, mount offset from ``sim.airframe``).

Printed per distance band: views with a fix, the helicopter position error (3-D and
horizontal; median / 95th percentile / max, cm), the heading error (deg), the share of fixes
within the 99 % sphere of their own ``fix_sigma`` (3.37 sigma), and the CPU time per image of
estimate + fix. Ground truth is used here only to score the fixes.

Run: .venv/bin/python bench/landing.py [--views 120] [--seed 1]
"""

from __future__ import annotations

import argparse
import math
import time

import cv2
import numpy as np

from hdrc3_control.ppc_modes import Pose, look_at_angles
from hdrc3_perception.camera import Intrinsics
from hdrc3_perception.pad_fix import FixStatus, PadPlacement, helicopter_fix
from hdrc3_perception.pad_pose import PoseStatus, estimate
from sim.render.renderer import Renderer
from sim.sensors.camera import COLOR_CAMERA, camera_intrinsics
from sim.sensors.camera_model import camera_pose
from sim.sensors.ptu import PtuParams
from sim.truth_state import TruthState
from sim.world_loader import load_world

BANDS = ((0.0, 5.0), (5.0, 10.0), (10.0, 15.0), (15.0, 20.0))
CHI3_99 = math.sqrt(11.345)
"""Radius (in sigmas) holding 99 % of a 3-D Gaussian with ``sigma`` per axis."""


def _truth(position: np.ndarray, roll: float, pitch: float, heading: float) -> TruthState:
    p = (float(position[0]), float(position[1]), float(position[2]))
    return TruthState(0.0, p, (0.0, 0.0, 0.0), roll, pitch, heading, (0.0, 0.0, 0.0),
                      (0.0, 0.0, -9.81), 1500.0, True, False, p[2], 80.0)  # fmt: skip


def main() -> None:
    """Run the views and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--views", type=int, default=120)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--min", type=float, default=2.0, help="nearest view, m")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    world = load_world("revinge")
    placement = PadPlacement.of_world(world)
    renderer = Renderer(world)
    sim_k = camera_intrinsics(COLOR_CAMERA, 0.0)
    k = Intrinsics(sim_k.width, sim_k.height, sim_k.fx, sim_k.fy, sim_k.cx, sim_k.cy)
    jitter, encoder = COLOR_CAMERA.jitter, PtuParams().encoder_noise
    rows: dict[tuple[float, float], list[tuple[float, float, float, bool] | None]] = {
        b: [] for b in BANDS
    }
    statuses: dict[str, int] = {}
    cpu = 0.0
    for _ in range(args.views):
        distance = rng.uniform(args.min, 20.0)
        elevation = math.radians(rng.uniform(30.0, 90.0))
        azimuth = rng.uniform(0.0, 2.0 * math.pi)
        offset = distance * np.array([math.cos(elevation) * math.cos(azimuth),
                                      math.cos(elevation) * math.sin(azimuth),
                                      math.sin(elevation)])  # fmt: skip
        heading = rng.uniform(0.0, 2.0 * math.pi)
        roll, pitch = (math.radians(a) for a in rng.uniform(-5.0, 5.0, 2))
        position = placement.origin + offset  # the camera near here: the CG 0.5 m away
        pan, tilt = look_at_angles(
            Pose(tuple(position), roll, pitch, heading), tuple(placement.origin)
        )
        shown = (pan + rng.normal(0.0, jitter), tilt + rng.normal(0.0, jitter))
        read = (pan + rng.normal(0.0, encoder), tilt + rng.normal(0.0, encoder))
        truth = _truth(position, roll, pitch, heading)
        rgb = renderer.render_color(camera_pose(truth, *shown, COLOR_CAMERA.mount_offset), sim_k)
        gray = cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2GRAY)
        start = time.process_time()
        pose = estimate(gray, k)
        fix = None
        if pose.status is PoseStatus.OK and pose.rotation is not None:
            assert pose.translation is not None
            fix = helicopter_fix(0.0, pose.rotation, pose.translation, read, placement)
        cpu += time.process_time() - start
        statuses[pose.status.value] = statuses.get(pose.status.value, 0) + 1
        band = next(b for b in BANDS if b[0] <= distance < b[1] or distance == 20.0 == b[1])
        if fix is None or fix.status is not FixStatus.OK:
            rows[band].append(None)
            continue
        error = np.asarray(fix.position) - position
        turn = abs((fix.heading - heading + math.pi) % math.tau - math.pi)
        within = float(np.linalg.norm(error)) <= CHI3_99 * fix.sigma
        rows[band].append((float(np.linalg.norm(error)), math.hypot(error[0], error[1]),
                           math.degrees(turn), within))  # fmt: skip
    renderer.release()
    print(f"revinge L1, simulator renderer 720x576 48 deg, views {args.views}, seed {args.seed}")
    print("band (m)  | views | fixes | 3-D error cm med/p95/max | horiz. cm med/p95/max "
          "| heading deg med/max | within 99 % of sigma")  # fmt: skip
    for band, results in rows.items():
        good = [r for r in results if r is not None]
        if not results:
            continue
        if not good:
            print(f"{band[0]:4.0f}-{band[1]:<4.0f} | {len(results):5d} |    0%", flush=True)
            continue
        e3 = np.array([100.0 * r[0] for r in good])
        eh = np.array([100.0 * r[1] for r in good])
        hd = np.array([r[2] for r in good])
        print(
            f"{band[0]:4.0f}-{band[1]:<4.0f} | {len(results):5d} | "
            f"{len(good) / len(results):5.0%} | "
            f"{np.median(e3):5.1f} / {np.percentile(e3, 95):5.1f} / {e3.max():5.1f} | "
            f"{np.median(eh):5.1f} / {np.percentile(eh, 95):5.1f} / {eh.max():5.1f} | "
            f"{np.median(hd):5.2f} / {hd.max():5.2f} | {np.mean([r[3] for r in good]):5.0%}",
            flush=True,
        )
    print(f"statuses: {statuses}")
    print(f"estimate + fix: {1000.0 * cpu / args.views:.1f} ms CPU per image "
          f"({args.views / cpu:.0f} Hz)")  # fmt: skip


if __name__ == "__main__":
    main()
