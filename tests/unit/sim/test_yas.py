import math
from dataclasses import replace

import pytest

from sim.rc_transmitter import FlightModeSwitch, RcState, RcSticks
from sim.rmax_params import RmaxParams
from sim.sensors.attitude import AttitudeSample
from sim.sensors.barometer import BarometerSample, isa_pressure
from sim.sensors.fault import FaultMode
from sim.sensors.ground_contact import GroundContactSample
from sim.sensors.imu import ImuSample
from sim.sensors.suite import SensorReadings
from sim.world_loader import load_world
from sim.world_sim import SimConfig, WorldSim
from sim.yacs import Yacs, YacsCommand, YacsInput
from sim.yas import GRAVITY, Yas

DT = 0.005
HOVER_FORCE = (0.0, 0.0, -GRAVITY)


def readings(
    time: float,
    *,
    attitude: tuple[float, float, float] | None = None,
    rates: tuple[float, float, float] | None = None,
    force: tuple[float, float, float] = HOVER_FORCE,
    altitude: float | None = None,
    on_ground: bool | None = None,
) -> SensorReadings:
    """One step's samples; None fields were not due (or dropped)."""
    return SensorReadings(
        time=time,
        gps=None,
        imu=None if rates is None else ImuSample(time, force, rates),
        barometer=None
        if altitude is None
        else BarometerSample(time, altitude, isa_pressure(altitude)),
        attitude=None if attitude is None else AttitudeSample(time, *attitude),
        rpm=None,
        ground_contact=None if on_ground is None else GroundContactSample(time, on_ground),
        power=None,
        ptu=None,
        color_camera=None,
        thermal_camera=None,
        laser=None,
        radiation=None,
    )


def feed(yas: Yas, start: int, steps: int, roll_rate: float, attitude: bool, gyro: bool) -> None:
    """Steps of a constant roll rate; attitude every 4th step (50 Hz), gyro every step.

    The ``k * 1e-9`` stand for sensor noise: a live sensor never repeats its vector exactly.
    """
    for k in range(start, start + steps):
        t = k * DT
        roll = roll_rate * (k - start) * DT
        yas.observe(
            readings(
                t,
                attitude=(roll, 0.0, k * 1e-9) if attitude and k % 4 == 0 else None,
                rates=(roll_rate + k * 1e-9, 0.0, 0.0) if gyro else None,
            )
        )


@pytest.mark.parametrize(
    ("attitude", "gyro", "attitude_ok", "rates_ok", "roll_after_1s"),
    [
        (True, True, True, True, 0.2),  # nominal: estimate follows the rotation
        (False, True, False, True, 0.2),  # attitude lost: coasts on the gyro
        (True, False, True, False, 0.2),  # gyro lost: attitude samples, rates from differences
        (False, False, False, False, 0.0),  # both lost: frozen at the last estimate
    ],
)
def test_lost_sensors_degrade_the_estimate_in_a_defined_way(
    attitude: bool, gyro: bool, attitude_ok: bool, rates_ok: bool, roll_after_1s: float
) -> None:
    yas = Yas()
    feed(yas, 0, 200, 0.0, attitude=True, gyro=True)  # 1 s level, both sensors fine
    assert (yas.attitude_ok, yas.rates_ok) == (True, True)
    feed(yas, 200, 201, 0.2, attitude=attitude, gyro=gyro)  # then roll at 0.2 rad/s
    meas = yas.measurement()
    assert (meas.attitude_ok, yas.rates_ok) == (attitude_ok, rates_ok)
    assert meas.roll == pytest.approx(roll_after_1s, abs=0.01)
    assert meas.p == pytest.approx(0.2 if attitude or gyro else 0.0, abs=0.01)


def test_stuck_attitude_counts_as_lost_and_the_gyro_carries_on() -> None:
    yas = Yas()
    feed(yas, 0, 200, 0.0, attitude=True, gyro=True)
    for k in range(200, 400):  # the sensor repeats its last vector (FREEZE) while rolling
        t = k * DT
        yas.observe(readings(t, attitude=(0.0, 0.0, 0.0), rates=(0.2, 0.0, k * 1e-9)))
    assert not yas.attitude_ok
    assert yas.roll == pytest.approx(0.2 * 199 * DT, abs=0.01)


