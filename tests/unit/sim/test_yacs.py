import math

import pytest

from hdrc3_base.errors import ConfigError
from sim.aircraft import Aircraft
from sim.rc_transmitter import FlightModeSwitch, RcState, RcSticks
from sim.rmax_params import RmaxParams
from sim.velocity_hold import VelocityHold, fly
from sim.yacs import CommandSource, VerticalMode, Yacs, YacsCommand, YacsInput

LEVEL = YacsInput(roll=0.0, pitch=0.0, p=0.0, q=0.0, r=0.0, climb_rate=0.0, on_ground=False)


def rc(mode: FlightModeSwitch, link: bool = True, sticks: RcSticks | None = None) -> RcState:
    return RcState(link_ok=link, mode=mode, engine_on=True, sticks=sticks or RcSticks())


@pytest.mark.parametrize(
    "kwargs",
    [
        {"roll": math.nan},
        {"yaw_rate": math.inf},
        {"vertical": 1.5, "vertical_mode": VerticalMode.COLLECTIVE},
        {"vertical": -0.1, "vertical_mode": VerticalMode.COLLECTIVE},
    ],
)
def test_command_validation(kwargs: dict[str, object]) -> None:
    with pytest.raises(ConfigError):
        YacsCommand(**kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("state", "source"),
    [
        (rc(FlightModeSwitch.AUTONOMOUS), CommandSource.COMPUTER),
        (rc(FlightModeSwitch.AUTONOMOUS, link=False), CommandSource.COMPUTER),
        (rc(FlightModeSwitch.MANUAL), CommandSource.PILOT),
        (rc(FlightModeSwitch.MANUAL, link=False), CommandSource.FAILSAFE),
    ],
)
def test_command_source_follows_rc(state: RcState, source: CommandSource) -> None:
    yacs = Yacs(RmaxParams(), 0.005)
    yacs.step(state, LEVEL)
    assert yacs.source is source


@pytest.mark.parametrize(
    ("cmd", "field", "sign"),
    [
        (YacsCommand(roll=0.1), "lateral", 1),
        (YacsCommand(roll=-0.1), "lateral", -1),
        (YacsCommand(pitch=0.1), "longitudinal", -1),  # nose up = disc back
        (YacsCommand(pitch=-0.1), "longitudinal", 1),
        (YacsCommand(yaw_rate=0.3), "pedal", 1),
        (YacsCommand(vertical=0.7, vertical_mode=VerticalMode.COLLECTIVE), "collective", 1),
    ],
)
def test_servo_signs(cmd: YacsCommand, field: str, sign: int) -> None:
    yacs = Yacs(RmaxParams(), 0.005)
    yacs.command(cmd)
    servo = yacs.step(rc(FlightModeSwitch.AUTONOMOUS), LEVEL)
    assert math.copysign(1.0, getattr(servo, field)) == sign


def test_manual_sticks_map_to_attitude() -> None:
    yacs = Yacs(RmaxParams(), 0.005)
    servo = yacs.step(rc(FlightModeSwitch.MANUAL, sticks=RcSticks(roll=1.0, throttle=0.4)), LEVEL)
    assert servo.lateral > 0.0
    assert servo.collective == 0.4


def test_on_ground_without_climb_demand_idles_collective() -> None:
    yacs = Yacs(RmaxParams(), 0.005)
    grounded = YacsInput(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, on_ground=True)
    yacs.command(YacsCommand(vertical=-0.5))
    assert yacs.step(rc(FlightModeSwitch.AUTONOMOUS), grounded).collective == 0.0


def hovering() -> tuple[Aircraft, VelocityHold]:
    ac = Aircraft(payload=10.0)
    ac.rc.set_engine(True)
    ac.rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    ac.run(10.0)
    hold = VelocityHold()
    fly(ac, hold, 5.0, climb_rate=1.5)
    fly(ac, hold, 8.0)
    return ac, hold


def test_holds_level_attitude_in_hover() -> None:
    ac, _ = hovering()
    ac.command(YacsCommand())
    ac.run(3.0)  # settle from the trim attitude the velocity hold flew
    worst = 0.0
    for _ in range(400):
        ac.step()
        s = ac.truth()
        worst = max(worst, abs(s.roll), abs(s.pitch))
    assert worst < math.radians(0.5)


@pytest.mark.parametrize("axis", ["roll", "pitch"])
def test_attitude_step_response(axis: str) -> None:
    ac, _ = hovering()
    ac.command(YacsCommand())
    ac.run(2.0)
    target = math.radians(10.0)
    ac.command(YacsCommand(roll=target) if axis == "roll" else YacsCommand(pitch=target))
    trace: list[float] = []
    for _ in range(400):  # 2 s
        ac.step()
        trace.append(getattr(ac.truth(), axis))
    rise = next(i for i, v in enumerate(trace) if v > 0.9 * target) * ac.model.dt
    assert rise < 1.0
    assert max(trace) < 1.2 * target  # overshoot below 20 %
    assert trace[-1] == pytest.approx(target, abs=math.radians(1.0))
    assert rise > 0.1  # a physical rotor, not a teleport


def test_yaw_rate_tracking() -> None:
    ac, _ = hovering()
    ac.command(YacsCommand(yaw_rate=0.5))
    ac.run(3.0)
    assert ac.truth().body_rates[2] == pytest.approx(0.5, abs=0.05)


def test_lost_link_in_manual_descends_level() -> None:
    ac, _ = hovering()
    ac.rc.set_mode(FlightModeSwitch.MANUAL)
    ac.rc.set_link(False)
    ac.run(6.0)
    s = ac.truth()
    assert ac.status().source is CommandSource.FAILSAFE
    assert s.velocity_enu[2] == pytest.approx(-0.5, abs=0.1)
    assert abs(s.roll) < math.radians(3.0) and abs(s.pitch) < math.radians(3.0)


@pytest.mark.parametrize("wind_enu", [(10.0, 0.0, 0.0), (0.0, -10.0, 0.0), (-7.07, 7.07, 0.0)])
def test_holds_attitude_in_10_m_s_wind_without_outer_loop(
    wind_enu: tuple[float, float, float],
) -> None:
    ac, _ = hovering()
    ac.model.set_wind(wind_enu)
    ac.command(YacsCommand(roll=0.02, pitch=0.01))
    ac.run(2.0)
    for _ in range(400):
        ac.step()
        s = ac.truth()
        assert s.roll == pytest.approx(0.02, abs=math.radians(1.0))
        assert s.pitch == pytest.approx(0.01, abs=math.radians(1.0))
    downwind = (s.velocity_enu[0] * wind_enu[0] + s.velocity_enu[1] * wind_enu[1]) / 10.0
    assert downwind > 0.5  # no outer loop: it drifts with the air while holding attitude
