"""Navigation Kalman filter: IMU-driven position/velocity, aided by GPS, barometer and vision.

State ``x = [p_enu(3), v_enu(3), b_acc_enu(3), b_baro]``. The IMU's specific force, rotated to ENU
with the attitude sensor's angles, drives the prediction at the IMU rate (200 Hz); GPS position and
velocity (10 Hz), barometric height (25 Hz), vision position (landing) and, on the skids, a
zero-velocity and ground-height reference correct it. Between GPS fixes and during GPS dropouts
the filter dead-reckons on the IMU; :meth:`StateEstimator.health` reports how trustworthy it is.

Vision (chapter §5.4 "Sensor Fusion"): a fix of the landing pad camera is stamped with its
image's time and arrives late; the filter moves it to its own time by its own motion since
(:class:`~hdrc3_control.aiding.PositionHistory`) and gates it like every other measurement, so
outliers are rejected and occlusions are dead-reckoned through on the IMU. While vision fixes
are accepted, GPS gives only its velocity (its position is metres off and correlated: it would
pull the centimetre solution). A run of rejected fixes that agree with each other means the
filter is off (e.g. it was on a biased GPS when the pad came into view): then they are taken.
:meth:`StateEstimator.used` says which sources corrected the solution lately.

The two linear Kalman steps are written out (:class:`LinearKalman`, with the Joseph-form
covariance update filterpy's ``KalmanFilter`` uses) instead of importing filterpy: its package
imports ``scipy.stats``, which took 2-3 s of the 5 s a ``control_kernel`` needed to come back
after a ``kill -9`` on the loaded machine (issue 21: the terminal event of the lost command waits
for the restarted node).

Barometer monitor: the filter's bias state follows slow weather drift, so a barometer that drifts
fast (a blocked static port, a heating sensor) would carry the height away unnoticed (GPS height
is too poor, 3 m correlated, to veto it). GPS Doppler velocity is not: integrated, its vertical
component gives the climb to 0.2 m over half a minute. The monitor compares the barometer's height
change with that integral over the last ``baro_window``, their difference low-passed (1 s; the
barometer alone low-passed would lag a 3 m/s climb by 3 m); a difference above
``baro_drift_limit`` excludes the barometer for the rest of the filter's life. The height then
goes back to the filter's height at the start of the window plus the GPS climb since, and GPS
velocity (with the GPS height, weakly) carries it on. :attr:`StateEstimator.baro_fault` says why.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import ConfigError
from hdrc3_control.aiding import (
    AidingLog,
    AidingSource,
    PositionHistory,
    Verdict,
    consistent,
)
from hdrc3_control.commands import EstimatedState, EstimatorHealth, G, Vec3, wrap_2pi
from hdrc3_control.measurements import (
    AttitudeMeasurement,
    BaroMeasurement,
    GpsMeasurement,
    GroundContactMeasurement,
    ImuMeasurement,
    VisionPoseMeasurement,
)

_N = 10
_P, _V, _BA, _BB = slice(0, 3), slice(3, 6), slice(6, 9), 9


@dataclass(frozen=True, slots=True)
class EstimatorConfig:
    """Noise model and health thresholds."""

    accel_sigma: float = 0.4
    """Process noise on acceleration (IMU noise, attitude error, vibration), m/s^2."""
    accel_bias_walk: float = 0.01
    """Accelerometer bias random walk, m/s^2/sqrt(s)."""
    baro_bias_walk: float = 0.03
    """Barometer drift random walk, m/sqrt(s)."""
    gps_horizontal_sigma: float = 0.6
    gps_vertical_sigma: float = 30.0
    """GPS height error is large and correlated over minutes (white-noise equivalent is huge):
    the barometer, referenced on the ground before take-off, carries the vertical."""
    gps_velocity_sigma: float = 0.15
    baro_sigma: float = 0.3
    ground_sigma: float = 0.05
    """Height reference and zero velocity while on the skids, m and m/s."""
    cg_above_skids: float = 0.45
    """Height of the CG above the skid bottoms, m (what the ground reference adds)."""
    gate_sigma: float = 5.0
    """Innovations beyond this many sigma are rejected as outliers."""
    gate_reset_count: int = 10
    """After this many consecutive GPS rejections the filter trusts GPS again (re-acquisition)."""
    aiding_timeout: float = 0.5
    """Without GPS/vision for longer than this the filter is dead-reckoning (DEGRADED), s."""
    max_dead_reckoning: float = 10.0
    """Dead reckoning longer than this is LOST, s."""
    imu_timeout: float = 0.1
    attitude_timeout: float = 0.5
    frozen_count: int = 20
    """This many identical consecutive IMU samples mean a frozen IMU."""
    baro_window: float = 30.0
    """Barometer monitor: how far back the barometer's height change is compared, s."""
    baro_drift_limit: float = 3.0
    """Barometer monitor: height change against the GPS climb that excludes the barometer, m
    (its natural spread over the window: about 0.5 m, the barometer's own slow drift)."""
    coast_accel_sigma: float = 3.0
    """Acceleration uncertainty while IMU samples repeat (a stuck IMU), m/s^2: the filter
    coasts on a constant-velocity model and GPS and barometer carry the solution."""
    vision_priority: float = 3.0
    """GPS gives only its velocity while a vision fix was accepted within this, s: through a
    short gap in the fixes (a frame dropped by a loaded image pipeline, an occlusion) the filter
    dead-reckons on GPS velocity (centimetres in 3 s) instead of jumping to the GPS position,
    metres off, that the next fixes would then be gated against."""
    vision_max_delay: float = 1.0
    """Vision fixes older than this (image time behind the filter's time) are stale, s."""
    vision_reset_spread: float = 0.3
    """``gate_reset_count`` rejected fixes whose innovations agree to this (RMS, m) are taken."""

    def __post_init__(self) -> None:
        """Reject non-positive noise figures and timeouts."""
        values = (
            self.accel_sigma,
            self.gps_horizontal_sigma,
            self.gps_vertical_sigma,
            self.gps_velocity_sigma,
            self.baro_sigma,
            self.ground_sigma,
            self.aiding_timeout,
            self.max_dead_reckoning,
            self.imu_timeout,
            self.attitude_timeout,
        )
        if not all(math.isfinite(v) and v > 0.0 for v in values):
            raise ConfigError(f"estimator noise figures and timeouts must be > 0, got {values}")


