"""Fault injection shared by every sensor: drop, freeze, bias, noise-up.

One implementation for all sensors: a sensor exposes its measurement as a float vector; the
switch turns that vector into the faulty one (or None for a dropped sample).
"""

from __future__ import annotations

import enum
import math

import numpy as np
from numpy.typing import NDArray

from sim.sensors.errors import SensorError


class FaultMode(enum.Enum):
    """Injected fault of one sensor."""

    NONE = "none"
    DROP = "drop"
    """No samples at all (cable cut, device dead)."""
    FREEZE = "freeze"
    """The last good sample is repeated with fresh timestamps (stuck value)."""
    BIAS = "bias"
    """``magnitude`` is added to the measurement vector (scalar or per-field, sensor units)."""
    NOISE_UP = "noise_up"
    """The sensor's random noise is multiplied by ``magnitude`` (>= 0)."""


class FaultSwitch:
    """The fault currently injected into one sensor (mutable: tests flip it at run time)."""

    def __init__(self) -> None:
        self.mode = FaultMode.NONE
        self.magnitude: NDArray[np.float64] = np.zeros(1)

    def set(self, mode: FaultMode, magnitude: float | tuple[float, ...] = 0.0) -> None:
        """Inject ``mode``; ``magnitude`` is the bias (BIAS) or noise factor (NOISE_UP)."""
        values = np.atleast_1d(np.asarray(magnitude, dtype=np.float64))
        if not np.all(np.isfinite(values)):
            raise SensorError(f"fault magnitude must be finite, got {magnitude}")
        if mode is FaultMode.NOISE_UP and (values.size != 1 or values[0] < 0.0):
            raise SensorError(f"noise-up factor must be one number >= 0, got {magnitude}")
        self.mode = mode
        self.magnitude = values

    def clear(self) -> None:
        """Remove the fault."""
        self.set(FaultMode.NONE)

    @property
    def noise_scale(self) -> float:
        """Factor on the sensor's random noise (1 unless NOISE_UP)."""
        return float(self.magnitude[0]) if self.mode is FaultMode.NOISE_UP else 1.0

    def apply(
        self,
        value: NDArray[np.float64],
        last: NDArray[np.float64] | None,
        biasable: NDArray[np.float64],
    ) -> NDArray[np.float64] | None:
        """Faulty version of ``value`` given the last published vector (None: dropped).

        ``biasable`` is 1 for fields a bias applies to and 0 for discrete fields (bitmasks).
        """
        if self.mode is FaultMode.DROP:
            return None
        if self.mode is FaultMode.FREEZE and last is not None:
            return last
        if self.mode is FaultMode.BIAS:
            if self.magnitude.size not in (1, value.size):
                raise SensorError(
                    f"bias has {self.magnitude.size} values, the sensor measures {value.size}"
                )
            return value + self.magnitude * biasable
        return value


def wrap_angle(angle: float) -> float:
    """Angle wrapped to [0, 2*pi)."""
    return angle % math.tau
