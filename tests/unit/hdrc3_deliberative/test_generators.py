from __future__ import annotations

import re

import pytest

from hdrc3_deliberative.generators import (
    DepotsSize,
    DriverLogSize,
    LogisticsSize,
    RoversSize,
    SatelliteSize,
    UavSize,
    ZenoSize,
    blocks_problem,
    depots_problem,
    driverlog_problem,
    logistics_problem,
    rovers_problem,
    satellite_problem,
    uav_problem,
    zenotravel_problem,
)


def test_logistics_generator_is_deterministic_and_sized() -> None:
    size = LogisticsSize(42, 14, 4)
    text = logistics_problem(size, 7)
    assert text == logistics_problem(size, 7) != logistics_problem(size, 8)
    assert text.count("(at obj") == 2 * 42  # initial + goal
    assert "apt14 - airport" not in text or "apt14" in text
    assert text.count("(in-city") == 14 * 2


def test_uav_generator() -> None:
    text = uav_problem(UavSize(3, 4, 8, 2), 1)
    assert text.count("goal at(") == 8
    assert "object carrier1, carrier2: carrier" in text
    assert text == uav_problem(UavSize(3, 4, 8, 2), 1)


def test_generator_rejects_empty_sizes() -> None:
    with pytest.raises(ValueError, match="positive"):
        logistics_problem(LogisticsSize(0, 1, 1), 1)


def test_zenotravel_generator_follows_the_ipc_layout() -> None:
    text = zenotravel_problem(ZenoSize(cities=5, planes=2, people=4), 3)
    assert (
        text == zenotravel_problem(ZenoSize(5, 2, 4), 3) != zenotravel_problem(ZenoSize(5, 2, 4), 4)
    )
    assert text.count("(next fl") == 6  # fuel levels fl0 .. fl6
    assert text.count("(fuel-level plane") == 2
    assert text.count("(at person") == 2 * 4  # initial + goal
    assert text.count("(at plane") == 2 + 1  # initial + the second aircraft's goal
    with pytest.raises(ValueError, match="two cities"):
        zenotravel_problem(ZenoSize(1, 1, 1), 1)


def test_numeric_zenotravel_generator() -> None:
    size = ZenoSize(cities=4, planes=3, people=5)
    text = zenotravel_problem(size, 3, numeric=True)
    assert text == zenotravel_problem(size, 3, numeric=True)
    assert "flevel" not in text and "(next " not in text
    assert text.count("(= (distance ") == 4 * 4 and "(= (distance city2 city2) 0)" in text
    for function in ("slow-burn", "fast-burn", "zoom-limit", "capacity", "fuel", "onboard"):
        assert text.count(f"(= ({function} plane") == 3
    assert "(= (total-fuel-used) 0)" in text and "(:metric minimize (total-fuel-used))" in text
    assert text.count("(at person") == 2 * 5 and text.count("(at plane") == 3 + 1


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_blocks_generator_makes_consistent_states(seed: int) -> None:
    text = blocks_problem(12, seed)
    init, goal = text.split("(:goal")
    on_table = init.count("(on-table ")
    on = init.count("(on ")
    assert on_table + on == 12  # every block lies on the table or on one other block
    assert init.count("(clear ") == on_table  # one clear block per tower
    assert "(on-table" not in goal and goal.count("(on ") <= 11


@pytest.mark.parametrize(
    ("size", "seed"),
    [(DepotsSize(1, 2, 2, 3, 3, 6), 1), (DepotsSize(3, 2, 4, 9, 7, 20), 2)],
)
def test_depots_generator_follows_the_ipc_layout(size: DepotsSize, seed: int) -> None:
    text = depots_problem(size, seed)
    assert text == depots_problem(size, seed)
    init, goal = text.split("(:goal")
    places = size.depots + size.distributors
    for i in range(places):  # place i has pallet i and hoist i
        place = f"depot{i}" if i < size.depots else f"distributor{i - size.depots}"
        assert f"(at pallet{i} {place})" in init and f"(at hoist{i} {place})" in init
    assert init.count("(available hoist") == size.hoists
    assert init.count("(at truck") == size.trucks
    assert init.count("(on crate") == size.crates  # every crate lies on one surface
    assert init.count("(clear ") == size.pallets  # one clear top per pallet stack
    goal_surfaces = [line.split()[1].rstrip(")") for line in goal.split("(on ")[1:]]
    assert len(goal_surfaces) == len(set(goal_surfaces))  # goal towers: one crate per surface


def test_depots_generator_rejects_places_without_pallet_or_hoist() -> None:
    with pytest.raises(ValueError, match="one pallet and one hoist per place"):
        depots_problem(DepotsSize(2, 2, 1, 3, 4, 5), 1)


