"""Closed-loop harness: the hdrc3_control core flying the simulated RMAX in-process.

The simulator (``sim``) is the world: ``Aircraft`` (FDM + YACS at 200 Hz) and ``SensorSuite``.
The stack side is ``hdrc3_control``: the ``StateEstimator`` fed with the sensor samples and a
control function called at 50 Hz whose ``AttitudeCommand`` is mapped to a ``YacsCommand``. Used by
bench/control_kernel.py and (loaded by file path) by tests/unit/hdrc3_control.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hdrc3_control.braking import BrakeOutput, BrakeStatus, EmergencyBrake
from hdrc3_control.commands import AttitudeCommand, EstimatedState, VerticalMode
from hdrc3_control.hover import HoverController, HoverOutput, HoverSetpoint, HoverStatus
from hdrc3_control.landing import Landing, LandingOutput, LandingPhase, LandingTarget
from hdrc3_control.measurements import (
    AttitudeMeasurement,
    BaroMeasurement,
    GpsMeasurement,
    GroundContactMeasurement,
    ImuMeasurement,
)
from hdrc3_control.path_following import PathEvent, PathFollower, PathOutput, PathStatus
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.state_estimator import EstimatorConfig, StateEstimator
from hdrc3_control.takeoff import Takeoff, TakeoffConfig, TakeoffOutput, TakeoffStatus
from sim.aircraft import Aircraft
from sim.flight_model import InitialPlacement
from sim.rc_transmitter import FlightModeSwitch
from sim.sensors.power import PowerDevice
from sim.sensors.suite import SensorReadings, SensorSuite
from sim.truth_state import TruthState
from sim.world_geometry import WorldGeometry
from sim.world_loader import load_world
from sim.yacs import VerticalMode as YacsVerticalMode
from sim.yacs import YacsCommand

CONTROL_HZ = 50
FDM_PER_TICK = 4
"""200 Hz FDM steps per 50 Hz control tick."""

Controller = Callable[[EstimatedState, float], AttitudeCommand]


def to_yacs(cmd: AttitudeCommand) -> YacsCommand:
    """The node's mapping of the kernel output to the YACS interface."""
    mode = (
        YacsVerticalMode.COLLECTIVE
        if cmd.vertical_mode is VerticalMode.COLLECTIVE
        else YacsVerticalMode.VERTICAL_RATE
    )
    return YacsCommand(cmd.roll, cmd.pitch, cmd.yaw_rate, cmd.vertical, mode)


@dataclass
class FlightLog:
    """One row per control tick."""

    time: list[float] = field(default_factory=list)
    truth: list[TruthState] = field(default_factory=list)
    estimate: list[EstimatedState] = field(default_factory=list)
    command: list[AttitudeCommand] = field(default_factory=list)

    def arrays(self) -> dict[str, np.ndarray]:
        """Columns as numpy arrays (t, truth/estimate position and velocity)."""
        return {
            "t": np.array(self.time),
            "pos": np.array([s.position_enu for s in self.truth]),
            "vel": np.array([s.velocity_enu for s in self.truth]),
            "est_pos": np.array([s.position for s in self.estimate]),
            "est_vel": np.array([s.velocity for s in self.estimate]),
        }


class GustModel:
    """First-order Gauss-Markov gust per axis (horizontal sigma, vertical half of it)."""

    def __init__(self, sigma: float, tau: float, seed: int) -> None:
        self.sigma = sigma
        self.tau = tau
        self.rng = np.random.default_rng(seed)
        self.value = np.zeros(3)

    def step(self, dt: float) -> tuple[float, float, float]:
        """Advance by dt and return the gust velocity (ENU)."""
        if self.sigma <= 0.0:
            return (0.0, 0.0, 0.0)
        a = math.exp(-dt / self.tau)
        scale = np.array([self.sigma, self.sigma, 0.5 * self.sigma])
        self.value = a * self.value + math.sqrt(1 - a * a) * scale * self.rng.standard_normal(3)
        return (float(self.value[0]), float(self.value[1]), float(self.value[2]))


