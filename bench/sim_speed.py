"""Simulation speed of the RMAX flight model + YACS at 200 Hz (simulated s per wall s).

Each case is a function returning a ``Result``; ``CASES`` lists them and ``main`` prints a table.

The world_sim cases start the real `hdrc3-world-sim` node and a separate controller process
(bench/lockstep_controller.py) on a private ROS domain:
- lockstep: world_sim advances only when the controller answered the tick (speed 0 = unpaced);
  the controller reads the attitude sensor, or every control sensor incl. the 200 Hz IMU;
- free-running: no controller; the observer measures how fast /clock advances at a given speed.
"x RT (cpu)" of the lockstep cases is per CPU second of the world_sim process alone (nan for
free-running cases, where world_sim's CPU window cannot be aligned with the measurement).

Run: .venv/bin/python bench/sim_speed.py [--seconds 60] [--only lockstep]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import psutil

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


BENCH_DIR = Path(__file__).resolve().parent
WORLD_SIM = str(Path(sys.executable).parent / "hdrc3-world-sim")
DOMAIN_ID = int(os.environ.get("HDRC3_BENCH_DOMAIN", "140"))


def world_sim_case(
    name: str, count: int, seconds: float, speed: float, lockstep: bool, sensors: str = "attitude"
) -> Result:
    """Run world_sim with ``count`` aircraft and a separate controller (or observer) process."""
    agents = [f"uav{i}" for i in range(count)]
    quoted = ",".join(f"'{a}'" for a in agents)
    env = dict(os.environ, ROS_DOMAIN_ID=str(DOMAIN_ID), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    ros_args = ["--ros-args", "-p", f"agents:=[{quoted}]", "-p", f"speed:={speed!r}"]
    if lockstep:
        ros_args += ["-p", f"lockstep:=[{quoted}]"]
    cmd = [sys.executable, str(BENCH_DIR / "lockstep_controller.py"), "--agents", ",".join(agents)]
    cmd += ["--seconds", str(seconds), "--sensors", sensors]
    if not lockstep:
        cmd.append("--observe")
    with tempfile.TemporaryFile() as log:  # world_sim's log, shown only if the case fails
        sim = subprocess.Popen([WORLD_SIM, *ros_args], env=env, stdout=log, stderr=log)
        try:
            probe = psutil.Process(sim.pid)
            before = probe.cpu_times()
            out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
            after = probe.cpu_times()
            lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
            report = json.loads(lines[-1]) if lines else {"error": out.stderr[-500:]}
            if "error" in report:
                log.seek(0)
                raise RuntimeError(f"{name}: {report}; world_sim: {log.read()[-2000:].decode()}")
        finally:
            sim.send_signal(signal.SIGINT)
            try:
                sim.wait(timeout=10)
            except subprocess.TimeoutExpired:
                sim.kill()
    # free-running, world_sim also runs while the observer starts: its CPU window is unknown
    cpu = (after.user + after.system) - (before.user + before.system) if lockstep else math.nan
    return Result(name, count, report["sim"], report["wall"], cpu)


CASES: list[Callable[[float], Result]] = [
    lambda s: fdm_yacs(1, s),
    lambda s: fdm_yacs(3, s),
    lambda s: world_sim_case("lockstep x1", 1, s, 0.0, True),
    lambda s: world_sim_case("lockstep x3", 3, s, 0.0, True),
    lambda s: world_sim_case("lockstep x1 all", 1, s, 0.0, True, "all"),
    lambda s: world_sim_case("lockstep x3 all", 3, s, 0.0, True, "all"),
    lambda s: world_sim_case("free max x1", 1, s, 0.0, False),
    lambda s: world_sim_case("free max x3", 3, s, 0.0, False),
    lambda s: world_sim_case("free 5x x1", 1, min(s, 20.0), 5.0, False),
]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0, help="simulated seconds per case")
    parser.add_argument("--only", default="", help="run only cases whose name contains this")
    args = parser.parse_args()
    header = ("case", "aircraft", "sim s", "wall s", "cpu s", "x real time", "x RT (cpu)")
    widths = (9, 9, 9, 9, 13, 12)
    print(
        f"{header[0]:<20}" + "".join(f"{h:>{w}}" for h, w in zip(header[1:], widths, strict=True))
    )
    names = ["FDM+YACS x1", "FDM+YACS x3", "lockstep x1", "lockstep x3", "lockstep x1 all"]
    names += ["lockstep x3 all", "free max x1", "free max x3", "free 5x x1"]
    for case, case_name in zip(CASES, names, strict=True):
        if args.only not in case_name:
            continue
        r = case(args.seconds)
        print(
            f"{r.name:<20}{r.aircraft:>9}{r.sim_seconds:>9.1f}{r.wall_seconds:>9.3f}"
            f"{r.cpu_seconds:>9.3f}{r.real_time_factor:>13.1f}{r.cpu_time_factor:>12.1f}"
        )
    print("x real time: simulated s / wall s for all aircraft together; x RT (cpu): per CPU s")
    print(
        f"load average: {' '.join(f'{x:.2f}' for x in os.getloadavg())} on {os.cpu_count()} cores"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
