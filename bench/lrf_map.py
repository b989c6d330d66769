"""Laser elevation map of revinge's town block (chapter section 11.2): accuracy, changes, planning.

A closed-loop flight in process: the JSBSim RMAX of ``sim.world_sim`` in ``revinge_changed`` (a
container C1 and new trees V-new that the stack's model, ``revinge``, lacks), flown by the PFC
kernel (:class:`~hdrc3_control.kernel_harness.KernelFlight`) along the coverage pattern the
``laser-map-area`` executor flies, 30 m above the block at 6 m/s, with ``--wind`` m/s of wind.
The LMS-291 (1 deg, 180 deg, 13 ms per scan, 1 cm noise) turns at 3 rad/s; the laser mapper
registers every scan with the kernel's own state estimate (GPS, IMU, barometer with their noise)
at the Data Interface's 25 Hz, as the ``laser_mapper`` node does.

Printed:
- the map: mapped cells, RMS / p95 / max height error against the highest point of the true
  surface in each cell (what a cell stores) and, for reference, against the surface at the cell
  centre (larger along walls: a cell half on a roof holds the roof);
- the overlay with the model: every region found, and whether C1 and V-new are among them;
- planning: a low flight through the corridor (6, -95, 7) -> (6, 8, 7) in the model alone and
  in the model with the map stored in the GIS; the path's clearance from C1 (the margin is 6 m);
- costs: registration time per scan, time to store the map in the GIS.

Writes ``--out``/lrf_map.png: the map, the model's buildings, the changes found and both paths.
Run: .venv/bin/python bench/lrf_map.py [--out out/lrf] [--seed 3] [--wind 3]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import matplotlib
import numpy as np
import shapely
from shapely.geometry import Point, Polygon

from hdrc3_control.kernel import FlightMode
from hdrc3_control.kernel_harness import KernelFlight
from hdrc3_navigation.coverage import CoverageStatus, Platform, plan_part
from hdrc3_navigation.elevation_map import ElevationMap
from hdrc3_navigation.gis import Gis
from hdrc3_navigation.planner import PathPlanner, PlanRequest, PlanStatus
from hdrc3_perception.camera import NavPose
from hdrc3_perception.laser_mapping import LaserMapper, ScanLine
from hdrc3_perception.laser_node import cropped
from hdrc3_tst.rmax_executors import laser_swath_width
from sim.sensors.power import PowerDevice
from sim.wind import WindSettings
from sim.world_loader import load_world

matplotlib.use("Agg")
import matplotlib.pyplot as plt

AREA = ((-30.0, -75.0), (85.0, -75.0), (85.0, -10.0), (-30.0, -10.0))
"""The town block of ``examples/tst/lrf_mapping.tst``."""
ALTITUDE, SPEED, ROTATION = 30.0, 6.0, 3.0
CORRIDOR = ((6.0, -95.0, 7.0), (6.0, 8.0, 7.0))
STATE_PERIOD = 0.04
"""s: the Data Interface's 25 Hz."""
SPIN_UP_S = 20.0


def waypoints(start: tuple[float, float]) -> list[tuple[float, float, float]]:
    """The corners of the executor's coverage pattern, 30 m above the block's highest corner."""
    world = load_world("revinge")
    ground = max(world.terrain.height(e, n) for e, n in AREA)
    me = Platform("uav0", laser_swath_width(ALTITUDE), SPEED, start)
    plan = plan_part(list(AREA), 1, 1, me, ground + ALTITUDE, 3.0)
    assert plan.status is CoverageStatus.PLANNED, plan.reason
    segments = plan.assignments[0].segments
    points = [tuple(segments[0].start)] + [tuple(s.end) for s in segments]
    return [(float(p[0]), float(p[1]), float(p[2])) for p in points]


