"""The YACS's sensor front end (the Yamaha Attitude Sensor, YAS): what the inner loop flies on.

The YACS never sees the true state. After every 200 Hz flight-model step the aircraft's
``SensorSuite`` is read once; :meth:`Yas.observe` takes those very samples (the ones world_sim
publishes, same noise, biases and injected faults) and keeps the inner loop's estimate:

- attitude: roll/pitch of the attitude sensor (50 Hz) blended into a gyro-propagated estimate
  (a complementary filter, as an AHRS does): the 200 Hz gyro carries the estimate between the
  attitude samples and smooths their white noise, the samples remove the gyro's bias drift;
- body rates: the IMU gyro (200 Hz). The real YAS has rate gyros of its own; the simulation has one
  rate-gyro model, the IMU, and both the YACS and the PFC's navigation filter read it;
- climb rate: a baro-inertial vertical channel (third-order complementary filter: height,
  climb rate, accelerometer bias) on the barometer (25 Hz) and the IMU's vertical specific force.
  That is what a vertical-rate hold without GPS uses: the barometer alone is far too noisy to
  differentiate (0.3 m at 25 Hz is ~10 m/s of rate noise), the accelerometer alone drifts; GPS
  velocity is the flight computer's sensor, not the helicopter's, and has outages;
- ground contact: the skid switch, last sample held.

A missing measurement never raises. A sensor counts as *lost* when it delivered no sample for its
timeout (dropped, unpowered) or repeats the previous vector bit for bit (FREEZE: a live noisy
sensor never does). Then: attitude lost -> the estimate coasts on the gyros alone
(``attitude_ok`` False; it drifts with the gyro bias, about 0.2 deg/s); gyro lost -> the
attitude follows the attitude samples directly and the rates are their differences
(``rates_ok`` False); both lost -> the estimate freezes and the rates read zero. Climb rate
without barometer coasts on the accelerometer (the height is re-anchored when the barometer comes
back), without IMU it follows the barometer alone (slower and noisier: 0.3 rad/s bandwidth).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.sensors.attitude import AttitudeSample
from sim.sensors.imu import ImuSample
from sim.sensors.suite import SensorReadings
from sim.yacs import YacsInput

GRAVITY = 9.80665
"""m/s^2; the bias state absorbs the difference to local gravity."""


@dataclass(frozen=True, slots=True)
class YasParams:
    """Filter gains and staleness timeouts of the YAS front end."""

    attitude_blend: float = 0.2
    """Fraction of the attitude-sample innovation taken per sample (time constant ~0.1 s at
    50 Hz: the gyro bias leaves < 0.05 deg, the 0.2 deg sample noise drops to ~0.07 deg)."""
    attitude_timeout: float = 0.1
    """s without a new attitude sample before the attitude counts as lost (5 samples)."""
    rate_timeout: float = 0.025
    """s without a new gyro sample before the rates count as lost (5 samples)."""
    vertical_bandwidth: float = 0.3
    """rad/s, triple pole of the baro-inertial filter in the air."""
    ground_bandwidth: float = 1.0
    """rad/s, double pole of the zero-velocity update (climb rate, bias) on the skids."""
    baro_gap: float = 0.2
    """s between barometer samples (5 missed) after which the height is re-anchored."""


def _wrap_pi(angle: float) -> float:
    return (angle + math.pi) % math.tau - math.pi


class Yas:
    """Attitude, rate, climb-rate and ground-contact estimate from the aircraft's sensor samples."""

    def __init__(self, params: YasParams | None = None) -> None:
        """Empty estimate: level, at rest, airborne until the skid switch says otherwise."""
        self.params = params or YasParams()
        self.reset()

    def reset(self) -> None:
        """Forget everything (level, at rest, no sample seen)."""
        self._time: float | None = None
        self.roll = 0.0
        self.pitch = 0.0
        self.heading = 0.0
        self._rates = (0.0, 0.0, 0.0)
        self._accel_up = 0.0
        self._attitude: AttitudeSample | None = None
        self._imu: ImuSample | None = None
        self._attitude_time = -math.inf
        self._imu_time = -math.inf
        self._baro_time = -math.inf
        self._height: float | None = None
        self._climb = 0.0
        self._accel_bias = 0.0
        self._on_ground = False
        self.attitude_ok = False
        """True while the attitude sensor delivers fresh samples."""
        self.rates_ok = False
        """True while the gyro delivers fresh samples."""

    def shift_time(self, seconds: float) -> None:
        """Move the times of the last step and samples by ``seconds`` (the world's clock jumped)."""
        if self._time is not None:
            self._time += seconds
        self._attitude_time += seconds
        self._imu_time += seconds
        self._baro_time += seconds

    def observe(self, readings: SensorReadings) -> None:
        """Advance to ``readings.time`` and fuse the samples that came due in this step."""
        now = readings.time
        dt = 0.0 if self._time is None else max(0.0, now - self._time)
        self._time = now
        p = self.params
        imu = self._fresh_imu(readings.imu)
        if imu is not None:
            self._imu_time = now
            self._rates = imu.angular_rate
        self.rates_ok = now - self._imu_time <= p.rate_timeout + 1e-9
        if self.rates_ok:
            self._propagate_attitude(dt)
        attitude = self._fresh_attitude(readings.attitude)
        if attitude is not None:
            self._fuse_attitude(attitude, now)
        self.attitude_ok = now - self._attitude_time <= p.attitude_timeout + 1e-9
        if imu is not None:
            self._accel_up = self._vertical_specific_force(imu) - GRAVITY
        self._propagate_vertical(dt)
        if readings.barometer is not None:
            self._fuse_baro(readings.barometer.altitude, now - self._baro_time)
            self._baro_time = now
        if readings.ground_contact is not None:
            self._on_ground = readings.ground_contact.on_ground

    @property
    def accel_bias(self) -> float:
        """Estimated bias of the vertical specific force, m/s^2 (for test evaluation)."""
        return self._accel_bias

    def measurement(self) -> YacsInput:
        """The YACS input now."""
        p, q, r = self._rates if self.rates_ok or self.attitude_ok else (0.0, 0.0, 0.0)
        return YacsInput(
            roll=self.roll,
            pitch=self.pitch,
            p=p,
            q=q,
            r=r,
            climb_rate=self._climb,
            on_ground=self._on_ground,
            attitude_ok=self.attitude_ok,
        )

    # ------------------------------------------------------------- attitude
    def _fresh_imu(self, imu: ImuSample | None) -> ImuSample | None:
        """The IMU sample unless absent or stuck (identical to the previous one)."""
        if imu is None:
            return None
        previous, self._imu = self._imu, imu
        stuck = previous is not None and (
            previous.angular_rate == imu.angular_rate
            and previous.specific_force == imu.specific_force
        )
        return None if stuck else imu

    def _fresh_attitude(self, sample: AttitudeSample | None) -> AttitudeSample | None:
        """The attitude sample unless absent or stuck (identical to the previous one)."""
        if sample is None:
            return None
        previous, self._attitude = self._attitude, sample
        stuck = previous is not None and (
            (previous.roll, previous.pitch, previous.heading)
            == (sample.roll, sample.pitch, sample.heading)
        )
        return None if stuck else sample

    def _propagate_attitude(self, dt: float) -> None:
        p, q, r = self._rates
        sr, cr = math.sin(self.roll), math.cos(self.roll)
        cp = math.cos(self.pitch)
        cp = math.copysign(max(abs(cp), 1e-3), cp)  # no blow-up at +-90 deg pitch
        tp = math.sin(self.pitch) / cp
        self.roll = _wrap_pi(self.roll + (p + (q * sr + r * cr) * tp) * dt)
        self.pitch += (q * cr - r * sr) * dt
        self.heading = (self.heading + (q * sr + r * cr) / cp * dt) % math.tau

    def _fuse_attitude(self, sample: AttitudeSample, now: float) -> None:
        first = self._attitude_time == -math.inf
        if self.rates_ok and not first:
            k = self.params.attitude_blend
            self.roll = _wrap_pi(self.roll + k * _wrap_pi(sample.roll - self.roll))
            self.pitch += k * (sample.pitch - self.pitch)
            self.heading = (self.heading + k * _wrap_pi(sample.heading - self.heading)) % math.tau
        else:
            if not self.rates_ok and not first:
                self._rates = self._rates_from_attitude(sample, now - self._attitude_time)
            self.roll, self.pitch, self.heading = sample.roll, sample.pitch, sample.heading
        self._attitude_time = now

    def _rates_from_attitude(self, sample: AttitudeSample, dt: float) -> tuple[float, float, float]:
        """Body rates from the change since the last estimate (gyro lost)."""
        if dt <= 0.0:
            return self._rates
        roll_dot = _wrap_pi(sample.roll - self.roll) / dt
        pitch_dot = (sample.pitch - self.pitch) / dt
        yaw_dot = _wrap_pi(sample.heading - self.heading) / dt
        sr, cr = math.sin(sample.roll), math.cos(sample.roll)
        sp, cp = math.sin(sample.pitch), math.cos(sample.pitch)
        return (
            roll_dot - yaw_dot * sp,
            pitch_dot * cr + yaw_dot * sr * cp,
            -pitch_dot * sr + yaw_dot * cr * cp,
        )

    # ------------------------------------------------------------- vertical
    def _vertical_specific_force(self, imu: ImuSample) -> float:
        """Upward component of the measured specific force (body FRD rotated by the estimate)."""
        fx, fy, fz = imu.specific_force
        sr, cr = math.sin(self.roll), math.cos(self.roll)
        sp, cp = math.sin(self.pitch), math.cos(self.pitch)
        return -(-sp * fx + sr * cp * fy + cr * cp * fz)

    def _propagate_vertical(self, dt: float) -> None:
        if self._height is None:
            return
        accel = self._accel_up - self._accel_bias if self.rates_ok else 0.0
        self._height += (self._climb + 0.5 * accel * dt) * dt
        self._climb += accel * dt
        if self._on_ground and self.rates_ok:
            # On the skids the climb rate is zero: a zero-velocity update, whose velocity error
            # also aligns the accelerometer bias (as a real YAS does before take-off). Going
            # through the velocity lets the jolts of the skids (tens of m/s^2 for a step, but no
            # net velocity) cancel instead of entering the bias.
            w = self.params.ground_bandwidth
            self._accel_bias += w * w * self._climb * dt
            self._climb -= min(1.0, 2.0 * w * dt) * self._climb

    def _fuse_baro(self, height: float, interval: float) -> None:
        """Correct height, climb rate and accelerometer bias with one barometer sample."""
        if self._height is None or interval > self.params.baro_gap:
            # first fix, or the first after an outage: only the climb rate matters to the YACS,
            # so take the height as it is rather than bleed the gap's error into the climb rate
            self._height = height
            return
        # gains of the continuous filter with poles (s + w)^3, over the interval since the last fix
        w = self.params.vertical_bandwidth
        error = height - self._height
        self._height += 3.0 * w * error * interval
        if self._on_ground and self.rates_ok:
            return  # climb rate and bias come from the zero-velocity update
        self._climb += 3.0 * w * w * error * interval
        if self.rates_ok:  # without accelerometer there is no bias to learn
            self._accel_bias -= w**3 * error * interval
