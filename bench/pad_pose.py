"""Landing-pad pose estimation (chapter §5.4) over the landing mode's 20 m hemisphere.

Draws ``--views`` camera positions uniformly in distance (``--min`` to 20 m from the pad's
centre) and in elevation (30 to 90 deg) around the pad, aims the colour camera (720 x 576,
48 deg) at the pad with a pointing error of up to ``--pointing`` deg (the PTU's tracking lag)
and a random roll, renders the pattern (``pad_view.render``: exact ray-plane intersection,
2x2 supersampling) with Gaussian image noise of ``--noise`` grey levels, and runs
``pad_pose.estimate`` on it. Printed per distance band: the share of views with a pose, the
median and largest error of the pad's position in the camera frame and of the camera's position
on the pad, and the estimation rate (images per second of one core's CPU time; rendering
excluded). Target (issue 16): pose estimation >= 25 Hz.

Run: .venv/bin/python bench/pad_pose.py [--views 200] [--seed 1] [--noise 4] [--pointing 5]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from hdrc3_perception.pad_pose import PoseStatus, estimate
from hdrc3_perception.pad_view import look_at, render
from hdrc3_perception.synthetic import COLOR_K

BANDS = ((0.0, 5.0), (5.0, 10.0), (10.0, 15.0), (15.0, 20.0))


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    axis = axis / np.linalg.norm(axis)
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def main() -> None:
    """Run the views and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--views", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--min", type=float, default=1.5, help="nearest view, m")
    parser.add_argument("--noise", type=float, default=4.0, help="image noise sigma, grey levels")
    parser.add_argument("--pointing", type=float, default=5.0, help="aiming error, deg")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    rows: dict[tuple[float, float], list[tuple[bool, float, float]]] = {b: [] for b in BANDS}
    statuses: dict[str, int] = {}
    cpu = 0.0
    for _ in range(args.views):
        distance = rng.uniform(args.min, 20.0)
        elevation = math.radians(rng.uniform(30.0, 90.0))
        azimuth = rng.uniform(0.0, 2.0 * math.pi)
        eye = distance * np.array(
            [
                math.cos(elevation) * math.cos(azimuth),
                math.cos(elevation) * math.sin(azimuth),
                math.sin(elevation),
            ]
        )
        rotation, _ = look_at(tuple(eye), roll=rng.uniform(-math.pi, math.pi))
        miss = _rotation(rng.normal(size=3), math.radians(rng.uniform(0.0, args.pointing)))
        rotation = miss @ rotation
        translation = -rotation @ eye
        image = render(COLOR_K, rotation, translation).astype(np.float64)
        image += rng.normal(0.0, args.noise, image.shape)
        gray = np.clip(np.round(image), 0, 255).astype(np.uint8)
        start = time.process_time()
        pose = estimate(gray, COLOR_K)
        cpu += time.process_time() - start
        statuses[pose.status.value] = statuses.get(pose.status.value, 0) + 1
        band = next(b for b in BANDS if b[0] <= distance < b[1] or distance == 20.0 == b[1])
        if pose.status is PoseStatus.OK and pose.translation is not None:
            pad_error = float(np.linalg.norm(pose.translation - translation))
            camera_error = float(np.linalg.norm(pose.camera_in_pad - eye))
            rows[band].append((True, pad_error, camera_error))
        else:
            rows[band].append((False, math.nan, math.nan))
    print(f"views {args.views}, seed {args.seed}, noise {args.noise}, pointing {args.pointing} deg")
    print(
        "band (m)  | views | with pose | pad in camera cm median/max | camera on pad cm median/max"
    )
    for band, results in rows.items():
        good = [r for r in results if r[0]]
        if not results:
            continue
        pad = [100.0 * r[1] for r in good] or [math.nan]
        cam = [100.0 * r[2] for r in good] or [math.nan]
        print(
            f"{band[0]:4.0f}-{band[1]:<4.0f} | {len(results):5d} | "
            f"{len(good) / len(results):8.0%} | "
            f"{np.median(pad):8.1f} / {max(pad):6.1f} | {np.median(cam):8.1f} / {max(cam):6.1f}",
            flush=True,
        )
    print(f"statuses: {statuses}")
    print(
        f"estimation rate: {args.views / cpu:.1f} Hz (CPU {1000.0 * cpu / args.views:.1f} ms/image)"
    )


if __name__ == "__main__":
    main()