class LinearKalman:
    """State ``x`` and covariance ``P`` of a linear Kalman filter; predict and update."""

    def __init__(self, dim: int) -> None:
        """Zero state, identity covariance."""
        self.x: NDArray[np.float64] = np.zeros(dim)
        self.P: NDArray[np.float64] = np.eye(dim)

    def predict(
        self,
        f: NDArray[np.float64],
        q: NDArray[np.float64],
        b: NDArray[np.float64],
        u: NDArray[np.float64],
    ) -> None:
        """``x = F x + B u``, ``P = F P F' + Q``."""
        self.x = f @ self.x + b @ u
        self.P = f @ self.P @ f.T + q

    def update(
        self, z: NDArray[np.float64], h: NDArray[np.float64], r: NDArray[np.float64]
    ) -> None:
        """Correct with measurement ``z = H x + v``, ``v ~ N(0, R)`` (Joseph form for ``P``)."""
        p = self.P
        s = h @ p @ h.T + r
        k = np.linalg.solve(s.T, (p @ h.T).T).T  # P H' S^-1 (S symmetric)
        self.x = self.x + k @ (z - h @ self.x)
        i_kh = np.eye(len(self.x)) - k @ h
        self.P = i_kh @ p @ i_kh.T + k @ r @ k.T


def body_to_enu(roll: float, pitch: float, heading: float, vec: Vec3) -> NDArray[np.float64]:
    """Rotate a body-FRD vector into ENU (Euler 3-2-1 angles, heading clockwise from north)."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    ch, sh = math.cos(heading), math.sin(heading)
    x, y, z = vec
    north = cp * ch * x + (sr * sp * ch - cr * sh) * y + (cr * sp * ch + sr * sh) * z
    east = cp * sh * x + (sr * sp * sh + cr * ch) * y + (cr * sp * sh - sr * ch) * z
    down = -sp * x + sr * cp * y + cr * cp * z
    return np.array([east, north, -down])


class StateEstimator:
    """The navigation filter; feed measurements in time order, read :meth:`estimate`."""

    def __init__(self, config: EstimatorConfig | None = None) -> None:
        """Create an uninitialised filter (it initialises on the first GPS or vision fix)."""
        self.config = config or EstimatorConfig()
        self._warm: tuple[float, float] | None = None
        """Barometer bias seed for the next initialisation (kept by :meth:`reset`)."""
        self.reset()

    def reset(self) -> None:
        """Forget everything; the next position fix initialises the filter again."""
        self._kf = LinearKalman(_N)
        self._initialised = False
        self._time: float | None = None
        self._attitude: AttitudeMeasurement | None = None
        self._rates: Vec3 = (0.0, 0.0, 0.0)
        self._last_imu: ImuMeasurement | None = None
        self._same_imu = 0
        self._imu_time = -math.inf
        self._aiding_time = -math.inf
        self._on_ground = False
        self._ground_height = 0.0
        self._baro: BaroMeasurement | None = None
        self._rejected = 0
        self._rpm = 0.0
        self.aiding = AidingLog()
        """Verdicts per aiding source (:meth:`used`)."""
        self._history = PositionHistory(self.config.vision_max_delay + 0.1)
        self._vision_rejects: list[NDArray[np.float64]] = []
        self._travel = np.zeros(3)
        self._fq_cache: tuple[float, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]
        self._fq_cache = (-1.0, np.eye(_N), np.zeros((_N, _N)), np.zeros((_N, 3)))
        self.rejections = 0
        """Measurements rejected by the innovation gate since the last reset."""
        self.baro_fault: str | None = None
        """Why the barometer is excluded (the monitor found it drifting), or None."""
        self._gps_climb = 0.0
        self._gps_velocity: tuple[float, float] | None = None
        self._offset_low: float | None = None
        """Barometer height minus GPS climb, low-passed (1 s)."""
        self._baro_history: deque[tuple[float, float, float, float | None]] = deque()
        """(time, barometer height minus GPS climb, GPS climb, filter height) once a second."""

    @property
    def initialised(self) -> bool:
        """True once a position fix has initialised the filter."""
        return self._initialised

    def seed_baro_bias(self, bias: float, sigma: float) -> None:
        """Initialise with this barometer bias (a warm start: ``hdrc3_control.warm_start``).

        The next initialisation (after any :meth:`reset`) takes its height from the barometer
        minus ``bias`` instead of from the GPS fix, whose vertical error is metres.
        """
        if not (math.isfinite(bias) and math.isfinite(sigma) and sigma > 0.0):
            raise ConfigError(f"barometer bias seed must be finite, got {bias} +- {sigma}")
        self._warm = (bias, sigma)

    def baro_reference(self) -> tuple[float, float]:
        """The barometer bias estimate and its standard deviation, m."""
        if not self._initialised:
            raise ConfigError("state estimator not initialised")
        return float(self._kf.x[_BB]), math.sqrt(max(0.0, float(self._kf.P[_BB, _BB])))

    # ------------------------------------------------------------------ inputs
    def update_attitude(self, meas: AttitudeMeasurement) -> None:
        """Take the attitude sensor's angles (used to rotate the IMU's specific force)."""
        self._attitude = meas

    def update_rpm(self, rpm: float) -> None:
        """Remember the last rotor rpm reading (passed through to the estimate)."""
        self._rpm = rpm

    def update_imu(self, meas: ImuMeasurement) -> None:
        """Predict to the IMU sample's time with its specific force (the filter's clock)."""
        frozen = self._last_imu is not None and (
            meas.specific_force == self._last_imu.specific_force
            and meas.angular_rate == self._last_imu.angular_rate
        )
        self._same_imu = self._same_imu + 1 if frozen else 0
        self._last_imu = meas
        self._imu_time = meas.time
        self._rates = meas.angular_rate
        if not self._initialised or self._attitude is None:
            self._time = meas.time
            return
        dt = meas.time - (self._time if self._time is not None else meas.time)
        self._time = meas.time
        if dt <= 0.0 or dt > 0.5:
            return
        acc = body_to_enu(
            self._attitude.roll, self._attitude.pitch, self._attitude.heading, meas.specific_force
        )
        acc[2] -= G
        f, q, b = self._transition(dt)
        if frozen:
            # a repeated sample is no measurement (real IMU noise never repeats): integrating a
            # stuck specific force diverges within seconds (an emergency landing on it hit the
            # ground at 5 m/s); coast instead, with the uncertainty of a manoeuvring helicopter
            acc = np.zeros(3)
            q = q.copy()
            q[0:6, 0:6] *= (self.config.coast_accel_sigma / self.config.accel_sigma) ** 2
        before = self._kf.x[_P].copy()
        self._kf.predict(f, q, b, acc)
        # the motion of the predictions alone: corrections in between do not move a late fix
        self._travel = self._travel + (self._kf.x[_P] - before)
        self._history.add(meas.time, self._travel)

    def update_gps(self, meas: GpsMeasurement) -> bool:
        """Correct with a GPS fix; returns False if the gate rejected it."""
        c = self.config
        self._integrate_climb(meas)
        z = np.array([*meas.position, *meas.velocity])
        if not self._initialised:
            self._initialise(np.array(meas.position), np.array(meas.velocity))
            self._aiding_time = meas.time
            return True
        h = np.zeros((6, _N))
        h[0:3, _P] = np.eye(3)
        h[3:6, _V] = np.eye(3)
        gh, gv, vs = c.gps_horizontal_sigma, c.gps_vertical_sigma, c.gps_velocity_sigma
        r = np.diag([gh**2, gh**2, gv**2, vs**2, vs**2, vs**2])
        source = AidingSource.GPS
        if self.aiding.age(AidingSource.VISION, meas.time) <= c.vision_priority:
            z, h, r, source = z[3:], h[3:], r[3:, 3:], AidingSource.GPS_VELOCITY
        force = self._rejected >= c.gate_reset_count
        if not self._correct(z, h, r, force=force):
            self._rejected += 1
            self.aiding.note(source, Verdict.REJECTED, meas.time)
            return False
        self._rejected = 0
        self._aiding_time = meas.time
        self.aiding.note(source, Verdict.ACCEPTED, meas.time)
        return True

    def update_baro(self, meas: BaroMeasurement) -> bool:
        """Correct the height with a barometric reading (height + baro bias)."""
        self._baro = meas
        self._monitor_baro(meas)
        if not self._initialised or self.baro_fault is not None:
            return False
        h = np.zeros((1, _N))
        h[0, 2] = 1.0
        h[0, _BB] = 1.0
        ok = self._correct(np.array([meas.height]), h, np.array([[self.config.baro_sigma**2]]))
        self.aiding.note(AidingSource.BARO, Verdict.ACCEPTED if ok else Verdict.REJECTED, meas.time)
        return ok

    def update_ground_contact(self, meas: GroundContactMeasurement) -> None:
        """On the skids: zero velocity and the CG at a known height above the terrain."""
        self._on_ground = meas.on_ground
        self._ground_height = meas.ground_height
        if not (meas.on_ground and self._initialised):
            return
        c = self.config
        h = np.zeros((4, _N))
        h[0, 2] = 1.0
        h[1:4, _V] = np.eye(3)
        z = np.array([meas.ground_height + c.cg_above_skids, 0.0, 0.0, 0.0])
        self._correct(z, h, np.eye(4) * c.ground_sigma**2, force=True)
        self.aiding.note(AidingSource.GROUND, Verdict.ACCEPTED, meas.time)

    def update_vision(self, meas: VisionPoseMeasurement) -> Verdict:
        """Correct with a vision fix of the image's time; counts as aiding like GPS."""
        c, log, vision = self.config, self.aiding, AidingSource.VISION
        z = np.array(meas.position, dtype=np.float64)
        if not (np.all(np.isfinite(z)) and math.isfinite(meas.sigma) and meas.sigma > 0.0):
            log.note(vision, Verdict.INVALID, meas.time)
            return Verdict.INVALID
        if not self._initialised:
            self._initialise(z, np.zeros(3))
            self._aiding_time = meas.time
            log.note(vision, Verdict.ACCEPTED, meas.time)
            return Verdict.ACCEPTED
        now = self._time if self._time is not None else meas.time
        if now - meas.time > c.vision_max_delay:
            log.note(vision, Verdict.STALE, meas.time)
            return Verdict.STALE
        if meas.time < now:
            then = self._history.at(meas.time)
            if then is None:
                log.note(vision, Verdict.STALE, meas.time)
                return Verdict.STALE
            z = z + (self._travel - then)  # the filter's own motion since the image
        h = np.zeros((3, _N))
        h[:, _P] = np.eye(3)
        innovation = z - self._kf.x[_P]
        rejects = self._vision_rejects
        force = len(rejects) >= c.gate_reset_count and consistent(
            rejects[-c.gate_reset_count :], c.vision_reset_spread
        )
        norm = float(np.linalg.norm(innovation))
        if force:  # the filter was off by the innovation: say so, so that the fix pulls it over
            self._kf.P[_P, _P] += np.diag(innovation**2)
        if not self._correct(z, h, np.eye(3) * meas.sigma**2, force=force):
            rejects.append(innovation)
            del rejects[: -c.gate_reset_count]
            log.note(vision, Verdict.REJECTED, meas.time, norm)
            return Verdict.REJECTED
        rejects.clear()
        self._aiding_time = max(self._aiding_time, meas.time)
        log.note(vision, Verdict.ACCEPTED, meas.time, norm)
        return Verdict.ACCEPTED

    def used(self, now: float) -> tuple[AidingSource, ...]:
        """The sources that corrected the solution within ``aiding_timeout`` before ``now``."""
        return self.aiding.used(now, self.config.aiding_timeout)

    # ------------------------------------------------------------------ barometer monitor
    def _integrate_climb(self, meas: GpsMeasurement) -> None:
        """Integrate the GPS vertical velocity; a gap (> 0.5 s) restarts the comparison."""
        vz = meas.velocity[2]
        last = self._gps_velocity
        self._gps_velocity = (meas.time, vz)
        if last is None or not 0.0 < meas.time - last[0] <= 0.5:
            self._baro_history.clear()
            self._gps_climb = 0.0
            return
        self._gps_climb += 0.5 * (vz + last[1]) * (meas.time - last[0])

    def _monitor_baro(self, meas: BaroMeasurement) -> None:
        """Compare the barometer's height change with the GPS climb (one entry per second)."""
        c = self.config
        gps = self._gps_velocity
        if self.baro_fault is not None or gps is None or meas.time - gps[0] > 0.5:
            return
        offset = meas.height - self._gps_climb
        low = self._offset_low
        if low is None or not self._baro_history:
            low = offset
        # the difference is low-passed (1 s at 25 Hz), not the barometer alone: a low-pass lags
        # a climb by the climb rate times 1 s, which must not count as drift
        self._offset_low = offset = low + 0.04 * (offset - low)
        history = self._baro_history
        while history and meas.time - history[0][0] > c.baro_window:
            history.popleft()
        if not history or meas.time - history[-1][0] >= 1.0:
            height = float(self._kf.x[2]) if self._initialised else None
            history.append((meas.time, offset, self._gps_climb, height))
        for then, past, _, _ in history:
            if abs(offset - past) > c.baro_drift_limit:
                self.baro_fault = (
                    f"barometer drifting: its height changed {offset - past:+.1f} m against "
                    f"the GPS climb in {meas.time - then:.0f} s"
                )
                self._exclude_baro(history[0])
                return

    def _exclude_baro(self, start: tuple[float, float, float, float | None]) -> None:
        """Back to the height at the start of the window plus the GPS climb since."""
        _, _, climb, height = start
        if height is None or not self._initialised:
            return
        self._kf.x[2] = height + self._gps_climb - climb
        self._kf.P[2, :] = 0.0
        self._kf.P[:, 2] = 0.0
        self._kf.P[2, 2] = 1.0  # m^2: the window's spread (0.5 m) and the filter's own

    # ------------------------------------------------------------------ outputs
    def lost_cause(self, now: float) -> str | None:
        """Why the solution is unusable (LOST) at ``now``, or None if it is usable."""
        c = self.config
        if not self._initialised:
            return "navigation not initialised"
        if self._attitude is None or now - self._attitude.time > c.attitude_timeout:
            return "no attitude data"
        if now - self._imu_time > c.imu_timeout:
            return "no IMU data"
        if self._same_imu >= c.frozen_count:
            return "IMU frozen (identical samples)"
        age = now - self._aiding_time
        if age > c.max_dead_reckoning:
            return f"no GPS fix for {age:.1f} s (dead-reckoning limit {c.max_dead_reckoning:g} s)"
        return None

    def health(self, now: float) -> EstimatorHealth:
        """OK with current aiding, DEGRADED while dead-reckoning, LOST when unusable."""
        c = self.config
        if self.lost_cause(now) is not None:
            return EstimatorHealth.LOST
        if now - self._aiding_time > c.aiding_timeout:
            return EstimatorHealth.DEGRADED
        return EstimatorHealth.OK

    def aiding_age(self, now: float) -> float:
        """Seconds since the last accepted GPS or vision fix."""
        return now - self._aiding_time

    def estimate(self, now: float) -> EstimatedState:
        """The current solution; raises ConfigError before the filter is initialised."""
        if not self._initialised or self._attitude is None:
            raise ConfigError("state estimator not initialised (no position fix or attitude yet)")
        x = self._kf.x
        p = self._kf.P
        att = self._attitude
        return EstimatedState(
            time=now,
            position=(float(x[0]), float(x[1]), float(x[2])),
            velocity=(float(x[3]), float(x[4]), float(x[5])),
            roll=att.roll,
            pitch=att.pitch,
            heading=wrap_2pi(att.heading),
            rates=self._rates,
            on_ground=self._on_ground,
            health=self.health(now),
            position_sigma=math.sqrt(max(0.0, float(p[0, 0] + p[1, 1]) / 2.0)),
            rotor_rpm=self._rpm,
        )

    def covariance(self) -> NDArray[np.float64]:
        """Copy of the state covariance (for consistency checks)."""
        return np.array(self._kf.P, copy=True)

    def state_vector(self) -> NDArray[np.float64]:
        """Copy of the state vector [p, v, accel bias, baro bias]."""
        return np.array(self._kf.x, copy=True)

    # ------------------------------------------------------------------ internals
    def _initialise(self, position: NDArray[np.float64], velocity: NDArray[np.float64]) -> None:
        c = self.config
        x = np.zeros(_N)
        x[_P] = position
        x[_V] = velocity
        height_var, bias_var = c.gps_vertical_sigma**2, 5.0**2
        if self._baro is not None and self._warm is not None:
            bias, sigma = self._warm
            self._warm = None
            x[2] = self._baro.height - bias
            x[_BB] = bias
            height_var, bias_var = sigma**2 + c.baro_sigma**2, sigma**2
        elif self._baro is not None:
            x[_BB] = self._baro.height - position[2]
        self._kf.x = x
        self._kf.P = np.diag(
            [
                c.gps_horizontal_sigma**2,
                c.gps_horizontal_sigma**2,
                height_var,
                *([c.gps_velocity_sigma**2] * 3),
                *([0.1**2] * 3),
                bias_var,
            ]
        )
        self._initialised = True

    def _transition(
        self, dt: float
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        cached_dt, f, q, b = self._fq_cache
        if abs(cached_dt - dt) < 1e-9:
            return f, q, b
        c = self.config
        f = np.eye(_N)
        f[_P, _V] = np.eye(3) * dt
        f[_P, _BA] = -np.eye(3) * 0.5 * dt * dt
        f[_V, _BA] = -np.eye(3) * dt
        b = np.zeros((_N, 3))
        b[_P, :] = np.eye(3) * 0.5 * dt * dt
        b[_V, :] = np.eye(3) * dt
        q = np.zeros((_N, _N))
        g = np.array([[0.5 * dt * dt], [dt]])
        block = (g @ g.T) * c.accel_sigma**2
        for axis in range(3):
            idx = [axis, axis + 3]
            q[np.ix_(idx, idx)] = block
        q[_BA, _BA] = np.eye(3) * c.accel_bias_walk**2 * dt
        q[_BB, _BB] = c.baro_bias_walk**2 * dt
        self._fq_cache = (dt, f, q, b)
        return f, q, b

    def _correct(
        self,
        z: NDArray[np.float64],
        h: NDArray[np.float64],
        r: NDArray[np.float64],
        *,
        force: bool = False,
    ) -> bool:
        kf = self._kf
        y = z - h @ kf.x
        s = h @ kf.P @ h.T + r
        nis = float(y @ np.linalg.solve(s, y))
        if not force and nis > self.config.gate_sigma**2 * len(z):
            self.rejections += 1
            return False
        kf.update(z, h, r)
        return True