class SimFlight:
    """One aircraft in the Revinge world with sensors, the estimator and a 50 Hz control slot."""

    def __init__(
        self,
        seed: int = 1,
        payload: float = 0.0,
        wind: tuple[float, float, float] = (0.0, 0.0, 0.0),
        gust_sigma: float = 0.0,
        placement: InitialPlacement | None = None,
        estimator: EstimatorConfig | None = None,
    ) -> None:
        self.world = load_world("revinge")
        o = self.world.origin
        self.suite = SensorSuite(self.world, seed=seed, geometry=WorldGeometry(self.world))
        # imaging payloads cost milliseconds per frame and play no part in flight control
        for dev in (
            PowerDevice.COLOR_CAMERA,
            PowerDevice.THERMAL_CAMERA,
            PowerDevice.LASER,
            PowerDevice.PTU,
        ):
            self.suite.power.switch(dev, on=False)
        # the YACS flies on the same suite the estimator is fed from (as in world_sim)
        self.aircraft = Aircraft(
            placement=placement or InitialPlacement(),
            origin=(o.latitude, o.longitude, o.altitude),
            terrain_height=self.world.terrain.height,
            payload=payload,
            sensors=self.suite,
        )
        self.estimator = StateEstimator(estimator)
        self.wind = wind
        self.gusts = GustModel(gust_sigma, 2.0, seed + 1000)
        self.log = FlightLog()
        self.dt_fdm = self.aircraft.model.dt
        self.dt = self.dt_fdm * FDM_PER_TICK
        self.gps_blocked = False
        self.touchdowns: list[TruthState] = []
        """Truth at each FDM step where the skids made contact (airborne the step before)."""
        self.aircraft.model.set_wind(wind)

    @property
    def now(self) -> float:
        """Sim time, s."""
        return self.aircraft.model.time

    def truth(self) -> TruthState:
        """Ground truth now."""
        return self.aircraft.truth()

    def state(self) -> EstimatedState:
        """The navigation filter's estimate now."""
        return self.estimator.estimate(self.now)

    def _feed(self, r: SensorReadings) -> None:
        est = self.estimator
        if r.attitude is not None:
            a = r.attitude
            est.update_attitude(AttitudeMeasurement(a.time, a.roll, a.pitch, a.heading))
        if r.imu is not None:
            est.update_imu(ImuMeasurement(r.imu.time, r.imu.specific_force, r.imu.angular_rate))
        if r.gps is not None and not self.gps_blocked:
            est.update_gps(GpsMeasurement(r.gps.time, r.gps.position_enu, r.gps.velocity_enu))
        if r.barometer is not None:
            height = r.barometer.altitude - self.world.origin.altitude
            est.update_baro(BaroMeasurement(r.barometer.time, height))
        if r.rpm is not None:
            est.update_rpm(r.rpm.rpm)
        if r.ground_contact is not None:
            if est.initialised:
                e, n, _ = est.estimate(r.ground_contact.time).position
            else:
                e, n, _ = self.truth().position_enu
            ground = self.world.terrain.height(e, n)
            est.update_ground_contact(
                GroundContactMeasurement(r.ground_contact.time, r.ground_contact.on_ground, ground)
            )

    def step_fdm(self) -> None:
        """One 200 Hz step of the world and the sensors into the estimator."""
        was_on_ground = self.aircraft.model.on_ground
        readings = self.aircraft.step()
        truth = self.aircraft.truth()
        if truth.on_ground and not was_on_ground:
            self.touchdowns.append(truth)
        if readings is not None:  # always: the aircraft has the suite
            self._feed(readings)

    def tick(self, controller: Controller) -> EstimatedState:
        """One 50 Hz control tick: estimate -> controller -> YACS, then 4 FDM steps."""
        gust = self.gusts.step(self.dt)
        if self.gusts.sigma > 0.0:
            self.aircraft.model.set_wind(self.wind, gust)
        state = self.state()
        cmd = controller(state, self.now)
        self.aircraft.command(to_yacs(cmd))
        self.log.time.append(self.now)
        self.log.truth.append(self.truth())
        self.log.estimate.append(state)
        self.log.command.append(cmd)
        for _ in range(FDM_PER_TICK):
            self.step_fdm()
        return state

    def start_engine(self, spin_up: float = 12.0) -> None:
        """Engine on, autonomous mode, wait on the skids until the rotor is governed."""
        self.aircraft.rc.set_engine(True)
        self.aircraft.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
        self.aircraft.command(YacsCommand(vertical=-1.0))
        while not self.estimator.initialised or self.now < spin_up:
            self.step_fdm()

    def fly(
        self,
        controller: Controller,
        seconds: float,
        until: Callable[[], bool] | None = None,
    ) -> bool:
        """Tick ``controller`` for up to ``seconds``; True if ``until`` became true first."""
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.tick(controller)
            if until is not None and until():
                return True
        return until is None


