import math
import xml.etree.ElementTree as ET

import pytest

from hdrc3_base.errors import ConfigError
from sim.aircraft import Aircraft
from sim.flight_model import MODEL_DIR, FlightModel, InitialPlacement, ServoCommand
from sim.rc_transmitter import FlightModeSwitch
from sim.rmax_params import RmaxParams
from sim.rotor import figure_of_merit, hover_collective, momentum_hover_power
from sim.velocity_hold import VelocityHold, fly
from sim.yacs import YacsCommand

G = 9.80665


def sloped(east: float, north: float) -> float:
    return 12.0 + 0.02 * east - 0.01 * north


def test_xml_matches_params() -> None:
    p = RmaxParams()
    root = ET.parse(MODEL_DIR / "rmax.xml").getroot()
    mb = root.find("mass_balance")
    assert mb is not None
    assert float(mb.findtext("emptywt", "nan")) == p.empty_mass
    inertia = tuple(float(mb.findtext(k, "nan")) for k in ("ixx", "iyy", "izz"))
    assert inertia == p.inertia
    assert float(mb.findtext("location/z", "nan")) == p.skid_height


@pytest.mark.parametrize(
    ("east", "north", "heading"), [(0.0, 0.0, 0.0), (120.0, -40.0, 1.2), (-300.0, 250.0, 4.0)]
)
def test_starts_on_the_terrain_engine_off(east: float, north: float, heading: float) -> None:
    fm = FlightModel(placement=InitialPlacement(east, north, heading), terrain_height=sloped)
    for _ in range(200):
        fm.step()
    s = fm.truth()
    assert s.position_enu[0] == pytest.approx(east, abs=0.05)
    assert s.position_enu[1] == pytest.approx(north, abs=0.05)
    assert s.position_enu[2] == pytest.approx(sloped(east, north) + 0.45, abs=0.03)
    assert s.heading == pytest.approx(heading, abs=0.01)
    assert s.on_ground and not s.engine_running and s.rotor_rpm == 0.0
    assert abs(s.height_above_ground) < 0.03
    assert s.specific_force_body[2] == pytest.approx(-G, rel=0.01)
    assert s.mass == pytest.approx(61.0 + 4.4, abs=0.01)


def test_payload_and_fuel_set_mass() -> None:
    fm = FlightModel(fuel=2.0, payload=10.0)
    assert fm.truth().mass == pytest.approx(73.0, abs=0.01)
    fm.set_payload(0.0)
    assert fm.truth().mass == pytest.approx(63.0, abs=0.01)


