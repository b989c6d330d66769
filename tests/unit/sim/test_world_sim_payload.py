"""The payload hook coupled into the flight model: cable pull, lift-off with and without load."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from sim.rc_transmitter import FlightModeSwitch
from sim.world import DynamicObject, ObjectKind
from sim.world_loader import load_world
from sim.world_sim import TICK_RATE_HZ, SimConfig, WorldSim
from sim.yacs import VerticalMode, YacsCommand

WORLD = load_world("revinge")
PAD = WORLD.pad("H1")


def _full_collective_with_carrier(mass: float) -> tuple[WorldSim, float, float]:
    """A carrier of ``mass`` kg gripped under the aircraft on its pad, then full collective.

    Returns the simulator and the highest carrier and aircraft heights above the ground.
    """
    carrier = DynamicObject(
        "heavy", ObjectKind.CARRIER, PAD.east, PAD.north, PAD.heading, (1.2, 0.8, 0.1),
        capacity=4, mass=mass,
    )  # fmt: skip
    sim = WorldSim(SimConfig(replace(WORLD, objects=(carrier,)), ("uav0",)))
    rc = sim.agents["uav0"].aircraft.rc
    rc.set_engine(True)
    rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    sim.hook_command("uav0", 0.0, magnet=True)  # the stowed hook rests on the lifting plate
    idle = YacsCommand(vertical=0.0, vertical_mode=VerticalMode.COLLECTIVE)
    for _ in range(6 * TICK_RATE_HZ):  # engine start and rotor run-up on the ground
        sim.command("uav0", idle)
        sim.advance()
    assert sim.carrying("uav0").object_id == "heavy"
    ground = WORLD.terrain.height(PAD.east, PAD.north)
    full = YacsCommand(vertical=1.0, vertical_mode=VerticalMode.COLLECTIVE)
    carrier_top = aircraft_top = 0.0
    for _ in range(8 * TICK_RATE_HZ):
        sim.command("uav0", full)
        sim.advance()
        carrier_top = max(carrier_top, sim.object_poses()["heavy"].up - ground)
        aircraft_top = max(aircraft_top, sim.truth("uav0").height_above_ground)
    return sim, carrier_top, aircraft_top


@pytest.mark.parametrize(("mass", "lifts"), [(8.0, True), (80.0, False)])
def test_an_overweight_carrier_keeps_the_helicopter_on_the_ground(mass: float, lifts: bool) -> None:
    sim, carrier_top, aircraft_top = _full_collective_with_carrier(mass)
    if lifts:
        assert carrier_top > 5.0 and aircraft_top > 5.0
    else:
        assert carrier_top < 0.05 and aircraft_top < 0.3
        # the cable carries what the rotor lifts beyond the aircraft's own weight
        assert 0.5 * mass * 9.81 < sim.carrying("uav0").tension < 1.05 * mass * 9.81


def test_the_cable_pull_reaches_the_flight_model() -> None:
    sim = WorldSim(SimConfig(WORLD, ("uav0",)))
    for _ in range(TICK_RATE_HZ):
        sim.advance()
    pull = sim.agents["uav0"].aircraft.model.hook_force
    assert math.hypot(*pull) == pytest.approx(sim.carrying("uav0").tension, rel=0.02)  # filtered
    assert pull[2] == pytest.approx(-sim.payload.params.hook_mass * 9.81, rel=0.05)