# ---------------------------------------------------------------------- flight phases
@dataclass
class PhaseResult:
    """What a flight phase ended with (``outputs`` are the control function's per-tick outputs)."""

    ok: bool
    outputs: list[Any]
    integral: tuple[float, float]
    first_tick: int
    """Index of the phase's first row in ``SimFlight.log``."""


def takeoff(f: SimFlight, height: float = 10.0, timeout: float = 40.0) -> PhaseResult:
    """Take off from the skids to ``height`` (returns ok=False with the failure in outputs)."""
    fn = Takeoff(TakeoffConfig(height=height))
    i0 = len(f.log.time)
    outs: list[TakeoffOutput] = []
    if fn.start(f.state(), f.now) is not TakeoffStatus.CLIMBING:
        return PhaseResult(False, outs, (0.0, 0.0), i0)

    def ctl(s: EstimatedState, now: float) -> AttitudeCommand:
        outs.append(fn.update(s, now, f.dt))
        return outs[-1].command

    f.fly(ctl, timeout, until=lambda: outs[-1].status is not TakeoffStatus.CLIMBING)
    return PhaseResult(outs[-1].status is TakeoffStatus.DONE, outs, fn.loop.integral, i0)


def hover(
    f: SimFlight,
    setpoint: HoverSetpoint,
    seconds: float,
    integral: tuple[float, float] = (0.0, 0.0),
    until_stable: bool = False,
) -> PhaseResult:
    """Hover at ``setpoint`` for ``seconds`` (or until Hover-Stable-CO if ``until_stable``)."""
    fn = HoverController(setpoint, integral=integral)
    i0 = len(f.log.time)
    outs: list[HoverOutput] = []

    def ctl(s: EstimatedState, now: float) -> AttitudeCommand:
        outs.append(fn.update(s, f.dt))
        return outs[-1].command

    stable = (lambda: outs[-1].status is HoverStatus.STABLE) if until_stable else None
    f.fly(ctl, seconds, until=stable)
    return PhaseResult(outs[-1].status is HoverStatus.STABLE, outs, fn.loop.integral, i0)


@dataclass
class PathRun(PhaseResult):
    """A path execution: offers and Request-Segment events with their sim times."""

    sent: dict[int, float] = field(default_factory=dict)
    requests: list[tuple[float, int]] = field(default_factory=list)


