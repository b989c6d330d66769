"""Power management: switches, status bitmask matching HelicopterState, voltage and current."""

from __future__ import annotations

import pytest

from sim.sensors.fake_truth import make_truth
from sim.sensors.power import ALL_DEVICES, DEVICE_CURRENT, PowerDevice, PowerManager, PowerSensor

MSG_BITS = {
    "POWER_PFC": PowerDevice.PFC,
    "POWER_PPC": PowerDevice.PPC,
    "POWER_DRC": PowerDevice.DRC,
    "POWER_GPS": PowerDevice.GPS,
    "POWER_IMU": PowerDevice.IMU,
    "POWER_COLOR_CAMERA": PowerDevice.COLOR_CAMERA,
    "POWER_THERMAL_CAMERA": PowerDevice.THERMAL_CAMERA,
    "POWER_PTU": PowerDevice.PTU,
    "POWER_LASER": PowerDevice.LASER,
    "POWER_RADIO": PowerDevice.RADIO,
}


@pytest.mark.parametrize("constant", sorted(MSG_BITS))
def test_bits_equal_the_message_constants(constant: str) -> None:
    from hdrc3_interfaces.msg import HelicopterState

    assert getattr(HelicopterState, constant) == MSG_BITS[constant].value


def test_switching_devices() -> None:
    manager = PowerManager()
    assert manager.status == int(ALL_DEVICES) == 1023
    manager.switch(PowerDevice.LASER | PowerDevice.PTU, on=False)
    assert not manager.is_on(PowerDevice.LASER) and manager.is_on(PowerDevice.GPS)
    assert manager.status == 1023 - 256 - 128
    manager.switch(PowerDevice.PTU, on=True)
    assert manager.is_on(PowerDevice.PTU) and not manager.is_on(PowerDevice.PTU | PowerDevice.LASER)


def test_current_and_voltage_follow_the_load() -> None:
    manager = PowerManager()
    full = manager.current()
    assert full == pytest.approx(sum(DEVICE_CURRENT.values()))
    sensor = PowerSensor(manager, seed=1)
    loaded = sensor.update(make_truth(0.0))
    manager.switch(PowerDevice.LASER, on=False)
    light = sensor.update(make_truth(1.0))
    assert loaded is not None and light is not None
    assert light.status == manager.status
    assert light.current == pytest.approx(full - DEVICE_CURRENT[PowerDevice.LASER], abs=0.3)
    assert light.voltage > loaded.voltage - 0.1  # less sag with less load
