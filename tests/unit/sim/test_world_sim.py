from collections import Counter
from dataclasses import replace
from math import pi

import pytest

from hdrc3_base.errors import ConfigError
from sim.rc_transmitter import FlightModeSwitch
from sim.wind import WindSettings
from sim.world_loader import load_world
from sim.world_sim import TICK_NS, SimConfig, WorldSim, start_pads
from sim.yacs import YacsCommand

WORLD = load_world("revinge")


def _sim(agents: tuple[str, ...] = ("uav0", "uav1"), **changes: object) -> WorldSim:
    return WorldSim(replace(SimConfig(WORLD, agents), **changes))  # type: ignore[arg-type]


def _fly(sim: WorldSim, ticks: int) -> list[tuple[float, ...]]:
    """Engine on, autonomous, climb: return uav0's position and attitude per tick."""
    rc = sim.agents["uav0"].aircraft.rc
    rc.set_engine(True)
    rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    out = []
    for k in range(ticks):
        sim.command("uav0", YacsCommand(roll=0.01 * (k % 7), vertical=1.0))
        sim.advance()
        t = sim.truth("uav0")
        out.append((*t.position_enu, t.roll, t.pitch, t.heading, t.rotor_rpm))
    return out


def test_agents_start_on_the_pads_in_order() -> None:
    sim = _sim()
    assert sim.time_ns == 0
    for _ in range(25):  # placed 5 mm above the pad: let the skids settle
        sim.advance()
    for agent, pad in zip(("uav0", "uav1"), ("H1", "H2"), strict=True):
        truth = sim.truth(agent)
        p = WORLD.pad(pad)
        assert truth.position_enu[:2] == pytest.approx((p.east, p.north), abs=0.01)
        assert truth.on_ground and not truth.engine_running


@pytest.mark.parametrize(
    ("agents", "message"),
    [((), "at least one agent"), (("a", "a"), "listed twice")],
)
def test_bad_agent_lists(agents: tuple[str, ...], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        start_pads(WORLD, agents)


def test_extra_agents_start_beside_the_pads() -> None:
    pads = start_pads(WORLD, ("a", "b", "c", "d", "e"))
    h1, h2 = WORLD.pad("H1"), WORLD.pad("H2")
    assert [p.name for p in pads] == ["H1", "H2", "H1+1", "H2+1", "H1+2"]
    assert (pads[2].east, pads[2].north) == (h1.east + 10.0, h1.north)
    assert (pads[4].east, pads[4].north) == (h1.east + 20.0, h1.north)
    assert (pads[3].east, pads[3].north) == (h2.east + 10.0, h2.north)


def test_the_vision_landing_pad_is_no_start_pad() -> None:
    assert WORLD.pad("L1").pattern and "L1" not in {
        p.name for p in start_pads(WORLD, ("a", "b", "c"))
    }
    only_vision = replace(WORLD, pads=(WORLD.pad("L1"),))
    with pytest.raises(ConfigError, match="has no start pads"):
        start_pads(only_vision, ("a",))


def test_no_spot_beside_the_pads_is_a_clear_error() -> None:
    # H1+3 would be 30 m east of H1, which is where H2 is
    with pytest.raises(ConfigError, match="agent a6: 30 m east of pad H1 is too close to H2"):
        start_pads(WORLD, tuple(f"a{i}" for i in range(7)))


def test_a_tick_is_four_fdm_steps_with_sensors_at_their_rates() -> None:
    sim = _sim(("uav0",))
    counts: Counter[str] = Counter()
    assert len(sim.take_readings()["uav0"]) == 1  # every sensor's first sample at t = 0
    for _ in range(50):  # one sim second
        sim.advance()
        for readings in sim.take_readings()["uav0"]:
            for field in readings.__slots__:
                if field != "time" and getattr(readings, field) is not None:
                    counts[field] += 1
    assert sim.time_ns == 50 * TICK_NS
    assert sim.truth("uav0").time == pytest.approx(1.0)
    assert counts == {
        "imu": 200,
        "attitude": 50,
        "ground_contact": 50,
        "barometer": 25,
        "rpm": 25,
        "ptu": 25,
        "color_camera": 25,
        "thermal_camera": 25,
        "gps": 10,
        "power": 5,
        "radiation": 1,
    }  # the laser is switched off at start


def test_same_seed_and_commands_give_bit_identical_trajectories() -> None:
    gusty = WindSettings((4.0, 1.0, 0.0), 1.5)
    a = _fly(_sim(seed=5, wind=gusty), 700)
    b = _fly(_sim(seed=5, wind=gusty), 700)
    c = _fly(_sim(seed=6, wind=gusty), 700)
    assert a == b
    assert a[-1][2] > a[0][2] + 1.0  # it did climb
    assert a != c  # other gusts


def test_full_reset_replays_the_run_from_time_zero() -> None:
    sim = _sim(seed=2, wind=WindSettings((0.0, 3.0, 0.0), 1.0))
    first = _fly(sim, 600)
    sim.reset()
    assert sim.time_ns == 0
    assert sim.agents["uav0"].aircraft.rc.state.mode is FlightModeSwitch.MANUAL
    assert _fly(sim, 600) == first


def test_agent_reset_and_teleport_keep_the_world_clock() -> None:
    sim = _sim()
    _fly(sim, 600)
    spinning = sim.truth("uav0").rotor_rpm
    assert spinning > 800.0
    sim.place("uav0", 10.0, 20.0, 5.0, 1.0)
    truth = sim.truth("uav0")
    assert truth.time == pytest.approx(sim.time)
    assert truth.position_enu[:2] == pytest.approx((10.0, 20.0), abs=0.01)
    assert truth.height_above_ground == pytest.approx(5.0, abs=0.05)
    assert truth.rotor_rpm == pytest.approx(spinning)
    sim.reset("uav0")
    after = sim.truth("uav0")
    assert after.time == pytest.approx(sim.time) and not after.engine_running
    assert after.position_enu[:2] == pytest.approx(
        (WORLD.pad("H1").east, WORLD.pad("H1").north), abs=0.01
    )


def test_a_driving_car_moves_with_sim_time_and_a_reset_brings_it_back() -> None:
    world = load_world("revinge_chase")
    sim = WorldSim(SimConfig(world, ("uav0",)))
    start = sim.object_poses()["chase1"]
    assert (start.east, start.north, start.heading, start.speed) == (100.0, -100.0, pi / 2, 0.0)
    assert "car1" not in sim.object_poses()  # a parked car stays where the world file has it
    for _ in range(50):  # 1 s at 2 m/s^2 from rest
        sim.advance()
    pose = sim.object_poses()["chase1"]
    assert (pose.east, pose.north, pose.speed) == pytest.approx((101.0, -100.0, 2.0))
    assert pose.up == pytest.approx(world.terrain.height(101.0, -100.0)) and pose.held_by == ""
    assert sim.objects["chase1"] == world.objects[-1]  # the object keeps its start pose
    sim.reset()
    assert sim.object_poses()["chase1"] == start