def test_climb_rate_from_barometer_and_accelerometer() -> None:
    yas = Yas()
    climb = 1.0
    for k in range(12000):  # 60 s of steady climb (from a zero estimate), barometer at 25 Hz
        t = k * DT
        yas.observe(
            readings(
                t,
                attitude=(0.0, 0.0, k * 1e-9) if k % 4 == 0 else None,
                rates=(0.0, 0.0, k * 1e-9),
                altitude=100.0 + climb * t if k % 8 == 0 else None,
                on_ground=False if k % 4 == 0 else None,
            )
        )
    assert yas.measurement().climb_rate == pytest.approx(climb, abs=0.02)


def test_on_the_skids_the_climb_rate_is_zero_and_the_bias_aligns() -> None:
    yas = Yas()
    bias = 0.08  # accelerometer reads 0.08 m/s^2 too much upward
    for k in range(2000):
        t = k * DT
        yas.observe(
            readings(
                t,
                attitude=(0.0, 0.0, k * 1e-9) if k % 4 == 0 else None,
                rates=(0.0, 0.0, k * 1e-9),
                force=(0.0, 0.0, -GRAVITY - bias),
                altitude=50.0 if k % 8 == 0 else None,
                on_ground=True if k % 4 == 0 else None,
            )
        )
    meas = yas.measurement()
    assert meas.on_ground
    assert meas.climb_rate == pytest.approx(0.0, abs=0.005)
    assert yas.accel_bias == pytest.approx(bias, abs=0.005)


def test_yacs_freezes_its_attitude_integrators_while_the_attitude_is_lost() -> None:
    rc = RcState(link_ok=True, mode=FlightModeSwitch.AUTONOMOUS, engine_on=True, sticks=RcSticks())
    tilted = YacsInput(0.05, 0.0, 0.0, 0.0, 0.0, 0.0, on_ground=False)
    outputs = {}
    for ok in (True, False):
        yacs = Yacs(RmaxParams(), DT)
        yacs.command(YacsCommand())
        first = yacs.step(rc, replace(tilted, attitude_ok=ok))
        for _ in range(199):
            last = yacs.step(rc, replace(tilted, attitude_ok=ok))
        outputs[ok] = last.lateral - first.lateral
    assert outputs[True] < -0.01  # the integrator trims against the error
    assert outputs[False] == 0.0  # coasted attitude: the trim stays


WORLD = load_world("revinge")


def hovering_sim() -> WorldSim:
    sim = WorldSim(SimConfig(WORLD, ("uav0",), seed=4))
    rc = sim.agents["uav0"].aircraft.rc
    rc.set_engine(True)
    rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    for vertical, seconds in ((-1.0, 11.0), (1.5, 4.0), (0.0, 3.0)):
        sim.command("uav0", YacsCommand(vertical=vertical))
        for _ in range(round(seconds * 50)):
            sim.advance()
    return sim


def test_the_yacs_flies_the_attitude_sensor_world_sim_publishes() -> None:
    sim = hovering_sim()
    bias = math.radians(3.0)
    sim.agents["uav0"].sensors.attitude.fault.set(FaultMode.BIAS, (bias, 0.0, 0.0))
    for _ in range(150):
        sim.advance()
    # the YACS holds the *measured* roll at zero, so the aircraft hangs at minus the bias
    assert sim.truth("uav0").roll == pytest.approx(-bias, abs=math.radians(0.5))


@pytest.mark.parametrize("mode", [FaultMode.DROP, FaultMode.FREEZE])
def test_lost_attitude_sensor_in_hover_coasts_and_recovers(mode: FaultMode) -> None:
    sim = hovering_sim()
    attitude = sim.agents["uav0"].sensors.attitude
    attitude.fault.set(mode)
    for _ in range(250):  # 5 s on the gyros alone
        sim.advance()
        truth = sim.truth("uav0")
        assert abs(truth.roll) < math.radians(10.0) and abs(truth.pitch) < math.radians(10.0)
    assert not sim.status("uav0").attitude_ok
    attitude.fault.clear()
    for _ in range(100):
        sim.advance()
    truth = sim.truth("uav0")
    assert sim.status("uav0").attitude_ok
    assert abs(truth.roll) < math.radians(2.0) and abs(truth.pitch) < math.radians(2.0)
    assert not truth.on_ground
