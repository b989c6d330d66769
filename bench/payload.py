"""Cost of the payload rigid bodies (MuJoCo) per simulated second, and their share of a tick.

Cases on the revinge world (6 boxes, 2 carriers), stepped at the flight model's 200 Hz:
- resting: every object asleep on the ground, one stowed hook under a hovering winch;
- falling: a box dropped from 10 m bouncing to rest (first 5 s after the release);
- carrying: a box on 1 m of cable under a winch flying a 2 m circle at 4 m/s;
- world_sim: one full WorldSim second (flight model, sensors, payload) of an aircraft on its pad,
  and the payload's part of it.
Figures are process CPU milliseconds per simulated second (lower is better).

Run: .venv/bin/python bench/payload.py [--seconds 20]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable

from rich.console import Console
from rich.table import Table

from sim.payload import PayloadWorld
from sim.world import BoxContents, DynamicObject, ObjectKind
from sim.world_loader import load_world
from sim.world_sim import FDM_RATE_HZ, TICK_RATE_HZ, SimConfig, WorldSim

DT = 1.0 / FDM_RATE_HZ
WORLD = load_world("revinge")
BOX1 = next(o for o in WORLD.objects if o.id == "box1")
GROUND = WORLD.terrain.height(BOX1.east, BOX1.north)
ANCHOR = (BOX1.east, BOX1.north, GROUND + 3.0)


def _cpu_ms(run: Callable[[], None]) -> float:
    start = time.process_time()
    run()
    return (time.process_time() - start) * 1000.0


def _stepping(world: PayloadWorld, steps: int) -> Callable[[], None]:
    """Run ``steps`` payload steps with the winch held at ANCHOR."""

    def run() -> None:
        for _ in range(steps):
            world.step(DT, {"uav0": ANCHOR})

    return run


def resting(seconds: float) -> float:
    """CPU ms per sim second with every object at rest and a stowed hook."""
    world = PayloadWorld(WORLD.terrain, list(WORLD.objects), {"uav0": ANCHOR})
    for _ in range(FDM_RATE_HZ):  # settle (objects fall asleep)
        world.step(DT, {"uav0": ANCHOR})
    steps = round(seconds * FDM_RATE_HZ)
    return _cpu_ms(_stepping(world, steps)) / seconds


def falling(seconds: float) -> float:
    """CPU ms per sim second of a box falling from 10 m and bouncing (the first 5 s)."""
    drop = DynamicObject(
        "drop", ObjectKind.BOX, -100.0, 50.0, 0.3, (0.4, 0.4, 0.3), None, BoxContents.WATER, 5.0
    )
    total = 0.0
    runs = max(1, round(seconds / 5.0))
    for _ in range(runs):
        world = PayloadWorld(WORLD.terrain, [*WORLD.objects, drop], {"uav0": ANCHOR})
        world.place("drop", -100.0, 50.0, WORLD.terrain.height(-100.0, 50.0) + 10.0)
        total += _cpu_ms(_stepping(world, 5 * FDM_RATE_HZ))
    return total / (5.0 * runs)


def carrying(seconds: float) -> float:
    """CPU ms per sim second of a box swinging under a winch flying a circle."""
    world = PayloadWorld(WORLD.terrain, list(WORLD.objects), {"uav0": ANCHOR})
    world.command("uav0", 2.95, magnet=True)
    for _ in range(6 * FDM_RATE_HZ):
        world.step(DT, {"uav0": ANCHOR})
    world.command("uav0", 1.0, magnet=True)
    for _ in range(6 * FDM_RATE_HZ):
        world.step(DT, {"uav0": ANCHOR})
    assert world.reading("uav0").carrying, "the bench's pick-up failed"
    steps = round(seconds * FDM_RATE_HZ)

    def fly() -> None:
        for k in range(steps):
            a = 2.0 * k * DT  # 4 m/s on a 2 m radius, starting where the winch hovers
            anchor = (ANCHOR[0] + 2.0 * math.cos(a) - 2.0, ANCHOR[1] + 2.0 * math.sin(a), ANCHOR[2])
            world.step(DT, {"uav0": anchor})

    return _cpu_ms(fly) / seconds


def world_sim(seconds: float) -> tuple[float, float]:
    """CPU ms per sim second of a whole WorldSim tick loop, and of its payload part."""
    sim = WorldSim(SimConfig(WORLD, ("uav0",)))
    payload_ms = 0.0
    step = sim.payload.step

    def timed(dt: float, anchors: dict[str, tuple[float, float, float]]) -> None:
        nonlocal payload_ms
        start = time.process_time()
        step(dt, anchors)
        payload_ms += (time.process_time() - start) * 1000.0

    sim.payload.step = timed  # type: ignore[method-assign]  # measuring wrapper
    ticks = round(seconds * TICK_RATE_HZ)

    def run() -> None:
        for _ in range(ticks):
            sim.advance()

    total = _cpu_ms(run)
    return total / seconds, payload_ms / seconds


def main(argv: list[str] | None = None) -> int:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="sim seconds per case")
    args = parser.parse_args(argv)
    console = Console(force_terminal=False, soft_wrap=True)
    table = Table(title=f"payload physics, {args.seconds:g} sim s per case (CPU ms per sim s)")
    table.add_column("case")
    table.add_column("CPU ms / sim s", justify="right")
    for name, case in (("resting", resting), ("falling", falling), ("carrying", carrying)):
        table.add_row(name, f"{case(args.seconds):.1f}")
        console.print(f"{name} done", highlight=False)
    whole, part = world_sim(args.seconds)
    table.add_row("world_sim tick loop (1 aircraft)", f"{whole:.1f}")
    table.add_row("  of which payload", f"{part:.1f} ({100.0 * part / whole:.0f} %)")
    console.print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
