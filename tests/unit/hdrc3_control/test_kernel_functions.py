"""TrackFunction (fcl_track) in the PFC kernel flying the simulated RMAX (lockstep, no ROS).

The colour tracker is replaced by its output: ground fixes of a car driving chase1's laps of
world revinge_chase (sim/drive.py), moved to start 20 m east of the hovering aircraft, with 3 m
of noise per axis, 5 images a second, each read 0.15 s after its image.
"""

from __future__ import annotations

import dataclasses
import math
import random
import statistics
from collections.abc import Callable

import pytest

from hdrc3_control.event_protocol import FINAL
from hdrc3_control.kernel_functions import NO_TRACK
from hdrc3_control.kernel_harness import KernelFlight
from hdrc3_control.pfc_state import Failsafe, FlightMode
from sim.drive import DrivePlan
from sim.sensors.fault import FaultMode
from sim.world_loader import load_world

FIX_PERIOD = 0.2
LATENCY = 0.15
SIGMA = 2.0
LOST = "track: target lost for 3.0 s"


def hovering(f: KernelFlight) -> bool:
    return f.kernel.machine_state("Mode-Switch") == "Hovering-ST"


def speed(f: KernelFlight) -> float:
    return math.hypot(*f.sim.truth(f.agent).velocity_enu[:2])


def airborne() -> KernelFlight:
    """Engine on, autonomous, take-off to 10 m above pad H1, hovering."""
    f = KernelFlight()
    f.engine_on(autonomous=True)
    assert f.run_until(lambda: f.kernel.mode is FlightMode.GROUND_IDLE, 5)
    f.run(12)
    cid = f.send("FCL-Takeoff-EV")
    assert f.run_until(lambda: f.finished(cid) and hovering(f), 60)
    return f


class Car:
    """chase1's drive from 20 m east of the aircraft, departing ``wait`` s from now."""

    def __init__(self, f: KernelFlight, wait: float = 2.0, seed: int = 7) -> None:
        (chase,) = [o for o in load_world("revinge_chase").objects if o.id == "chase1"]
        assert chase.drive is not None
        e, n, _ = f.sim.truth(f.agent).position_enu
        de, dn = e + 20.0 - chase.drive.route[0][0], n - chase.drive.route[0][1]
        route = tuple((x + de, y + dn) for x, y in chase.drive.route)
        self.plan = DrivePlan.of(
            dataclasses.replace(chase.drive, route=route, depart=f.sim.time + wait)
        )
        self.rng = random.Random(seed)
        self.next = f.sim.time - 1.0
        self.pending: list[tuple[float, float, float]] = []
        self.seen = True
        """False: the tracker lost the car (no more fixes)."""

    def feed(self, f: KernelFlight) -> None:
        """Hand the kernel the fixes read by now (what the node's ColorTrack callback does)."""
        while self.next <= f.sim.time:
            pose = self.plan.pose(self.next)
            noisy = (pose.east + self.rng.gauss(0, SIGMA), pose.north + self.rng.gauss(0, SIGMA))
            if self.seen:
                self.pending.append((self.next, *noisy))
            self.next += FIX_PERIOD
        while self.pending and self.pending[0][0] + LATENCY <= f.sim.time:
            t, e, n = self.pending.pop(0)
            assert f.kernel.target_fix(t, e, n, 0.75)

    def distance(self, f: KernelFlight) -> float:
        """True horizontal distance aircraft - car, m."""
        pose = self.plan.pose(f.sim.time)
        e, n, _ = f.sim.truth(f.agent).position_enu
        return math.hypot(pose.east - e, pose.north - n)


def fly(
    f: KernelFlight, car: Car, seconds: float, done: Callable[[], bool] = lambda: False
) -> bool:
    """Tick with the car's fixes for ``seconds`` of sim time or until ``done()``."""
    for _ in range(round(seconds / 0.02)):
        if done():
            return True
        car.feed(f)
        f.tick()
    return done()


def tracking() -> tuple[KernelFlight, Car, int]:
    """Airborne, the car seen for 1 s, fcl_track accepted."""
    f = airborne()
    car = Car(f)
    fly(f, car, 1.0)
    tid = f.send("FCL-Track-EV")
    assert fly(f, car, 2.0, lambda: bool(f.answers(tid)))
    assert f.answers(tid) == [("Cmd-Accepted-EV", "")]
    assert f.kernel.machine_state("Track") == "Track-Run-ST"
    return f, car, tid