@pytest.mark.parametrize(
    "kwargs", [{"fuel": -1.0}, {"fuel": 50.0}, {"payload": float("nan")}, {"rate_hz": 0.0}]
)
def test_bad_configuration_raises(kwargs: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        FlightModel(**kwargs)  # type: ignore[arg-type]


def test_wind_must_be_finite() -> None:
    with pytest.raises(ConfigError):
        FlightModel().set_wind((math.inf, 0.0, 0.0))


def trajectory() -> list[tuple[float, ...]]:
    ac = Aircraft(payload=5.0)
    ac.model.set_wind((3.0, -2.0, 0.0))
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(10.5)
    ac.command(YacsCommand(roll=0.05, pitch=-0.05, yaw_rate=0.2, vertical=1.5))
    out: list[tuple[float, ...]] = []
    for _ in range(800):
        ac.step()
        s = ac.truth()
        out.append((*s.position_enu, *s.velocity_enu, s.roll, s.pitch, s.heading, s.rotor_rpm))
    return out


def test_same_inputs_bit_identical_trajectory() -> None:
    first = trajectory()
    assert first[-1][2] > 1.0  # it did fly
    assert trajectory() == first


def hover_aircraft(mass_payload: float) -> Aircraft:
    ac = Aircraft(payload=mass_payload)
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(10.0)
    hold = VelocityHold()
    fly(ac, hold, 10.0, climb_rate=1.5)
    fly(ac, hold, 12.0)
    return ac


@pytest.mark.parametrize("payload", [0.0, 25.0])
def test_hover_collective_and_power_versus_momentum_theory(payload: float) -> None:
    ac = hover_aircraft(payload)
    m = ac.model
    p = m.params
    s = ac.truth()
    assert s.height_above_ground > 9.0  # out of ground effect (hub > 6 R)
    thrust, power = 0.0, 0.0
    pitches = 0.0
    n = 200
    for _ in range(n):
        ac.step()
        thrust += m.main_thrust / n
        power += m.main_power / n
        pitches += m.collective_pitch() / n
    weight = ac.truth().mass * G
    assert thrust == pytest.approx(weight, rel=0.03)
    tip = p.omega * p.main_rotor.radius
    ct = thrust / (1.225 * p.main_rotor.disc_area * tip * tip)
    fm = figure_of_merit(p.main_rotor, ct)
    ideal = momentum_hover_power(thrust, 1.225, p.main_rotor.disc_area)
    assert power == pytest.approx(ideal / fm, rel=0.2)
    assert pitches == pytest.approx(hover_collective(p.main_rotor, ct), rel=0.2)


def test_overweight_cannot_lift_off() -> None:
    ac = Aircraft(payload=100.0)  # 165 kg, far above the 95 kg maximum take-off mass
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(11.0)
    ac.command(YacsCommand(vertical=1.0))
    for _ in range(15):
        ac.run(1.0)
        assert ac.truth().on_ground
    s = ac.truth()
    assert s.height_above_ground < 0.05
    assert ac.model.servos.collective == 1.0  # it tried with everything it had


def test_engine_off_stays_on_ground() -> None:
    fm = FlightModel()
    fm.set_servos(ServoCommand(collective=1.0))
    for _ in range(2000):
        fm.step()
    assert fm.truth().on_ground and fm.truth().rotor_rpm == 0.0


def test_level_flight_at_15_m_s() -> None:
    ac = hover_aircraft(10.0)
    hold = VelocityHold()
    s = fly(ac, hold, 30.0, velocity_en=(0.0, 15.0))
    assert s.velocity_enu[1] == pytest.approx(15.0, abs=0.3)
    assert abs(s.velocity_enu[2]) < 0.2
    assert -0.25 < s.pitch < 0.0  # nose down to fly forward
    assert ac.model.powertrain.omega == pytest.approx(ac.model.params.omega, rel=0.01)


def test_hover_in_10_m_s_wind_holds_attitude() -> None:
    ac = hover_aircraft(10.0)
    ac.model.set_wind((10.0, 0.0, 0.0))  # air moves east: wind from the west, from the left
    hold = VelocityHold()
    fly(ac, hold, 30.0)
    rolls = []
    for _ in range(10):
        s = fly(ac, hold, 0.2)
        rolls.append(s.roll)
    assert math.hypot(s.velocity_enu[0], s.velocity_enu[1]) < 0.3
    assert max(rolls) - min(rolls) < math.radians(0.5)  # steady attitude
    assert rolls[-1] < -math.radians(3.0)  # leans left into the wind
    assert abs(s.heading - 0.0) < 0.05 or abs(s.heading - 2 * math.pi) < 0.05


def test_payload_pick_up_in_hover() -> None:
    ac = hover_aircraft(0.0)
    hold = VelocityHold()
    before = ac.truth()
    ac.model.set_payload(20.0)
    s = fly(ac, hold, 15.0)
    assert s.mass == pytest.approx(before.mass + 20.0, abs=0.05)
    assert not s.on_ground
    assert abs(s.position_enu[2] - before.position_enu[2]) < 3.0  # sags, then holds
    assert abs(s.velocity_enu[2]) < 0.1
    assert ac.model.main_thrust == pytest.approx(s.mass * G, rel=0.03)


@pytest.mark.parametrize("ccw", [True, False])
def test_either_rotor_sense_hovers_and_holds_heading(ccw: bool) -> None:
    ac = Aircraft(RmaxParams(main_rotor_ccw=ccw), placement=InitialPlacement(heading=1.0))
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(10.0)
    hold = VelocityHold()
    fly(ac, hold, 6.0, climb_rate=1.0, heading=1.0)
    s = fly(ac, hold, 6.0, heading=1.0)
    assert not s.on_ground and s.height_above_ground > 2.0
    assert s.heading == pytest.approx(1.0, abs=0.03)
    # the tail rotor pushes the same way as the torque reaction would turn the nose: the YACS
    # trims roll towards the opposite side to hold position
    assert math.copysign(1.0, s.roll) == (-1.0 if ccw else 1.0)