def fly(seed: int, wind: float) -> tuple[LaserMapper, list[float], list[tuple[float, float]]]:
    """Take off, fly the pattern with the laser collecting; the mapper and per-scan costs."""
    flight = KernelFlight(
        seed=seed, world="revinge_changed", wind=WindSettings((wind, 0.0, 0.0), 0.5)
    )
    sensors = flight.sim.agents[flight.agent].sensors
    mapper = LaserMapper(flight.world.bounds)
    costs: list[float] = []
    track: list[tuple[float, float]] = []
    flight.engine_on(autonomous=True)
    spun_up: float | None = None
    command: int | None = None
    legs: list[tuple[float, float, float]] | None = None
    leg = (0.0, 0.0, 0.0)
    next_state = 0.0
    while True:
        snap = flight.tick().snapshot
        mode = flight.kernel.mode
        if spun_up is None and mode is FlightMode.GROUND_IDLE:
            spun_up = snap.time + SPIN_UP_S
        elif command is None and spun_up is not None and snap.time >= spun_up:
            command = flight.send("FCL-Takeoff-EV")
        elif command is not None and flight.finished(command) and mode is FlightMode.HOVER:
            refused = any(name == "Cmd-Rejected-EV" for name, _ in flight.answers(command))
            if legs is None:
                legs = waypoints((snap.position[0], snap.position[1]))
                print(f"  take-off done at {snap.time:.0f} s; {len(legs)} waypoints", flush=True)
            elif refused:  # the hover mode still settling: the same leg again
                legs.insert(0, leg)
            elif not sensors.power.is_on(PowerDevice.LASER):  # at the first corner: collect
                sensors.laser.set_rotation_speed(ROTATION)
                sensors.power.switch(PowerDevice.LASER, True)
            if not legs:
                break
            leg = legs.pop(0)
            command = flight.send("Traj3D-Flyto-EV", (*leg, SPEED))
        for r in flight.readings:
            if r.laser is not None:
                s = r.laser
                beams = s.beam_angles
                mapper.add_scan(
                    ScanLine(
                        s.time,
                        s.rotation_angle,
                        beams[0],
                        beams[1] - beams[0],
                        np.asarray(s.ranges),
                    )
                )
        if snap.time >= next_state:
            next_state += STATE_PERIOD
            pose = NavPose(tuple(snap.position), snap.roll, snap.pitch, snap.heading)
            t0 = time.perf_counter()
            clouds = mapper.add_state(snap.time, pose)
            if clouds:
                costs.append((time.perf_counter() - t0) / len(clouds))
            if sensors.power.is_on(PowerDevice.LASER):
                track.append((snap.position[0], snap.position[1]))
        if snap.time > 900.0:
            raise SystemExit(f"the pattern was not flown in 900 s (mode {mode})")
    print(f"  pattern flown at {flight.sim.time:.0f} s", flush=True)
    return mapper, costs, track


def clearance(points: np.ndarray, footprint: Polygon, top: float) -> float:
    """Least distance of path points from a prism (ground to ``top``) over ``footprint``."""
    best = math.inf
    for e, n, u in points:
        horizontal = float(shapely.distance(footprint, Point(e, n)))
        best = min(best, math.hypot(horizontal, max(0.0, u - top)))
    return best


def path_points(planner: PathPlanner) -> np.ndarray | str:
    """The corridor flight's path sampled every metre or so, or why there is none."""
    result = planner.plan(PlanRequest(CORRIDOR[0], CORRIDOR[1], 3.0, timeout=10.0))
    if result.status is not PlanStatus.SOLVED:
        return f"{result.status.value}: {result.reason}"
    samples = []
    for seg in result.segments:
        n = max(2, math.ceil(seg.arc_length()))
        samples += [seg.position(float(s)) for s in np.linspace(0.0, 1.0, n)]
    return np.asarray(samples, dtype=np.float64)


def profile(
    ax: plt.Axes,
    m: ElevationMap,
    stale: np.ndarray | str,
    fresh: np.ndarray | str,
    container: Polygon,
    top: float,
) -> None:
    """The corridor seen from the side: the map under the line, C1, both paths' heights."""
    north = np.linspace(CORRIDOR[0][1], CORRIDOR[1][1], 400)
    east = np.full_like(north, CORRIDOR[0][0])
    ax.plot(north, m.heights_at(east, north), "k-", lw=1, label="map along east 6 m")
    n0, n1 = container.bounds[1], container.bounds[3]
    ax.add_patch(plt.Rectangle((n0, 0.0), n1 - n0, top, fc="red", alpha=0.4, label="C1 (true)"))
    for label, pts, style in (("model only", stale, "b--"), ("model + map", fresh, "m-")):
        if not isinstance(pts, str):
            ax.plot(pts[:, 1], pts[:, 2], style, lw=1.5, label=f"path, {label}")
    ax.set_xlabel("north, m")
    ax.set_ylabel("up, m")
    ax.set_title("the corridor from the side: the planner climbs 6 m clear of the mapped container")
    ax.legend(loc="upper left", fontsize=8)


