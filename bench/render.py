"""Rendering rate of colour + thermal frames per aircraft (issue 14 target: >= 25 Hz each).

Renders what world_render renders: for every aircraft one colour frame and one thermal frame
per exposure, from poses along a survey line over revinge (40 m up, cameras tilted 60 deg down),
in one process (as the node does). Prints frames/s per aircraft (wall clock) and CPU time per
colour+thermal pair (``time.process_time``: every thread of the process, llvmpipe's included).

    .venv/bin/python bench/render.py [--frames 100] [--save DIR]

``--save DIR`` also writes example frames (colour PNG, thermal as false colour 280-310 K) of
views from 40 m at bodies and distractors in revinge.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

from sim.render.imaging import CENTI_KELVIN
from sim.render.projection import look_at
from sim.render.renderer import Renderer
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, camera_intrinsics
from sim.sensors.camera_model import CameraPose, Intrinsics
from sim.world_loader import load_world


def poses(agent: int, frames: int) -> list[CameraPose]:
    """Camera poses of one aircraft flying east at 5 m/s, 40 m up, looking ahead and down."""
    out = []
    for k in range(frames):
        east = -150.0 + 0.2 * k
        north = -40.0 + 60.0 * agent
        eye = (east, north, 40.0)
        target = (east + 40.0 / math.tan(math.radians(60.0)), north, 0.0)
        out.append(look_at(eye, target))
    return out


def run(renderer: Renderer, agents: int, frames: int, color: Intrinsics) -> tuple[float, float]:
    """(pairs per second per aircraft, CPU ms per pair)."""
    thermal = camera_intrinsics(THERMAL_CAMERA, 0.0)
    tracks = [poses(a, frames) for a in range(agents)]
    renderer.render_color(tracks[0][0], color)  # warm-up: shaders, framebuffers
    renderer.render_thermal(tracks[0][0], thermal)
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for k in range(frames):
        stamp = k * 40_000_000
        for track in tracks:
            renderer.render_color(track[k], color, stamp)
            renderer.render_thermal(track[k], thermal, stamp)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    return frames / wall, 1e3 * cpu / (frames * agents)


EXAMPLES = {
    "body01": ("body01", 8.0, 40.0, 0.0),
    "body05": ("body05", 12.0, 40.0, 0.0),
    "body07": ("body07", 10.0, 35.0, 0.0),
    "body04_zoom": ("body04", 8.0, 35.0, 0.4),
    "body07_zoom": ("body07", 8.0, 35.0, 0.4),
    "dummy1": ("dummy1", 10.0, 40.0, 0.0),
    "animal3": ("animal3", 15.0, 45.0, 0.0),
    "body10_cool": ("body10", 10.0, 60.0, 0.0),
}
"""File stem -> (object looked at, metres south of it, height above it, colour zoom)."""


def save_examples(renderer: Renderer, out: Path) -> None:
    """Colour and thermal frames of the EXAMPLES views (published resolutions)."""
    import matplotlib.pyplot as plt

    world = renderer.world
    objects = {o.id: o for o in world.objects}
    out.mkdir(parents=True, exist_ok=True)
    for stem, (ident, south, height, zoom) in EXAMPLES.items():
        obj = objects[ident]
        ground = world.terrain.height(obj.east, obj.north)
        pose = look_at(
            (obj.east, obj.north - south, ground + height), (obj.east, obj.north, ground)
        )
        colour = renderer.render_color(pose, camera_intrinsics(COLOR_CAMERA, zoom), 1)
        counts = renderer.render_thermal(pose, camera_intrinsics(THERMAL_CAMERA, 0.0), 1)
        plt.imsave(out / f"{stem}_color.png", colour)
        kelvin = counts / CENTI_KELVIN
        plt.imsave(out / f"{stem}_thermal.png", kelvin, cmap="inferno", vmin=280.0, vmax=310.0)
        print(
            f"{out / stem}_{{color,thermal}}.png: {ident} from {height:.0f} m up, "
            f"{south:.0f} m south, colour zoom {zoom}; "
            f"thermal {kelvin.min():.1f}..{kelvin.max():.1f} K",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=100, help="exposures per aircraft")
    parser.add_argument("--save", type=Path, help="directory for example frames (PNG)")
    args = parser.parse_args()
    world = load_world("revinge")
    renderer = Renderer(world)
    if args.save is not None:
        save_examples(renderer, args.save)
    print(
        f"renderer: {renderer.renderer_name}; cores: {os.cpu_count()}; "
        f"load average {os.getloadavg()[0]:.1f}",
        flush=True,
    )
    print(f"scene: revinge, {args.frames} exposures per aircraft, thermal 160x120", flush=True)
    sizes = {
        "640x480 (issue target)": Intrinsics.from_fov(640, 480, math.radians(48.0)),
        "720x576 (published, COLOR_CAMERA)": Intrinsics.from_fov(720, 576, math.radians(48.0)),
    }
    for label, color in sizes.items():
        for agents in (1, 2):
            rate, cpu_ms = run(renderer, agents, args.frames, color)
            verdict = "meets" if rate >= 25.0 else "BELOW"
            print(
                f"colour {label}, {agents} aircraft: {rate:6.1f} colour+thermal pairs/s per "
                f"aircraft ({verdict} 25 Hz); CPU {cpu_ms:5.1f} ms per pair",
                flush=True,
            )
    renderer.release()


if __name__ == "__main__":
    main()