@pytest.mark.parametrize(
    ("size", "seed"), [(SatelliteSize(1, 1, 3, 3, 3), 1), (SatelliteSize(4, 3, 5, 12, 20), 2)]
)
def test_satellite_generator_follows_the_ipc_layout(size: SatelliteSize, seed: int) -> None:
    text = satellite_problem(size, seed)
    assert text == satellite_problem(size, seed)
    init, goal = text.split("(:goal")
    on_board = init.count("(on_board ")
    assert size.satellites <= on_board <= size.satellites * size.instruments
    assert init.count("(calibration_target ") == on_board  # one target per instrument
    assert init.count("(power_avail ") == init.count("(pointing ") == size.satellites
    images = re.findall(r"\(have_image ([^\s()]+) ([^\s()]+)\)", goal)
    assert len(images) == len(set(images)) == size.observations
    supported = set(re.findall(r"\(supports \S+ ([^\s()]+)\)", init))
    assert {mode for _, mode in images} <= supported  # every goal image can be taken
    assert goal.count("(pointing ") == size.satellites // 2


def test_satellite_generator_rejects_empty_sizes() -> None:
    with pytest.raises(ValueError, match="at least one satellite"):
        satellite_problem(SatelliteSize(0, 1, 1, 1, 1), 1)


def _reachable(edges: list[tuple[str, str]], start: str) -> set[str]:
    seen, todo = {start}, [start]
    while todo:
        node = todo.pop()
        for a, b in edges:
            if a == node and b not in seen:
                seen.add(b)
                todo.append(b)
    return seen


@pytest.mark.parametrize(
    ("size", "seed"), [(DriverLogSize(3, 1, 2, 1), 1), (DriverLogSize(12, 4, 10, 3), 2)]
)
def test_driverlog_generator_follows_the_ipc_layout(size: DriverLogSize, seed: int) -> None:
    text = driverlog_problem(size, seed)
    assert text == driverlog_problem(size, seed)
    init, goal = text.split("(:goal")
    links = re.findall(r"\(link (\S+) ([^\s()]+)\)", init)
    paths = re.findall(r"\(path (\S+) ([^\s()]+)\)", init)
    junctions = {f"s{i}" for i in range(size.junctions)}
    assert {a for a, _ in links} <= junctions
    assert all((b, a) in links for a, b in links)  # two-way roads
    assert junctions <= _reachable(links, "s0")  # roads connect every junction
    assert junctions <= _reachable(paths, "s0")  # and so do footpaths
    assert init.count("(empty ") == size.trucks
    assert len(re.findall(r"\(at package", goal)) == size.packages
    assert len(re.findall(r"\(at (driver|truck)", goal)) <= size.drivers + size.trucks


def test_driverlog_generator_rejects_empty_sizes() -> None:
    with pytest.raises(ValueError, match="at least one junction"):
        driverlog_problem(DriverLogSize(3, 0, 1, 1), 1)


@pytest.mark.parametrize(
    ("size", "seed"), [(RoversSize(1, 4, 2, 1, 3), 1), (RoversSize(4, 20, 6, 5, 15), 2)]
)
def test_rovers_generator_follows_the_ipc_layout(size: RoversSize, seed: int) -> None:
    text = rovers_problem(size, seed)
    assert text == rovers_problem(size, seed)
    init, goal = text.split("(:goal")
    visible = set(re.findall(r"\(visible (\S+) ([^\s()]+)\)", init))
    waypoints = {f"waypoint{i}" for i in range(size.waypoints)}
    for r in range(size.rovers):
        edges = re.findall(rf"\(can_traverse rover{r} (\S+) ([^\s()]+)\)", init)
        assert set(edges) <= visible  # rovers traverse only visible links
        assert waypoints <= _reachable(edges, "waypoint0")  # each rover reaches everything
    for kind in ("soil_analysis", "rock_analysis", "imaging"):
        assert f"(equipped_for_{kind} " in init
    assert init.count("(on_board ") == size.cameras
    goals = re.findall(r"\(communicated_\w+ [^()]+\)", goal)
    assert len(goals) == len(set(goals)) <= size.goals
    for w in re.findall(r"\(communicated_soil_data ([^\s()]+)\)", goal):
        assert f"(at_soil_sample {w})" in init  # every wanted sample exists


def test_rovers_generator_rejects_a_single_waypoint() -> None:
    with pytest.raises(ValueError, match="two waypoints"):
        rovers_problem(RoversSize(1, 1, 1, 1, 1), 1)
