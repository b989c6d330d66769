"""Draw a world's map (PNG) and measure geometry query and laser scan throughput.

Usage: .venv/bin/python bench/world_map.py [world] [out.png]
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Polygon

from sim.sensors.fake_truth import make_truth
from sim.sensors.laser import LaserRangeFinder
from sim.world import ObjectKind
from sim.world_geometry import WorldGeometry
from sim.world_loader import load_world


def draw(name: str, out: Path) -> None:
    world = load_world(name)
    fig, ax = plt.subplots(figsize=(12, 8))
    e0, n0, e1, n1 = world.bounds
    grid = world.terrain.array()
    image = ax.imshow(grid, origin="lower", extent=(e0, e1, n0, n1), cmap="Greens_r", alpha=0.5)
    fig.colorbar(image, ax=ax, label="terrain height (m)")
    for road in world.roads:
        xs, ys = zip(*road.points, strict=True)
        ax.plot(xs, ys, color="grey", linewidth=road.width * 0.6, solid_capstyle="butt")
    for veg in world.vegetation:
        ax.add_patch(Polygon(veg.polygon, color="darkgreen", alpha=0.5))
    for zone in world.no_fly_zones:
        ax.add_patch(Polygon(zone.polygon, fill=False, hatch="//", color="red"))
    for b in world.buildings:
        ax.add_patch(Polygon(b.footprint, color=plt.cm.copper(b.height / 15.0)))
        cx = sum(p[0] for p in b.footprint) / len(b.footprint)
        cy = sum(p[1] for p in b.footprint) / len(b.footprint)
        ax.text(
            cx, cy, f"{b.name}\n{b.height:g} m", fontsize=6, ha="center", va="center", color="w"
        )
    for pad in world.pads:
        ax.add_patch(Circle((pad.east, pad.north), pad.radius, color="blue", alpha=0.6))
        ax.text(pad.east, pad.north, pad.name, color="w", ha="center", va="center")
    for depot in world.depots:
        ax.add_patch(Circle((depot.east, depot.north), depot.radius, fill=False, color="purple"))
        ax.text(depot.east, depot.north + depot.radius + 3, depot.name, ha="center", fontsize=7)
    markers = {
        ObjectKind.PERSON: "r*",
        ObjectKind.BOX: "ks",
        ObjectKind.CARRIER: "mD",
        ObjectKind.CAR: "c>",
        ObjectKind.DUMMY: "y*",
        ObjectKind.ANIMAL: "b^",
    }
    for kind, style in markers.items():
        objs = world.objects_of(kind)
        ax.plot([o.east for o in objs], [o.north for o in objs], style, label=kind.value)
    for place in world.places:
        ax.plot(place.east, place.north, "k+")
        ax.text(place.east + 3, place.north + 3, place.name, fontsize=7)
    ax.set_xlim(e0, e1)
    ax.set_ylim(n0, n1)
    ax.set_aspect("equal")
    ax.set_xlabel("east (m)")
    ax.set_ylabel("north (m)")
    ax.set_title(f"{world.name}: origin {world.origin.latitude} N {world.origin.longitude} E")
    ax.legend(loc="lower right")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"map written to {out}")


def throughput(name: str) -> None:
    world = load_world(name)
    started = time.perf_counter()
    geometry = WorldGeometry(world)
    print(f"index build: {1e3 * (time.perf_counter() - started):.1f} ms")
    rng = np.random.default_rng(0)
    e0, n0, e1, n1 = world.bounds
    count = 2000
    points = rng.uniform((e0, n0), (e1, n1), size=(count, 2))
    started = time.perf_counter()
    inside = sum(geometry.point_in_building(float(e), float(n)) is not None for e, n in points)
    elapsed = time.perf_counter() - started
    print(f"point_in_building: {count / elapsed:,.0f} queries/s ({inside} of {count} inside)")
    started = time.perf_counter()
    hits = 0
    for e, n in points[:500]:
        angle = float(rng.uniform(0.0, 2 * math.pi))
        direction = (math.cos(angle), math.sin(angle), -0.1)
        hits += geometry.ray_cast((float(e), float(n), 20.0), direction, 80.0) is not None
    elapsed = time.perf_counter() - started
    print(f"ray_cast (80 m): {500 / elapsed:,.0f} rays/s ({hits} of 500 hit)")
    lrf = LaserRangeFinder(geometry)
    truth = make_truth(position_enu=(-60.0, 40.0, 8.0), heading=math.pi / 2)
    started = time.perf_counter()
    scans = 0
    for k in range(40):
        if lrf.update(make_truth(k * lrf.period, position_enu=truth.position_enu)) is not None:
            scans += 1
    elapsed = time.perf_counter() - started
    print(
        f"laser scan (181 beams): {1e3 * elapsed / scans:.1f} ms per scan, "
        f"{scans * lrf.period / elapsed:.2f}x real time at {lrf.rate_hz:.0f} Hz"
    )


if __name__ == "__main__":
    world_name = sys.argv[1] if len(sys.argv) > 1 else "revinge"
    target = Path(sys.argv[2]) if len(sys.argv) > 2 else Path("out") / f"{world_name}_map.png"
    draw(world_name, target)
    throughput(world_name)
