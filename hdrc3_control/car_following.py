"""Reactive car following (chapter §6.1, §6.2.2 ``fcl_track``, Figure 12's *Track* automaton).

The colour tracker (``ppcl_ip_color_tracker``, §6.2.3) locates the car on the ground in every
colour image it tracks it in: a *fix*, noisy by a few metres (the aircraft's own navigation
error stretched along the camera ray) and stamped with the image's sim time, 0.1-0.2 s before
the control tick that reads it. Two parts turn the fixes into the outer loop's reference:

:class:`TargetEstimator` - a constant-velocity Kalman filter per horizontal axis (state: position
and velocity; white-acceleration process noise ``process_noise``; fix noise ``fix_sigma``). Both
axes share one covariance, since they have the same model and noise. A fix whose innovation lies
beyond ``gate`` standard deviations is an outlier and is dropped; ``max_gated`` outliers in a row
mean the filter lost the car (a new seed, a wrong region) and it restarts at the next fix. The
estimated speed is bounded by ``max_target_speed``; :meth:`TargetEstimator.predict` extrapolates
to the tick's time, at most ``max_extrapolation`` s past the last fix (then the car is taken to
stand there).

:class:`CarFollower` - the control law. With the car at ``c`` (velocity ``v_c``) and the
*look direction* ``chi`` (rad clockwise from north, from the aircraft's standoff point to the
car)::

    p_ref   = c - D (sin chi, cos chi),      up = the altitude the mode was engaged at
    v_ref   = v_c after a first-order lag (velocity_tau), |a_ref| <= max_accel, |v_ref| <= v_max
    a_ref   = d/dt of v_ref
    psi_ref = bearing from the aircraft to the car (the nose towards it; the PTU points finely)

``chi`` follows the car's direction of travel while it drives (speed above ``moving_speed``),
or, while it stands (below ``stop_speed``; hysteresis between the two), the bearing the aircraft
sees it on now, so a stopped car is held at distance ``D`` on the current bearing. ``chi`` is
low-passed (``direction_tau``) and its rate bounded (``max_swing_rate``), so at a corner the
standoff point swings round the car smoothly instead of jumping behind it (at most
``D * max_swing_rate`` of extra speed, left to the position loop: the look direction's rate is
too noisy at the low speeds of a corner to feed forward). Slow swings keep the distance best:
through a 90 degree corner the aircraft first flies beside the car at distance ``D``, then drifts
behind it. The car's speed is fed forward through a short lag, so a new estimate (5 fixes a
second) does not kick the attitude.

Hand-written because it is small and specific: a 2-state Kalman filter with a gate and bounds is
a few lines (filterpy and friends add a dependency and numpy overhead for 2x2 matrices at 50 Hz),
and no control library offers a "standoff behind a moving ground target" guidance law on top of
this project's outer loop (``outer_loop.py``).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import EstimatedState, Vec3, wrap_pi
from hdrc3_control.outer_loop import OuterLoopGains, Reference

Vec2 = tuple[float, float]


@dataclass(frozen=True, slots=True)
class CarFollowingConfig:
    """Parameters of the target estimate and the following law (``fcl_track``)."""

    distance: float = 20.0
    """Horizontal standoff distance to the car, m."""
    max_speed: float = 15.0
    """Limit of the reference velocity, m/s (the RMAX's envelope, ``ProfileLimits.max_speed``)."""
    max_accel: float = 3.0
    """Limit of the reference acceleration, m/s^2."""
    velocity_tau: float = 0.4
    """Time constant of the reference velocity's lag behind the standoff point's velocity, s."""
    direction_tau: float = 3.0
    """Time constant of the look direction's low-pass, s."""
    max_swing_rate: float = math.radians(10.0)
    """Fastest turn of the look direction (the standoff point round the car), rad/s."""
    moving_speed: float = 2.0
    """Above this the car drives: follow it from behind, m/s."""
    stop_speed: float = 1.0
    """Below this the car stands: keep the current bearing, m/s."""
    fix_sigma: float = 3.0
    """1-sigma error of a ground fix per horizontal axis, m."""
    process_noise: float = 3.0
    """White-acceleration spectral density of the car, m^2/s^3."""
    initial_speed_sigma: float = 8.0
    """1-sigma of the car's velocity before the second fix, m/s."""
    gate: float = 4.0
    """A fix further than this many standard deviations from the prediction is an outlier."""
    max_gated: int = 5
    """Outliers in a row after which the estimate restarts at the next fix."""
    max_target_speed: float = 25.0
    """Bound on the estimated car speed, m/s."""
    max_extrapolation: float = 1.0
    """Prediction beyond the last fix at most this long, s."""
    fix_recent: float = 2.0
    """Engaging needs a fix at most this old, s (an image reaches the PFC as a fix 0.1-0.2 s
    after it was taken, more than a second on a loaded machine)."""
    init_window: float = 3.0
    """Fixes at most this old when the mode engages start the estimate, s."""
    lost_timeout: float = 3.0
    """No accepted fix for this long: the target is lost and the command fails, s."""
    max_range: float = 200.0
    """Engaging refuses a car further than this from the aircraft, m."""
    gains: OuterLoopGains = field(default_factory=OuterLoopGains)

    def __post_init__(self) -> None:
        """Reject non-finite, non-positive or inconsistent values (ConfigError)."""
        positive = {
            "distance": self.distance,
            "max_speed": self.max_speed,
            "max_accel": self.max_accel,
            "velocity_tau": self.velocity_tau,
            "direction_tau": self.direction_tau,
            "max_swing_rate": self.max_swing_rate,
            "moving_speed": self.moving_speed,
            "stop_speed": self.stop_speed,
            "fix_sigma": self.fix_sigma,
            "process_noise": self.process_noise,
            "initial_speed_sigma": self.initial_speed_sigma,
            "gate": self.gate,
            "max_target_speed": self.max_target_speed,
            "max_extrapolation": self.max_extrapolation,
            "fix_recent": self.fix_recent,
            "init_window": self.init_window,
            "lost_timeout": self.lost_timeout,
            "max_range": self.max_range,
        }
        bad = [k for k, v in positive.items() if not (math.isfinite(v) and v > 0.0)]
        if bad:
            raise ConfigError(f"car following: {', '.join(bad)} must be finite and > 0")
        if self.stop_speed >= self.moving_speed:
            raise ConfigError(
                f"car following: stop_speed {self.stop_speed} must be below "
                f"moving_speed {self.moving_speed}"
            )
        if self.max_gated < 1:
            raise ConfigError(f"car following: max_gated must be >= 1, got {self.max_gated}")
        if self.distance >= self.max_range:
            raise ConfigError("car following: distance must be below max_range")


@dataclass(frozen=True, slots=True)
class TargetFix:
    """One ground fix of the tracked car (colour tracker, world ENU)."""

    time: float
    """Sim time of the image, s."""
    position: Vec3
    """m, ENU."""


class FixVerdict(enum.Enum):
    """What :meth:`TargetEstimator.update` did with a fix."""

    STARTED = "started"
    """The first fix (after a reset): the estimate starts here."""
    ACCEPTED = "accepted"
    GATED = "gated"
    """An outlier: too far from the prediction, dropped."""
    RESTARTED = "restarted"
    """After ``max_gated`` outliers in a row: the estimate started over at this fix."""
    STALE = "stale"
    """Older than the estimate: dropped."""
    INVALID = "invalid"
    """Not finite: dropped."""


@dataclass(frozen=True, slots=True)
class TargetEstimate:
    """The car at one instant."""

    time: float
    position: Vec3
    """m, ENU (up: low-passed fix heights)."""
    velocity: Vec2
    """m/s, east and north."""
    sigma: float
    """Horizontal position 1-sigma per axis, m."""
    age: float
    """Seconds since the last accepted fix."""

    @property
    def speed(self) -> float:
        """Horizontal speed, m/s."""
        return math.hypot(*self.velocity)


class TargetEstimator:
    """Constant-velocity Kalman filter over the ground fixes (module docstring)."""

    def __init__(self, config: CarFollowingConfig | None = None) -> None:
        """An empty estimate; the first fix starts it."""
        self.config = config or CarFollowingConfig()
        self.reset()

    def reset(self) -> None:
        """Forget the car."""
        self.started = False
        self.time = -math.inf
        """Time of the last accepted fix, s (-inf: none)."""
        self.position: Vec2 = (0.0, 0.0)
        self.velocity: Vec2 = (0.0, 0.0)
        self.up = 0.0
        self.p00 = self.p01 = self.p11 = 0.0
        self.gated = 0
        """Outliers in a row."""
        self.counts: dict[FixVerdict, int] = dict.fromkeys(FixVerdict, 0)

    def _start(self, fix: TargetFix) -> None:
        c = self.config
        self.started, self.time = True, fix.time
        self.position, self.velocity, self.up = fix.position[:2], (0.0, 0.0), fix.position[2]
        self.p00, self.p01, self.p11 = c.fix_sigma**2, 0.0, c.initial_speed_sigma**2
        self.gated = 0

    def _propagate(self, dt: float) -> tuple[Vec2, float, float, float]:
        """Position and covariance ``dt`` s after the last fix."""
        q = self.config.process_noise
        (e, n), (ve, vn) = self.position, self.velocity
        p00 = self.p00 + 2.0 * dt * self.p01 + dt * dt * self.p11 + q * dt**3 / 3.0
        p01 = self.p01 + dt * self.p11 + q * dt * dt / 2.0
        p11 = self.p11 + q * dt
        return (e + ve * dt, n + vn * dt), p00, p01, p11

    def update(self, fix: TargetFix) -> FixVerdict:
        """Take one fix (in time order); returns what became of it."""
        verdict = self._update(fix)
        self.counts[verdict] += 1
        return verdict

    def _update(self, fix: TargetFix) -> FixVerdict:
        c = self.config
        if not all(math.isfinite(v) for v in (fix.time, *fix.position)):
            return FixVerdict.INVALID
        if not self.started:
            self._start(fix)
            return FixVerdict.STARTED
        dt = fix.time - self.time
        if dt < 0.0:
            return FixVerdict.STALE
        (pe, pn), p00, p01, p11 = self._propagate(dt)
        s = p00 + c.fix_sigma**2
        ye, yn = fix.position[0] - pe, fix.position[1] - pn
        if (ye * ye + yn * yn) / s > c.gate**2:
            self.gated += 1
            if self.gated > c.max_gated:
                self._start(fix)
                return FixVerdict.RESTARTED
            return FixVerdict.GATED
        k0, k1 = p00 / s, p01 / s
        ve, vn = self.velocity[0] + k1 * ye, self.velocity[1] + k1 * yn
        speed = math.hypot(ve, vn)
        if speed > c.max_target_speed:
            ve, vn = ve * c.max_target_speed / speed, vn * c.max_target_speed / speed
        self.position, self.velocity = (pe + k0 * ye, pn + k0 * yn), (ve, vn)
        self.p00, self.p01, self.p11 = (1.0 - k0) * p00, (1.0 - k0) * p01, p11 - k1 * p01
        # bounded covariance: never more uncertain than a fresh start
        self.p00 = min(self.p00, c.fix_sigma**2)
        self.p11 = min(self.p11, c.initial_speed_sigma**2)
        self.up += 0.2 * (fix.position[2] - self.up)
        self.time, self.gated = fix.time, 0
        return FixVerdict.ACCEPTED

    def predict(self, t: float) -> TargetEstimate | None:
        """The car at time ``t`` (None before the first fix)."""
        if not self.started:
            return None
        age = max(0.0, t - self.time)
        horizon = min(age, self.config.max_extrapolation)
        (e, n), p00, _, _ = self._propagate(horizon)
        velocity = self.velocity if age <= self.config.max_extrapolation else (0.0, 0.0)
        return TargetEstimate(t, (e, n, self.up), velocity, math.sqrt(p00), age)


class FollowMode(enum.Enum):
    """Which direction the standoff point is taken along."""

    BEHIND = "behind"
    """The car drives: behind it along its smoothed direction of travel."""
    BEARING = "bearing"
    """The car stands: on the bearing the aircraft sees it on."""


@dataclass(frozen=True, slots=True)
class FollowOutput:
    """The reference of one tick and what it was made of."""

    reference: Reference
    mode: FollowMode
    look: float
    """Look direction chi, rad clockwise from north (standoff point -> car)."""
    distance: float
    """Horizontal distance aircraft - car (estimate), m."""


def _bearing(frm: Vec2, to: Vec2) -> float | None:
    """Bearing from ``frm`` to ``to``, rad clockwise from north (None when they coincide)."""
    de, dn = to[0] - frm[0], to[1] - frm[1]
    if math.hypot(de, dn) < 1.0:
        return None
    return math.atan2(de, dn) % math.tau


class CarFollower:
    """The following law (module docstring): target estimate + aircraft state -> Reference."""

    def __init__(self, config: CarFollowingConfig | None = None) -> None:
        """An idle follower; :meth:`start` engages it."""
        self.config = config or CarFollowingConfig()
        self.altitude = 0.0
        self.look = 0.0
        self.mode = FollowMode.BEARING
        self.velocity: Vec2 = (0.0, 0.0)

    def start(self, state: EstimatedState, target: TargetEstimate) -> None:
        """Engage at the aircraft's altitude, looking at the car from where the aircraft is."""
        c = self.config
        self.altitude = state.position[2]
        here = state.position[:2]
        seen = _bearing(here, target.position[:2])
        self.mode = FollowMode.BEHIND if target.speed > c.moving_speed else FollowMode.BEARING
        self.look = state.heading if seen is None else seen
        self.velocity = (state.velocity[0], state.velocity[1])

    def update(self, state: EstimatedState, target: TargetEstimate, dt: float) -> FollowOutput:
        """One tick of ``dt`` s: the reference that keeps the standoff."""
        c = self.config
        here, car = state.position[:2], target.position[:2]
        speed = target.speed
        if self.mode is FollowMode.BEARING and speed > c.moving_speed:
            self.mode = FollowMode.BEHIND
        elif self.mode is FollowMode.BEHIND and speed < c.stop_speed:
            self.mode = FollowMode.BEARING
        if self.mode is FollowMode.BEHIND:
            wanted: float | None = math.atan2(target.velocity[0], target.velocity[1])
        else:
            wanted = _bearing(here, car)
        if wanted is not None and dt > 0.0:
            step = wrap_pi(wanted - self.look) * min(1.0, dt / c.direction_tau)
            limit = c.max_swing_rate * dt
            self.look = (self.look + max(-limit, min(limit, step))) % math.tau
        d = c.distance
        standoff = (car[0] - d * math.sin(self.look), car[1] - d * math.cos(self.look))
        goal = _limit(target.velocity, c.max_speed)
        accel = (0.0, 0.0)
        if dt > 0.0:
            wanted_accel = (
                (goal[0] - self.velocity[0]) / max(c.velocity_tau, dt),
                (goal[1] - self.velocity[1]) / max(c.velocity_tau, dt),
            )
            accel = _limit(wanted_accel, c.max_accel)
            self.velocity = _limit(
                (self.velocity[0] + accel[0] * dt, self.velocity[1] + accel[1] * dt), c.max_speed
            )
        heading = _bearing(here, car)
        reference = Reference(
            position=(standoff[0], standoff[1], self.altitude),
            heading=state.heading if heading is None else heading,
            velocity=(self.velocity[0], self.velocity[1], 0.0),
            acceleration=accel,
        )
        distance = math.hypot(car[0] - here[0], car[1] - here[1])
        return FollowOutput(reference, self.mode, self.look, distance)


def _limit(v: Vec2, limit: float) -> Vec2:
    """``v`` scaled down to at most ``limit`` in magnitude."""
    norm = math.hypot(*v)
    if norm <= limit:
        return v
    return (v[0] * limit / norm, v[1] * limit / norm)
