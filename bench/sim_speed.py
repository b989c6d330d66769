"""Simulation speed of the RMAX flight model + YACS at 200 Hz (simulated s per wall s).

Each case is a function returning a ``Result``; ``CASES`` lists them and ``main`` prints a table.
More cases (e.g. lockstep over DDS with the world_sim node) can be appended to ``CASES``.

Run: .venv/bin/python bench/sim_speed.py [--seconds 60]
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

from sim.aircraft import Aircraft
from sim.flight_model import InitialPlacement
from sim.rc_transmitter import FlightModeSwitch
from sim.velocity_hold import VelocityHold
from sim.yacs import YacsCommand


@dataclass(frozen=True)
class Result:
    """Outcome of one benchmark case."""

    name: str
    aircraft: int
    sim_seconds: float
    wall_seconds: float
    cpu_seconds: float

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second (all aircraft together)."""
        return self.sim_seconds / self.wall_seconds

    @property
    def cpu_time_factor(self) -> float:
        """Simulated seconds per second of this process's CPU time (independent of other load)."""
        return self.sim_seconds / self.cpu_seconds


def _fleet(count: int) -> list[Aircraft]:
    fleet = []
    for i in range(count):
        ac = Aircraft(placement=InitialPlacement(east=30.0 * i, heading=0.5 * i), payload=10.0)
        ac.rc.set_engine(True)
        ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
        fleet.append(ac)
    return fleet


def fdm_yacs(count: int, seconds: float) -> Result:
    """Engine start, 10 s spin-up, climb, then a 50 Hz velocity-hold outer loop at 10 m/s east."""
    fleet = _fleet(count)
    holds = [VelocityHold() for _ in fleet]
    steps = round(seconds * 200.0)
    start = time.perf_counter()
    cpu_start = time.process_time()
    for k in range(steps):
        t = k * 0.005
        for ac, hold in zip(fleet, holds, strict=True):
            if k % 4 == 0:
                if t < 20.0:
                    ac.command(YacsCommand(vertical=1.5 if t > 10.0 else 0.0))
                else:
                    ac.command(hold.update(ac.truth(), 0.02, (10.0, 0.0), 0.0, math.pi / 2))
            ac.step()
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu_start
    for ac in fleet:
        s = ac.truth()
        if s.on_ground or not math.isfinite(s.position_enu[0]):
            raise RuntimeError(f"benchmark flight failed: {s}")
    return Result(f"FDM+YACS x{count}", count, seconds, wall, cpu)


CASES: list[Callable[[float], Result]] = [
    lambda s: fdm_yacs(1, s),
    lambda s: fdm_yacs(3, s),
]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0, help="simulated seconds per case")
    args = parser.parse_args()
    header = ("case", "aircraft", "sim s", "wall s", "cpu s", "x real time", "x RT (cpu)")
    widths = (9, 9, 9, 9, 13, 12)
    print(
        f"{header[0]:<20}" + "".join(f"{h:>{w}}" for h, w in zip(header[1:], widths, strict=True))
    )
    for case in CASES:
        r = case(args.seconds)
        print(
            f"{r.name:<20}{r.aircraft:>9}{r.sim_seconds:>9.1f}{r.wall_seconds:>9.3f}"
            f"{r.cpu_seconds:>9.3f}{r.real_time_factor:>13.1f}{r.cpu_time_factor:>12.1f}"
        )
    print("x real time: simulated s / wall s for all aircraft together; x RT (cpu): per CPU s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