def test_track_is_refused_without_a_colour_track() -> None:
    f = airborne()
    tid = f.send("FCL-Track-EV")
    assert f.run_until(lambda: f.finished(tid), 2)
    assert f.answers(tid) == [("Cmd-Rejected-EV", NO_TRACK)]
    assert f.run_until(lambda: hovering(f), 20)


def _cancel(f: KernelFlight, car: Car) -> None:
    f.send("FCL-Cancel-EV")


def _brake(f: KernelFlight, car: Car) -> None:
    f.send("Emergency-Brake-EV")


def _lose(f: KernelFlight, car: Car) -> None:
    car.seen = False


def _drop_gps(f: KernelFlight, car: Car) -> None:
    f.sim.agents[f.agent].sensors.sensors()["gps"].fault.set(FaultMode.DROP, (0.0,))


@pytest.mark.parametrize(
    ("interrupt", "reply", "reason", "within"),
    [
        (_cancel, "Cmd-Cancelled-EV", "cancelled", 1.0),
        (_brake, "Cmd-Cancelled-EV", "emergency brake", 1.0),
        (_lose, "Cmd-Failed-EV", LOST, 3.0 + LATENCY + 0.5),
        (_drop_gps, "Cmd-Failed-EV", "failsafe: GPS lost", 4.0),
    ],
)
def test_a_track_ends_once_braking_to_a_hover(
    interrupt: Callable[[KernelFlight, Car], None], reply: str, reason: str, within: float
) -> None:
    f, car, tid = tracking()
    fly(f, car, 12.0)  # the car drives off at 10 m/s: the aircraft follows it
    assert speed(f) > 5.0
    interrupt(f, car)
    assert fly(f, car, within, lambda: f.finished(tid))
    final = [(n, r) for n, r in f.answers(tid) if n in FINAL]
    assert len(final) == 1 and final[0][0] == reply and final[0][1].startswith(reason), final
    if reply == "Cmd-Failed-EV" and reason == LOST:
        # moving with the car: brake before the hover
        assert fly(f, car, 3.0, lambda: f.kernel.machine_state("Mode-Switch") == "Braking-ST")
    if interrupt is _drop_gps:  # the failsafe flies on (automata/failsafe.hcsm), not Track
        assert fly(f, car, 5.0, lambda: f.kernel.failsafe is Failsafe.HOLD)
        assert f.kernel.machine_state("Mode-Switch") in ("Stop-Ctrl-ST", "Braking-ST")
    else:
        assert fly(f, car, 40.0, lambda: hovering(f) and speed(f) < 1.0)
    assert [(n, r) for n, r in f.answers(tid) if n in FINAL] == final  # one final reply


def test_track_is_refused_while_hovering_on_dead_reckoning() -> None:
    f = airborne()
    car = Car(f)
    _drop_gps(f, car)
    assert fly(f, car, 6.0, lambda: f.kernel.failsafe is Failsafe.HOLD and hovering(f))
    tid = f.send("FCL-Track-EV")
    assert fly(f, car, 1.0, lambda: f.finished(tid))
    ((name, reason),) = f.answers(tid)
    assert name == "Cmd-Rejected-EV" and reason.startswith("failsafe: hovering on dead reckoning")


def test_the_aircraft_keeps_its_distance_behind_a_car_driving_laps() -> None:
    f, car, tid = tracking()
    engaged = f.sim.time
    altitude = f.sim.truth(f.agent).position_enu[2]
    samples: list[tuple[float, float, float]] = []

    def record() -> bool:
        t = f.sim.time - engaged
        samples.append((t, car.distance(f), f.sim.truth(f.agent).position_enu[2]))
        return False

    fly(f, car, 60.0, record)
    assert [n for n, _ in f.answers(tid)] == ["Cmd-Accepted-EV"]  # still following
    settled = [d for t, d, _ in samples if t > 15.0]
    assert max(d for _, d, _ in samples) < 40.0
    assert abs(statistics.mean(settled) - 20.0) < 3.0
    assert min(settled) > 5.0 and max(settled) < 32.0
    assert max(abs(up - altitude) for _, _, up in samples) < 2.5
    cid = f.send("FCL-Cancel-EV")
    assert fly(f, car, 40.0, lambda: f.finished(tid) and hovering(f))
    assert f.answers(tid)[-1] == ("Cmd-Cancelled-EV", "cancelled")
    assert f.answers(cid) == [("Cmd-Accepted-EV", ""), ("Cmd-Finished-EV", "")]
