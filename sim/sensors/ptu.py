"""Pan-tilt unit carrying the cameras (chapter section 4.3): limits, rate limits, angle sensor.

Pan turns about the body z axis (positive to the right), tilt about the panned y axis with
positive angles looking down: pan = 0, tilt = 0 looks forward along the body x axis, tilt =
pi/2 looks straight down.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.errors import SensorError
from sim.sensors.power import PowerDevice, PowerManager
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


@dataclass(frozen=True, slots=True)
class PtuParams:
    """Mechanical limits of the pan-tilt unit (assumed; the chapter gives none).

    Figures of a small commercial PTU for cameras of ~1 kg: about +-170 deg pan, tilt from a
    little above the horizon to slightly past nadir, and 60 deg/s slew rate.
    """

    pan_min: float = math.radians(-170.0)
    pan_max: float = math.radians(170.0)
    tilt_min: float = math.radians(-10.0)
    tilt_max: float = math.radians(95.0)
    pan_rate: float = math.radians(60.0)
    """Maximum pan speed, rad/s."""
    tilt_rate: float = math.radians(60.0)
    """Maximum tilt speed, rad/s."""
    sensor_rate_hz: float = 25.0
    """Rate of the angle reports (the chapter's camera state is published at 25 Hz)."""
    encoder_noise: float = math.radians(0.05)
    """rad, 1 sigma, angle read-out noise (stepper resolution ~0.05 deg)."""

    def __post_init__(self) -> None:
        """Reject inconsistent limits."""
        if not (self.pan_min < self.pan_max and self.tilt_min < self.tilt_max):
            raise SensorError("PTU limits must satisfy min < max")
        if not (self.pan_rate > 0.0 and self.tilt_rate > 0.0):
            raise SensorError("PTU rates must be > 0")


class PtuCommandStatus(enum.Enum):
    """Outcome of a PTU command."""

    ACCEPTED = "accepted"
    CLAMPED = "clamped"
    """Target outside the limits: moving to the nearest reachable angles."""
    REJECTED = "rejected"
    """Non-finite angles: target unchanged."""
    UNPOWERED = "unpowered"
    """The PTU is switched off: target unchanged."""


@dataclass(frozen=True, slots=True)
class PtuCommandResult:
    """Result of :meth:`PanTiltUnit.command`."""

    status: PtuCommandStatus
    pan_target: float
    tilt_target: float


class PanTiltUnit:
    """The PTU mechanism: absolute angle commands, integrated per simulation step."""

    def __init__(self, params: PtuParams | None = None, power: PowerManager | None = None) -> None:
        self.params = params or PtuParams()
        self.power = power
        self.pan = 0.0
        self.tilt = 0.0
        self.pan_target = 0.0
        self.tilt_target = 0.0

    def powered(self) -> bool:
        """Tell whether the PTU has power (True unless switched off)."""
        return self.power is None or self.power.is_on(PowerDevice.PTU)

    def command(self, pan: float, tilt: float) -> PtuCommandResult:
        """Move towards absolute angles (rad); out-of-range targets are clamped."""
        if not (math.isfinite(pan) and math.isfinite(tilt)):
            return PtuCommandResult(PtuCommandStatus.REJECTED, self.pan_target, self.tilt_target)
        if not self.powered():
            return PtuCommandResult(PtuCommandStatus.UNPOWERED, self.pan_target, self.tilt_target)
        p = self.params
        self.pan_target = min(max(pan, p.pan_min), p.pan_max)
        self.tilt_target = min(max(tilt, p.tilt_min), p.tilt_max)
        clamped = (self.pan_target, self.tilt_target) != (pan, tilt)
        status = PtuCommandStatus.CLAMPED if clamped else PtuCommandStatus.ACCEPTED
        return PtuCommandResult(status, self.pan_target, self.tilt_target)

    def step(self, dt: float) -> None:
        """Advance the mechanism by ``dt`` seconds at most at the rate limits."""
        if dt < 0.0 or not math.isfinite(dt):
            raise SensorError(f"PTU step must be finite and >= 0, got {dt}")
        if not self.powered():
            return
        self.pan += _limited(self.pan_target - self.pan, self.params.pan_rate * dt)
        self.tilt += _limited(self.tilt_target - self.tilt, self.params.tilt_rate * dt)

    @property
    def at_target(self) -> bool:
        """True when both axes have reached their targets."""
        return self.pan == self.pan_target and self.tilt == self.tilt_target


def _limited(error: float, max_step: float) -> float:
    return min(max(error, -max_step), max_step)


@dataclass(frozen=True, slots=True)
class PtuSample:
    """Measured PTU angles."""

    time: float
    pan: float
    tilt: float


class PtuSensor(Sensor[PtuSample]):
    """Angle read-out of the PTU; fields (pan, tilt) in rad for BIAS."""

    fields = ("pan", "tilt")

    def __init__(self, ptu: PanTiltUnit, seed: int = 0, power: PowerManager | None = None) -> None:
        self.ptu = ptu
        super().__init__("ptu", ptu.params.sensor_rate_hz, seed, power, PowerDevice.PTU)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        noise = scale * self.ptu.params.encoder_noise * self.rng.standard_normal(2)
        return np.array([self.ptu.pan, self.ptu.tilt]) + noise

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> PtuSample:
        return PtuSample(time, float(value[0]), float(value[1]))