def fly_path(
    f: SimFlight,
    segments: list[PathSegment],
    integral: tuple[float, float] = (0.0, 0.0),
    withhold_from: int | None = None,
    timeout: float = 150.0,
    stop_after: Callable[[PathOutput], bool] | None = None,
) -> PathRun:
    """Execute ``segments`` like the TST executor: send the next one on each Request-Segment.

    ``withhold_from``: index of the first segment that is never sent (safety braking scenario).
    ``stop_after``: end the phase early when it returns True for an output.
    """
    fn = PathFollower()
    i0 = len(f.log.time)
    run = PathRun(False, [], integral, i0)
    queue = list(segments[1:]) if withhold_from is None else list(segments[1:withhold_from])
    fn.start(f.state(), segments[0], integral)
    run.sent[segments[0].segment_id] = f.now

    def ctl(s: EstimatedState, now: float) -> AttitudeCommand:
        out = fn.update(s, now)
        run.outputs.append(out)
        if PathEvent.REQUEST_SEGMENT in out.events:
            run.requests.append((now, out.segment_id))
            if queue:
                seg = queue.pop(0)
                run.sent[seg.segment_id] = now
                fn.offer(seg)
        return out.command

    done = (PathStatus.ARRIVED, PathStatus.STOPPED, PathStatus.NAVIGATION_LOST)

    def finished() -> bool:
        last = run.outputs[-1]
        return last.status in done or (stop_after is not None and stop_after(last))

    f.fly(ctl, timeout, until=finished)
    run.ok = run.outputs[-1].status is PathStatus.ARRIVED
    run.integral = fn.loop.integral
    return run


def brake(f: SimFlight, integral: tuple[float, float], timeout: float = 30.0) -> PhaseResult:
    """Emergency brake from the current state until stopped."""
    fn = EmergencyBrake()
    fn.start(f.state(), integral)
    i0 = len(f.log.time)
    outs: list[BrakeOutput] = []

    def ctl(s: EstimatedState, now: float) -> AttitudeCommand:
        outs.append(fn.update(s, now))
        return outs[-1].command

    f.fly(ctl, timeout, until=lambda: outs[-1].status is not BrakeStatus.BRAKING)
    ok = outs[-1].status is BrakeStatus.STOPPED
    return PhaseResult(ok, outs, fn.follower.loop.integral, i0)


def land(
    f: SimFlight,
    target: LandingTarget,
    integral: tuple[float, float] = (0.0, 0.0),
    timeout: float = 90.0,
) -> PhaseResult:
    """Land on ``target``; on LANDED the engine is shut down as the function requests."""
    fn = Landing()
    fn.start(f.state(), target, integral)
    i0 = len(f.log.time)
    outs: list[LandingOutput] = []

    def ctl(s: EstimatedState, now: float) -> AttitudeCommand:
        outs.append(fn.update(s, now, f.dt))
        return outs[-1].command

    f.fly(ctl, timeout, until=lambda: outs[-1].phase is LandingPhase.LANDED)
    if outs[-1].engine_shutdown:
        f.aircraft.rc.set_engine(False)
    return PhaseResult(outs[-1].phase is LandingPhase.LANDED, outs, fn.loop.integral, i0)


def touchdown_velocity(f: SimFlight, first_tick: int) -> tuple[float, float]:
    """True (vertical, horizontal) speed at the first skid contact after log row ``first_tick``."""
    start = f.log.time[first_tick]
    for truth in f.touchdowns:
        if truth.time >= start:
            ve, vn, vu = truth.velocity_enu
            return abs(vu), math.hypot(ve, vn)
    return math.nan, math.nan


def figure7_path(start: tuple[float, float, float]) -> list[PathSegment]:
    """The three-segment path of chapter Figure 7: AB 8 m/s, BC 3 m/s, CD 8 m/s (A = start)."""
    z = start[2]
    b, c, d = (40.0, -60.0, z), (70.0, -30.0, z), (20.0, 60.0, z)
    return [
        PathSegment(start, b, (1.0, 0.0, 0.0), (1.0, 0.0, 0.0), 8.0, 3.0, 0),
        PathSegment(b, c, (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 3.0, 3.0, 1),
        PathSegment(c, d, (0.0, 1.0, 0.0), (-1.0, -1.0, 0.0), 8.0, 0.0, 2),
    ]


FIGURE7_START = InitialPlacement(east=-100.0, north=-60.0, heading=math.pi / 2)
"""Where the aircraft starts on the skids for the Figure 7 path (point A below)."""
