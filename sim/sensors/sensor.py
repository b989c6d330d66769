"""Base of every simulated sensor: scheduling, power gating, seeded noise, fault injection."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import replace
from typing import TYPE_CHECKING, ClassVar, Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

from sim.sensors.errors import SensorError
from sim.sensors.fault import FaultSwitch
from sim.truth_state import TruthState

if TYPE_CHECKING:
    from sim.sensors.power import PowerDevice, PowerManager

SampleT = TypeVar("SampleT")

_EPS = 1e-9  # tolerance on due times: FDM steps are float sums of dt


class Sensor(ABC, Generic[SampleT]):
    """A periodic sensor reading the ground truth.

    Subclasses define ``fields`` (layout of the measurement vector, which BIAS magnitudes refer
    to), ``_measure`` (noisy vector from the truth, None for a natural outage) and ``_pack``
    (vector to sample dataclass). Everything else is shared here.
    """

    fields: ClassVar[tuple[str, ...]] = ()
    biasable: ClassVar[NDArray[np.float64] | None] = None
    """Per-field 1/0 mask for BIAS (None: every field)."""

    def __init__(
        self,
        name: str,
        rate_hz: float,
        seed: int = 0,
        power: PowerManager | None = None,
        device: PowerDevice | None = None,
    ) -> None:
        if not (math.isfinite(rate_hz) and rate_hz > 0.0):
            raise SensorError(f"{name}: rate must be > 0 Hz, got {rate_hz}")
        self.name = name
        self.rate_hz = rate_hz
        self.power = power
        self.device = device
        self.fault = FaultSwitch()
        self.rng = np.random.default_rng(seed)
        self.reset(seed)

    @property
    def period(self) -> float:
        """Seconds between samples."""
        return 1.0 / self.rate_hz

    def reset(self, seed: int) -> None:
        """Restart: new random stream from ``seed``, no schedule, no last sample, fault kept."""
        self.rng = np.random.default_rng(seed)
        self._start: float | None = None
        self._count = 0
        self._last_time: float | None = None
        self._last: tuple[TruthState, NDArray[np.float64]] | None = None
        self._reset_state()

    def _reset_state(self) -> None:
        """Reset the subclass's error processes (they draw from ``self.rng``)."""

    def shift_time(self, seconds: float) -> None:
        """Move every time this sensor remembers by ``seconds`` (the world's clock jumped)."""
        if self._start is not None:
            self._start += seconds
        if self._last_time is not None:
            self._last_time += seconds
        if self._last is not None:
            truth, value = self._last
            self._last = (replace(truth, time=truth.time + seconds), value)

    def powered(self) -> bool:
        """Tell whether the sensor has power (True unless its device is switched off)."""
        return self.power is None or self.device is None or self.power.is_on(self.device)

    def update(self, truth: TruthState) -> SampleT | None:
        """Return the sample due at ``truth.time`` (None: not due, unpowered, dropped, faulted)."""
        if self._start is None:
            self._start = truth.time
        due = self._start + self._count * self.period
        if truth.time < due - _EPS:
            return None
        # Catch up without bursts if the caller skipped several periods.
        self._count = max(self._count + 1, math.floor((truth.time - self._start) / self.period) + 1)
        if not self.powered():
            self._last = None
            return None
        dt = 0.0 if self._last_time is None else truth.time - self._last_time
        self._last_time = truth.time
        value = self._measure(truth, dt, self.fault.noise_scale)
        if value is None:
            return None
        mask = self._bias_mask(value.size)
        last = None if self._last is None else self._last[1]
        faulty = self.fault.apply(value, last, mask)
        if faulty is None:
            return None
        if faulty is last and self._last is not None:
            return self._pack(truth.time, self._last[0], faulty)
        self._last = (truth, faulty)
        return self._pack(truth.time, truth, faulty)

    def _bias_mask(self, size: int) -> NDArray[np.float64]:
        """1 for fields a BIAS applies to, 0 for discrete ones."""
        return np.ones(size) if self.biasable is None else self.biasable

    @abstractmethod
    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        """Noisy measurement vector; ``dt`` since the previous measurement, ``scale`` on noise."""

    @abstractmethod
    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> SampleT:
        """Sample stamped ``time`` from a (possibly faulty) vector and the truth it came from."""
