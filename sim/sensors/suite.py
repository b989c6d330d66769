"""All sensors and payload actuators of one simulated RMAX, stepped together.

The world_sim node owns one suite per aircraft: each FDM step it calls :meth:`SensorSuite.step`
with the truth state and publishes whatever samples came due. Fault injection and power
switching address sensors by name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sim.sensors.attitude import AttitudeSample, AttitudeSensor
from sim.sensors.barometer import Barometer, BarometerSample
from sim.sensors.camera import COLOR_CAMERA, THERMAL_CAMERA, Camera, CameraFrame
from sim.sensors.engine import RpmSample, RpmSensor
from sim.sensors.errors import SensorError
from sim.sensors.gps import Gps, GpsSample
from sim.sensors.ground_contact import GroundContactSample, GroundContactSensor
from sim.sensors.imu import Imu, ImuSample
from sim.sensors.laser import LaserRangeFinder, LaserScan
from sim.sensors.power import PowerManager, PowerSample, PowerSensor
from sim.sensors.ptu import PanTiltUnit, PtuSample, PtuSensor
from sim.sensors.radiation import RadiationField, RadiationSample, RadiationSensor
from sim.sensors.sensor import Sensor
from sim.truth_state import TruthState
from sim.world import World
from sim.world_geometry import WorldGeometry


@dataclass(frozen=True, slots=True)
class SensorReadings:
    """Samples that came due in one step (None: not due, dropped, unpowered or faulted)."""

    time: float
    gps: GpsSample | None
    imu: ImuSample | None
    barometer: BarometerSample | None
    attitude: AttitudeSample | None
    rpm: RpmSample | None
    ground_contact: GroundContactSample | None
    power: PowerSample | None
    ptu: PtuSample | None
    color_camera: CameraFrame | None
    thermal_camera: CameraFrame | None
    laser: LaserScan | None
    radiation: RadiationSample | None


class SensorSuite:
    """The sensor set of chapter sections 4.2-4.3 and 11.2 for one aircraft."""

    def __init__(self, world: World, seed: int, geometry: WorldGeometry | None = None) -> None:
        """Build every sensor; each gets its own stream derived from ``seed``."""
        self.power = PowerManager()
        self.ptu = PanTiltUnit(power=self.power)
        geometry = geometry or WorldGeometry(world)
        self.gps = Gps(world.origin, power=self.power)
        self.imu = Imu(power=self.power)
        self.barometer = Barometer(world.origin.altitude, power=self.power)
        self.attitude = AttitudeSensor(power=self.power)
        self.rpm = RpmSensor()
        self.ground_contact = GroundContactSensor()
        self.power_sensor = PowerSensor(self.power)
        self.ptu_sensor = PtuSensor(self.ptu, power=self.power)
        self.color_camera = Camera(COLOR_CAMERA, self.ptu, power=self.power)
        self.thermal_camera = Camera(THERMAL_CAMERA, self.ptu, power=self.power)
        self.laser = LaserRangeFinder(geometry, power=self.power)
        self.radiation = RadiationSensor(RadiationField(world))
        self.reset(seed)

    def sensors(self) -> dict[str, Sensor[Any]]:
        """Every sensor by its name (for fault injection)."""
        all_sensors: list[Sensor[Any]] = [
            self.gps,
            self.imu,
            self.barometer,
            self.attitude,
            self.rpm,
            self.ground_contact,
            self.power_sensor,
            self.ptu_sensor,
            self.color_camera,
            self.thermal_camera,
            self.laser,
            self.radiation,  # last: the seeds of the others do not change
        ]
        return {s.name: s for s in all_sensors}

    def sensor(self, name: str) -> Sensor[Any]:
        """Return the sensor called ``name`` (SensorError if none)."""
        found = self.sensors().get(name)
        if found is None:
            known = ", ".join(sorted(self.sensors()))
            raise SensorError(f"no sensor named {name!r} (known: {known})")
        return found

    def reset(self, seed: int) -> None:
        """Restart every sensor with independent streams derived from ``seed``."""
        sensors = list(self.sensors().values())
        children = np.random.SeedSequence(seed).spawn(len(sensors))
        for sensor, child in zip(sensors, children, strict=True):
            sensor.reset(int(child.generate_state(1)[0]))

    def shift_time(self, seconds: float) -> None:
        """Move every sensor's remembered times by ``seconds`` (the world's clock jumped)."""
        for sensor in self.sensors().values():
            sensor.shift_time(seconds)

    def step(self, truth: TruthState, dt: float) -> SensorReadings:
        """Advance the payload mechanisms by ``dt`` and read every sensor at ``truth.time``."""
        self.ptu.step(dt)
        self.color_camera.step(dt)
        self.thermal_camera.step(dt)
        self.laser.step(dt)
        return SensorReadings(
            time=truth.time,
            gps=self.gps.update(truth),
            imu=self.imu.update(truth),
            barometer=self.barometer.update(truth),
            attitude=self.attitude.update(truth),
            rpm=self.rpm.update(truth),
            ground_contact=self.ground_contact.update(truth),
            power=self.power_sensor.update(truth),
            ptu=self.ptu_sensor.update(truth),
            color_camera=self.color_camera.update(truth),
            thermal_camera=self.thermal_camera.update(truth),
            laser=self.laser.update(truth),
            radiation=self.radiation.update(truth),
        )
