"""How closely a world restored from a checkpoint continues, and what a checkpoint costs.

One world (revinge, two agents) flies uav0 in autonomous mode (climb, then forward flight with
a yaw rate) for ``--fly`` sim seconds; its checkpoint is decoded into a second world. Both then
take the same commands and the table prints the distance between the two uav0 (position,
velocity, heading) right after the restore and after some ticks: the error of restoring JSBSim
through ``ic/`` properties and ``run_ic()`` (integrator histories restart), everything else
(sensor noise streams, YAS, YACS, rotor and drive train) being restored bit for bit.
The cost lines time ``encode`` (pickle + SHA-256) and ``decode`` (incl. two JSBSim loads).

Run: .venv/bin/python bench/checkpoint_restore.py [--fly 30]
"""

from __future__ import annotations

import argparse
import math
import time

from sim import checkpoint
from sim.rc_transmitter import FlightModeSwitch
from sim.world_loader import load_world
from sim.world_sim import SimConfig, WorldSim
from sim.yacs import YacsCommand

REPORT_AFTER = (0, 1, 5, 50, 500, 1500)
"""Ticks after the restore at which the difference is printed."""


def command(tick: int, cruise_from: int) -> YacsCommand:
    """Climb, then fly forward and turn."""
    if tick < cruise_from:
        return YacsCommand(vertical=1.5)
    return YacsCommand(pitch=-0.12, vertical=0.3, yaw_rate=0.05)


def main() -> None:
    """Fly, checkpoint, restore, compare; print one line per report tick and the costs."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fly", type=float, default=30.0, help="sim s before the checkpoint")
    args = parser.parse_args()
    config = SimConfig(load_world("revinge"), ("uav0", "uav1"), seed=1)
    original = WorldSim(config)
    rc = original.agents["uav0"].aircraft.rc
    rc.set_engine(True)
    rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ticks = round(args.fly * 50)
    cruise_from = ticks // 2
    for k in range(ticks):
        original.command("uav0", command(k, cruise_from))
        original.advance()
        original.take_readings()
    run = checkpoint.RunState("bench")
    start = time.perf_counter()
    data = checkpoint.encode(original, run, 25)
    encode_s = time.perf_counter() - start
    restored = WorldSim(config)
    start = time.perf_counter()
    found = checkpoint.decode(data, restored)
    decode_s = time.perf_counter() - start
    state = found.state
    assert state is not None, found.reason
    restored.resume(state.tick, state.agents, state.wind, state.objects)
    truth = original.truth("uav0")
    print(
        f"checkpoint at t = {truth.time:.1f} s: uav0 {truth.position_enu[2]:.1f} m up, "
        f"{math.hypot(*truth.velocity_enu):.1f} m/s, {len(data)} bytes",
        flush=True,
    )
    print(f"{'ticks after':>11} {'d position m':>13} {'d velocity m/s':>15} {'d heading rad':>14}")
    done = 0
    for report in REPORT_AFTER:
        for k in range(ticks + done, ticks + report):
            for sim in (original, restored):
                sim.command("uav0", command(k, cruise_from))
                sim.advance()
                sim.take_readings()
        done = report
        a, b = original.truth("uav0"), restored.truth("uav0")
        print(
            f"{report:>11} {math.dist(a.position_enu, b.position_enu):>13.2e} "
            f"{math.dist(a.velocity_enu, b.velocity_enu):>15.2e} "
            f"{abs(a.heading - b.heading):>14.2e}",
            flush=True,
        )
    print(f"encode {encode_s * 1e3:.1f} ms, decode {decode_s * 1e3:.1f} ms", flush=True)


if __name__ == "__main__":
    main()