def main() -> None:
    """Fly, map, compare, plan, print and plot."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/lrf"))
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--wind", type=float, default=3.0, help="m/s from the west")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    print(f"mapping flight (seed {args.seed}, wind {args.wind:g} m/s) ...", flush=True)
    mapper, costs, track = fly(args.seed, args.wind)
    raw = cropped(mapper.snapshot("lrf-bench"))
    changed = load_world("revinge_changed")
    model_world = load_world("revinge")
    print(
        f"before alignment: RMS {raw.score(changed.surface_heights).rms:.3f} m against the true"
        " surface"
    )
    t0 = time.perf_counter()
    m, shift = raw.aligned_to(model_world.surface_heights)
    print(
        f"aligned to the model by ({shift.east:+.2f}, {shift.north:+.2f}, {shift.up:+.2f}) m "
        f"in {time.perf_counter() - t0:.2f} s: misfit {shift.misfit_before:.3f} -> "
        f"{shift.misfit_after:.3f} m"
    )
    score = m.score(changed.surface_heights)
    print(
        f"map: {score.cells} cells of {m.resolution:g} m mapped ({m.columns} x {m.rows} grid),"
        f" {mapper.points} returns, {sum(mapper.dropped.values())} scans dropped"
    )
    print(
        f"height error vs the highest true point per cell, all mapped cells: "
        f"RMS {score.rms:.3f} m, p95 {score.p95:.3f} m (target RMS <= 0.5)"
    )
    share = score.away_cells / score.cells
    print(
        f"  on the {score.away_cells} cells ({share:.0%}) at least 2 m from a height step: "
        f"RMS {score.away_rms:.3f} m"
    )
    changes = m.compare(model_world.surface_heights)
    new = {
        b.name: Polygon(b.footprint)
        for b in changed.buildings
        if b.name not in {x.name for x in model_world.buildings}
    }
    new |= {
        v.name: Polygon(v.polygon)
        for v in changed.vegetation
        if v.name not in {x.name for x in model_world.vegetation}
    }
    found = set()
    for c in changes:
        hits = [name for name, fp in new.items() if shapely.box(*c.bounds).intersects(fp)]
        found |= set(hits)
        print(
            f"change: {c.kind.value} {c.area:.0f} m^2 at ({c.centre[0]:.1f}, {c.centre[1]:.1f}),"
            f" {c.height:+.1f} m -> {', '.join(hits) or 'NOT a change of the world'}"
        )
    print(f"changes of the world found: {sorted(found)} of {sorted(new)}")

    container = next(b for b in changed.buildings if b.name == "C1")
    footprint = Polygon(container.footprint)
    planner = PathPlanner(Gis(model_world))
    stale = path_points(planner)
    t0 = time.perf_counter()
    triangles = planner.gis.add_elevation_map(m)
    stored = time.perf_counter() - t0
    fresh = path_points(planner)
    for label, pts in (("model only", stale), ("model + map", fresh)):
        if isinstance(pts, str):
            print(f"corridor path, {label}: none ({pts})")
        else:
            length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
            print(
                f"corridor path, {label}: {length:.0f} m, clearance from C1 "
                f"{clearance(pts, footprint, container.top):.2f} m (margin 6)"
            )
    print(f"GIS: {triangles} triangles stored in {stored * 1000:.0f} ms")
    if costs:
        print(f"registration: mean {np.mean(costs) * 1e6:.0f} us per scan of 181 beams")

    fig, (ax, side) = plt.subplots(
        2, 1, figsize=(9, 10), gridspec_kw={"height_ratios": [3, 1.4]}, layout="constrained"
    )
    shown = np.ma.masked_invalid(m.heights)
    extent = (
        m.east0,
        m.east0 + m.columns * m.resolution,
        m.north0,
        m.north0 + m.rows * m.resolution,
    )
    image = ax.imshow(shown, origin="lower", extent=extent, cmap="terrain")
    fig.colorbar(image, ax=ax, label="height, m (local up)")
    for b in model_world.buildings:
        ax.plot(*Polygon(b.footprint).exterior.xy, color="k", lw=0.8)
    for c in changes:
        ax.add_patch(
            plt.Rectangle(
                c.bounds[:2],
                c.bounds[2] - c.bounds[0],
                c.bounds[3] - c.bounds[1],
                fill=False,
                ec="red",
                lw=2,
            )
        )
    for label, pts, style in (("model only", stale, "b--"), ("model + map", fresh, "m-")):
        if not isinstance(pts, str):
            ax.plot(pts[:, 0], pts[:, 1], style, lw=1.5, label=f"corridor path, {label}")
    if track:
        ax.plot(*np.asarray(track).T, color="white", lw=0.6, label="track while collecting")
    ax.set_xlim(extent[0], extent[1])
    ax.set_ylim(min(extent[2], CORRIDOR[0][1]), max(extent[3], CORRIDOR[1][1]))
    ax.set_title("laser elevation map over the model (black); changes found in red")
    ax.set_xlabel("east, m")
    ax.set_ylabel("north, m")
    ax.legend(loc="lower right", fontsize=8)
    profile(side, m, stale, fresh, footprint, container.top)
    fig.savefig(args.out / "lrf_map.png", dpi=90)
    print(f"wrote {args.out / 'lrf_map.png'}")


if __name__ == "__main__":
    main()
