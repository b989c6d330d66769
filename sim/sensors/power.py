"""Power management unit (chapter section 4.3): device switches, bus voltage and current.

The unit switches every on-board device on or off in software and reports voltage and current
consumption; the status bitmask uses the ``POWER_*`` bits of ``HelicopterState.msg``.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState


class PowerDevice(enum.IntFlag):
    """Switchable devices; values equal HelicopterState.POWER_* constants."""

    PFC = 1
    PPC = 2
    DRC = 4
    GPS = 8
    IMU = 16
    COLOR_CAMERA = 32
    THERMAL_CAMERA = 64
    PTU = 128
    LASER = 256
    RADIO = 512


ALL_DEVICES = PowerDevice(sum(d.value for d in PowerDevice))

DEVICE_CURRENT: dict[PowerDevice, float] = {
    PowerDevice.PFC: 1.2,
    PowerDevice.PPC: 1.2,
    PowerDevice.DRC: 2.0,
    PowerDevice.GPS: 0.2,
    PowerDevice.IMU: 0.2,
    PowerDevice.COLOR_CAMERA: 0.4,
    PowerDevice.THERMAL_CAMERA: 0.3,
    PowerDevice.PTU: 0.8,
    PowerDevice.LASER: 1.6,
    PowerDevice.RADIO: 0.6,
}
"""Nominal current draw at 12 V, A (assumed: PC104 boards ~15 W, LMS-291 ~20 W, PTU ~10 W)."""


class PowerManager:
    """Software power switches of the on-board devices (all on after construction)."""

    def __init__(self, on: PowerDevice = ALL_DEVICES) -> None:
        self._on = PowerDevice(on)

    def switch(self, device: PowerDevice, on: bool) -> None:
        """Switch one device (or several OR-ed together) on or off."""
        self._on = self._on | device if on else self._on & ~device

    def is_on(self, device: PowerDevice) -> bool:
        """Tell whether every device in ``device`` is powered."""
        return (self._on & device) == device

    @property
    def status(self) -> int:
        """Bitmask of powered devices (HelicopterState.power_status)."""
        return int(self._on)

    def current(self) -> float:
        """Total current drawn by the powered devices, A."""
        return sum(a for d, a in DEVICE_CURRENT.items() if self._on & d)


@dataclass(frozen=True, slots=True)
class PowerParams:
    """Battery and measurement model of the power management unit."""

    rate_hz: float = 5.0
    nominal_voltage: float = 12.6
    """Open-circuit bus voltage, V (3S LiPo-like 12 V bus)."""
    internal_resistance: float = 0.05
    """Ohm: voltage sag under load."""
    voltage_noise: float = 0.02
    """V, 1 sigma (10-bit ADC over ~20 V full scale)."""
    current_noise: float = 0.05
    """A, 1 sigma (hall-effect current sensor)."""


@dataclass(frozen=True, slots=True)
class PowerSample:
    """One power-management report."""

    time: float
    status: int
    """Bitmask of powered devices (POWER_* bits)."""
    voltage: float
    current: float


class PowerSensor(Sensor[PowerSample]):
    """Reports the power manager's switch state, bus voltage and current."""

    fields = ("voltage", "current", "status")
    biasable = np.array([1.0, 1.0, 0.0])

    def __init__(self, manager: PowerManager, params: PowerParams | None = None, seed: int = 0):
        self.manager = manager
        self.params = params or PowerParams()
        super().__init__("power", self.params.rate_hz, seed=seed)

    def _measure(self, truth: TruthState, dt: float, scale: float) -> NDArray[np.float64] | None:
        p = self.params
        current = self.manager.current()
        noise = scale * self.rng.standard_normal(2)
        voltage = p.nominal_voltage - p.internal_resistance * current + p.voltage_noise * noise[0]
        return np.array([voltage, current + p.current_noise * noise[1], self.manager.status])

    def _pack(self, time: float, truth: TruthState, value: NDArray[np.float64]) -> PowerSample:
        return PowerSample(time, int(value[2]), float(value[0]), float(value[1]))
