"""Random problem generators for the shipped domains (deterministic for a given seed)."""

from __future__ import annotations

import itertools
import math
import random
from dataclasses import dataclass
from pathlib import Path

DOMAINS_DIR = Path(__file__).parent / "domains"
LOGISTICS_DOMAIN = DOMAINS_DIR / "logistics" / "domain.pddl"
LOGISTICS_CONTROL = DOMAINS_DIR / "logistics" / "control.tal"
UAV_DOMAIN = DOMAINS_DIR / "uav_logistics" / "domain.tal"
UAV_CONTROL = DOMAINS_DIR / "uav_logistics" / "control.tal"
UAV_SCENARIO = DOMAINS_DIR / "uav_logistics" / "scenario.tal"
ZENOTRAVEL_DOMAIN = DOMAINS_DIR / "zenotravel" / "domain.pddl"
ZENOTRAVEL_CONTROL = DOMAINS_DIR / "zenotravel" / "control.tal"
BLOCKS_DOMAIN = DOMAINS_DIR / "blocks" / "domain.pddl"
BLOCKS_CONTROL = DOMAINS_DIR / "blocks" / "control.tal"
DEPOTS_DOMAIN = DOMAINS_DIR / "depots" / "domain.pddl"
DEPOTS_CONTROL = DOMAINS_DIR / "depots" / "control.tal"
SATELLITE_DOMAIN = DOMAINS_DIR / "satellite" / "domain.pddl"
SATELLITE_CONTROL = DOMAINS_DIR / "satellite" / "control.tal"
SATELLITE_MODES = ("image", "spectrograph", "thermograph", "infrared")
DRIVERLOG_DOMAIN = DOMAINS_DIR / "driverlog" / "domain.pddl"
DRIVERLOG_CONTROL = DOMAINS_DIR / "driverlog" / "control.tal"
DRIVERLOG_NUMERIC_DOMAIN = DOMAINS_DIR / "driverlog_numeric" / "domain.pddl"
ZENOTRAVEL_NUMERIC_DOMAIN = DOMAINS_DIR / "zenotravel_numeric" / "domain.pddl"
ZENOTRAVEL_NUMERIC_CONTROL = DOMAINS_DIR / "zenotravel_numeric" / "control.tal"
ROVERS_DOMAIN = DOMAINS_DIR / "rovers" / "domain.pddl"
ROVERS_CONTROL = DOMAINS_DIR / "rovers" / "control.tal"
ZENO_FUEL_LEVELS = 7  # f0 .. f6 as in the IPC-2002 STRIPS problems


@dataclass(frozen=True)
class LogisticsSize:
    """Size of a generated Logistics problem (IPC-2000 style: one truck per city)."""

    packages: int
    cities: int
    airplanes: int
    locations_per_city: int = 2


def logistics_problem(size: LogisticsSize, seed: int, name: str = "") -> str:
    """A PDDL problem with IPC-2000 naming (apn, apt, pos, cit, tru, obj).

    Every city has one airport and ``locations_per_city - 1`` other locations and a truck;
    airplanes start at random airports; packages start and end at random places.
    """
    if size.packages < 1 or size.cities < 1 or size.airplanes < 1 or size.locations_per_city < 1:
        raise ValueError("sizes must be positive")
    rng = random.Random(seed)
    cities = [f"cit{i + 1}" for i in range(size.cities)]
    airports = [f"apt{i + 1}" for i in range(size.cities)]
    others = [
        [f"pos{c + 1}-{j + 1}" for j in range(size.locations_per_city - 1)]
        for c in range(size.cities)
    ]
    places = [[airports[c], *others[c]] for c in range(size.cities)]
    all_places = [p for ps in places for p in ps]
    trucks = [f"tru{i + 1}" for i in range(size.cities)]
    planes = [f"apn{i + 1}" for i in range(size.airplanes)]
    packages = [f"obj{i + 1}" for i in range(size.packages)]
    init = [f"(in-city {p} {cities[c]})" for c in range(size.cities) for p in places[c]]
    init += [f"(at {t} {rng.choice(places[c])})" for c, t in enumerate(trucks)]
    init += [f"(at {a} {rng.choice(airports)})" for a in planes]
    goals = []
    for pkg in packages:
        init.append(f"(at {pkg} {rng.choice(all_places)})")
        goals.append(f"(at {pkg} {rng.choice(all_places)})")
    objects = [
        " ".join(planes) + " - airplane",
        " ".join(airports) + " - airport",
        " ".join(p for ps in others for p in ps) + " - location" if any(others) else "",
        " ".join(cities) + " - city",
        " ".join(trucks) + " - truck",
        " ".join(packages) + " - package",
    ]
    pname = name or f"logistics-{size.packages}-{size.cities}-{size.airplanes}-{seed}"
    return _pddl_problem(pname, "logistics", objects, init, goals)


@dataclass(frozen=True)
class UavSize:
    """Size of a generated UAV logistics scenario (§11.1.2)."""

    helicopters: int
    bodies: int
    boxes: int
    carriers: int = 1
    supply_depots: int = 1
    carrier_depots: int = 1
    area: float = 400.0


def uav_problem(size: UavSize, seed: int, name: str = "") -> str:
    """A TAL-language problem for the UAV logistics domain.

    Body locations are scattered over a square area (as from a saliency map); boxes of food
    and medicine start at supply depots, carriers at carrier depots; each body needs the
    boxes assigned to it.
    """
    rng = random.Random(seed)

    def spot() -> tuple[float, float, float]:
        return (round(rng.uniform(0, size.area), 1), round(rng.uniform(0, size.area), 1), 0.0)

    lines = [
        f"problem {name or f'uav-{size.helicopters}-{size.bodies}-{size.boxes}-{seed}'} "
        "for uav-logistics"
    ]
    depots = [f"supply{i + 1}" for i in range(size.supply_depots)]
    cdepots = [f"carrierdepot{i + 1}" for i in range(size.carrier_depots)]
    bodies = [f"body{i + 1}" for i in range(size.bodies)]
    for group, tname in ((depots, "supply-depot"), (cdepots, "carrier-depot"), (bodies, "body")):
        for obj in group:
            x, y, z = spot()
            lines.append(f"object {obj}: {tname} @ ({x}, {y}, {z})")
    helis = [f"heli{i + 1}" for i in range(size.helicopters)]
    lines.append(f"object {', '.join(helis)}: helicopter")
    boxes = []
    for i in range(size.boxes):
        kind = "food-box" if i % 2 == 0 else "medicine-box"
        boxes.append(f"box{i + 1}")
        lines.append(f"object box{i + 1}: {kind}")
    carriers = [f"carrier{i + 1}" for i in range(size.carriers)]
    if carriers:
        lines.append(f"object {', '.join(carriers)}: carrier")
    for h in helis:
        base = rng.choice(depots)
        lines.append(
            f"init at({h}, {base}), free({h}), hovering({h}), "
            f"lift-capacity({h}) = 30, fuel({h}) = 5000"
        )
    for b in boxes:
        lines.append(f"init at({b}, {rng.choice(depots)}), weight({b}) = {rng.choice((4, 6, 8))}")
    for c in carriers:
        lines.append(f"init at({c}, {rng.choice(cdepots)}), load({c}) = 5, slots({c}) = 4")
    for i, b in enumerate(boxes):
        lines.append(f"goal at({b}, {bodies[i % len(bodies)]})")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class ZenoSize:
    """Parameters of the IPC-2002 ZenoTravel generator: cities, aircraft, people."""

    cities: int
    planes: int
    people: int


def _pddl_problem(
    name: str,
    domain: str,
    objects: list[str],
    init: list[str],
    goals: list[str],
    metric: str = "",
) -> str:
    body = "\n    ".join(o for o in objects if o)
    lines = "\n    ".join(init)
    goal_lines = "\n           ".join(goals)
    metric_line = f"\n  (:metric {metric})" if metric else ""
    return (
        f"(define (problem {name})\n  (:domain {domain})\n  (:objects\n    {body})\n"
        f"  (:init\n    {lines})\n  (:goal (and {goal_lines})){metric_line})\n"
    )


def zenotravel_problem(size: ZenoSize, seed: int, name: str = "", numeric: bool = False) -> str:
    """A ZenoTravel problem as the IPC-2002 generator lays it out (STRIPS, or ``numeric``).

    Aircraft start in random cities with a random fuel level, people in random cities; every
    person has a random goal city and every second aircraft one too. The numeric version
    (our reading of the competition's numeric problems) gives symmetric distances of 100-1000
    between cities (0 to itself), and per aircraft a slow burn of 1-5, a fast burn of 2-4
    times that, a zoom limit of 6-10, a capacity of 1500-3100 slow-burn units (enough for
    any slow flight) and a random fuel load up to the capacity; the metric is the fuel used.
    """
    if size.cities < 2 or size.planes < 1 or size.people < 1:
        raise ValueError("need at least two cities, one aircraft and one person")
    rng = random.Random(seed)
    cities = [f"city{i}" for i in range(size.cities)]
    planes = [f"plane{i + 1}" for i in range(size.planes)]
    people = [f"person{i + 1}" for i in range(size.people)]
    levels = [] if numeric else [f"fl{i}" for i in range(ZENO_FUEL_LEVELS)]
    init = [f"(next {levels[i]} {levels[i + 1]})" for i in range(len(levels) - 1)]
    goals = []
    for i, plane in enumerate(planes):
        init.append(f"(at {plane} {rng.choice(cities)})")
        if numeric:
            slow = rng.randint(1, 5)
            capacity = slow * rng.randint(1500, 3100)
            init += [
                f"(= (slow-burn {plane}) {slow})",
                f"(= (fast-burn {plane}) {slow * rng.randint(2, 4)})",
                f"(= (zoom-limit {plane}) {rng.randint(6, 10)})",
                f"(= (capacity {plane}) {capacity})",
                f"(= (fuel {plane}) {rng.randint(0, capacity)})",
                f"(= (onboard {plane}) 0)",
            ]
        else:
            init.append(f"(fuel-level {plane} {rng.choice(levels)})")
        if i % 2 == 1:
            goals.append(f"(at {plane} {rng.choice(cities)})")
    for person in people:
        init.append(f"(at {person} {rng.choice(cities)})")
        goals.insert(0, f"(at {person} {rng.choice(cities)})")
    objects = [
        " ".join(planes) + " - aircraft",
        " ".join(people) + " - person",
        " ".join(cities) + " - city",
        " ".join(levels) + " - flevel" if levels else "",
    ]
    metric = ""
    if numeric:
        init.append("(= (total-fuel-used) 0)")
        for a, b in itertools.combinations_with_replacement(cities, 2):
            far = 0 if a == b else rng.randint(100, 1000)
            init.append(f"(= (distance {a} {b}) {far})")
            if a != b:
                init.append(f"(= (distance {b} {a}) {far})")
        metric = "minimize (total-fuel-used)"
    pname = name or f"zeno-{size.cities}-{size.planes}-{size.people}-{seed}"
    return _pddl_problem(pname, "zenotravel", objects, init, goals, metric)


def _random_towers(blocks: list[str], rng: random.Random) -> list[list[str]]:
    """A random state: blocks shuffled and cut into towers (bottom first)."""
    order = blocks[:]
    rng.shuffle(order)
    towers: list[list[str]] = []
    for block in order:
        if towers and rng.random() < 0.7:
            rng.choice(towers).append(block)
        else:
            towers.append([block])
    return towers


def blocks_problem(blocks: int, seed: int, name: str = "") -> str:
    """A four-operator Blocks problem: random initial and goal towers (AIPS-2000 layout).

    As in the competition's problems, the goal lists only the ``on`` relations.
    """
    if blocks < 2:
        raise ValueError("need at least two blocks")
    rng = random.Random(seed)
    names = [f"b{i + 1}" for i in range(blocks)]
    init = ["(arm-empty)"]
    for tower in _random_towers(names, rng):
        init.append(f"(on-table {tower[0]})")
        init.extend(f"(on {upper} {lower})" for lower, upper in itertools.pairwise(tower))
        init.append(f"(clear {tower[-1]})")
    goals = [
        f"(on {upper} {lower})"
        for tower in _random_towers(names, rng)
        for lower, upper in itertools.pairwise(tower)
    ]
    pname = name or f"blocks-{blocks}-{seed}"
    return _pddl_problem(pname, "blocks", [" ".join(names)], init, goals)


@dataclass(frozen=True)
class DepotsSize:
    """Parameters of the IPC-2002 Depots generator (``-e -i -t -p -h -c``)."""

    depots: int
    distributors: int
    trucks: int
    pallets: int
    hoists: int
    crates: int


def depots_problem(size: DepotsSize, seed: int, name: str = "") -> str:
    """A STRIPS Depots problem as the IPC-2002 generator lays it out.

    Places are the depots then the distributors; place ``i`` gets pallet ``i`` and hoist
    ``i``, further pallets and hoists go to random places, trucks start at random places.
    Crates are stacked on random pallets; the goal stacks a random subset of the crates (each
    with probability 2/3) into towers on random pallets.
    """
    places_n = size.depots + size.distributors
    if size.depots < 1 or size.trucks < 1 or size.crates < 1:
        raise ValueError("need at least one depot, one truck and one crate")
    if size.pallets < places_n or size.hoists < places_n:
        raise ValueError("need at least one pallet and one hoist per place")
    rng = random.Random(seed)
    depots = [f"depot{i}" for i in range(size.depots)]
    distributors = [f"distributor{i}" for i in range(size.distributors)]
    places = depots + distributors
    pallets = [f"pallet{i}" for i in range(size.pallets)]
    hoists = [f"hoist{i}" for i in range(size.hoists)]
    trucks = [f"truck{i}" for i in range(size.trucks)]
    crates = [f"crate{i}" for i in range(size.crates)]
    pallet_at = {
        p: places[i] if i < places_n else rng.choice(places) for i, p in enumerate(pallets)
    }
    top = {p: p for p in pallets}
    init = []
    for pallet in pallets:
        init.append(f"(at {pallet} {pallet_at[pallet]})")
    init += [f"(at {t} {rng.choice(places)})" for t in trucks]
    for i, hoist in enumerate(hoists):
        place = places[i] if i < places_n else rng.choice(places)
        init += [f"(at {hoist} {place})", f"(available {hoist})"]
    for crate in crates:
        pallet = rng.choice(pallets)
        init += [f"(at {crate} {pallet_at[pallet]})", f"(on {crate} {top[pallet]})"]
        top[pallet] = crate
    init += [f"(clear {surface})" for surface in top.values()]
    goal_top = {p: p for p in pallets}
    goals = []
    for crate in rng.sample(crates, len(crates)):
        if rng.random() < 2 / 3:
            pallet = rng.choice(pallets)
            goals.append(f"(on {crate} {goal_top[pallet]})")
            goal_top[pallet] = crate
    if not goals:
        goals.append(f"(on {crates[0]} {rng.choice(pallets)})")
    objects = [
        " ".join(depots) + " - depot",
        " ".join(distributors) + " - distributor" if distributors else "",
        " ".join(trucks) + " - truck",
        " ".join(pallets) + " - pallet",
        " ".join(crates) + " - crate",
        " ".join(hoists) + " - hoist",
    ]
    pname = name or (
        f"depots-{size.depots}-{size.distributors}-{size.trucks}-{size.pallets}-"
        f"{size.hoists}-{size.crates}-{seed}"
    )
    return _pddl_problem(pname, "depot", objects, init, goals)


@dataclass(frozen=True)
class SatelliteSize:
    """Parameters of the IPC-2002 Satellite generator.

    Satellites, maximum instruments per satellite, modes, targets and observations.
    """

    satellites: int
    instruments: int
    modes: int
    targets: int
    observations: int


def satellite_problem(size: SatelliteSize, seed: int, name: str = "") -> str:
    """A STRIPS Satellite problem as the IPC-2002 generator lays it out.

    Calibration directions (``Star0``, ``GroundStation1``, ...) come first, then the targets
    (``Planet``/``Phenomenon``/``Star``); each satellite carries 1..``instruments``
    instruments, each supporting 1-3 modes and calibrated on a random calibration
    direction; satellites point at random directions with power available. Goals: distinct
    (target, mode) images of modes some instrument supports, and a final pointing direction
    for every second satellite.
    """
    if min(size.satellites, size.instruments, size.modes, size.targets) < 1:
        raise ValueError("need at least one satellite, instrument, mode and target")
    rng = random.Random(seed)
    n_calib = max(2, size.satellites)
    calib = [f"{('Star', 'GroundStation')[i % 2]}{i}" for i in range(n_calib)]
    kinds = ("Planet", "Phenomenon", "Star")
    targets = [f"{kinds[i % 3]}{n_calib + i}" for i in range(size.targets)]
    modes = [f"{SATELLITE_MODES[i % 4]}{i}" for i in range(size.modes)]
    satellites = [f"satellite{i}" for i in range(size.satellites)]
    init: list[str] = []
    instruments: list[str] = []
    supported: set[str] = set()
    for sat in satellites:
        for _ in range(rng.randint(1, size.instruments)):
            inst = f"instrument{len(instruments)}"
            instruments.append(inst)
            for mode in rng.sample(modes, rng.randint(1, min(3, len(modes)))):
                init.append(f"(supports {inst} {mode})")
                supported.add(mode)
            init.append(f"(calibration_target {inst} {rng.choice(calib)})")
            init.append(f"(on_board {inst} {sat})")
        init += [f"(power_avail {sat})", f"(pointing {sat} {rng.choice(calib + targets)})"]
    pairs = [(t, m) for t in targets for m in sorted(supported)]
    chosen = rng.sample(pairs, min(size.observations, len(pairs)))
    goals = [f"(have_image {t} {m})" for t, m in chosen]
    goals = [f"(pointing {sat} {rng.choice(targets)})" for sat in satellites[1::2]] + goals
    objects = [
        " ".join(satellites) + " - satellite",
        " ".join(instruments) + " - instrument",
        " ".join(modes) + " - mode",
        " ".join(calib + targets) + " - direction",
    ]
    pname = name or (
        f"satellite-{size.satellites}-{size.instruments}-{size.modes}-{size.targets}-"
        f"{size.observations}-{seed}"
    )
    return _pddl_problem(pname, "satellite", objects, init, goals)


def _random_map(nodes: list[str], extra: int, rng: random.Random) -> list[tuple[str, str]]:
    """Undirected edges of a random connected map: a random spanning tree plus ``extra``."""
    edges = [(nodes[rng.randrange(i)], node) for i, node in enumerate(nodes) if i]
    others = [(a, b) for i, a in enumerate(nodes) for b in nodes[i + 1 :]]
    chosen = set(edges) | {(b, a) for a, b in edges}
    spare = [e for e in others if e not in chosen]
    return edges + rng.sample(spare, min(extra, len(spare)))


@dataclass(frozen=True)
class DriverLogSize:
    """Parameters of the IPC-2002 DriverLog generator: junctions, drivers, packages, trucks."""

    junctions: int
    drivers: int
    packages: int
    trucks: int


def driverlog_problem(size: DriverLogSize, seed: int, name: str = "", numeric: bool = False) -> str:
    """A DriverLog problem as the IPC-2002 generator lays it out (STRIPS, or ``numeric``).

    Junctions ``s0..`` are joined by two-way road links (a random connected map with about
    half as many extra links as junctions); footpaths run along the spanning tree's links
    through path points ``p<i>-<j>``. Drivers, empty trucks and packages start at random
    junctions; every package, and each driver and truck with probability 1/2, gets a random
    goal junction. The numeric version adds random driving (1-100) and walking (5-50) times
    per two-way road link and footpath and minimises their sums ``(driven)`` + ``(walked)``.
    """
    if min(size.junctions, size.drivers, size.packages, size.trucks) < 1:
        raise ValueError("need at least one junction, driver, package and truck")
    rng = random.Random(seed)
    junctions = [f"s{i}" for i in range(size.junctions)]
    roads = _random_map(junctions, size.junctions // 2, rng)
    tree = roads[: size.junctions - 1]
    points = [f"p{a[1:]}-{b[1:]}" for a, b in tree]
    drivers = [f"driver{i + 1}" for i in range(size.drivers)]
    trucks = [f"truck{i + 1}" for i in range(size.trucks)]
    packages = [f"package{i + 1}" for i in range(size.packages)]
    init = [f"(at {d} {rng.choice(junctions)})" for d in drivers]
    init += [f"(at {t} {rng.choice(junctions)})" for t in trucks]
    init += [f"(empty {t})" for t in trucks]
    init += [f"(at {p} {rng.choice(junctions)})" for p in packages]
    for a, b in roads:
        init += [f"(link {a} {b})", f"(link {b} {a})"]
    for (a, b), point in zip(tree, points, strict=True):
        init += [f"(path {a} {point})", f"(path {point} {a})"]
        init += [f"(path {b} {point})", f"(path {point} {b})"]
    goals = [f"(at {d} {rng.choice(junctions)})" for d in drivers if rng.random() < 0.5]
    goals += [f"(at {t} {rng.choice(junctions)})" for t in trucks if rng.random() < 0.5]
    goals += [f"(at {p} {rng.choice(junctions)})" for p in packages]
    objects = [
        " ".join(drivers) + " - driver",
        " ".join(trucks) + " - truck",
        " ".join(packages) + " - obj",
        " ".join(junctions + points) + " - location",
    ]
    metric = ""
    if numeric:
        init += ["(= (driven) 0)", "(= (walked) 0)"]
        for a, b in roads:
            cost = rng.randint(1, 100)
            init += [f"(= (time-to-drive {a} {b}) {cost})", f"(= (time-to-drive {b} {a}) {cost})"]
        for a, b in tree:
            for end in (a, b):
                point, cost = f"p{a[1:]}-{b[1:]}", rng.randint(5, 50)
                init.append(f"(= (time-to-walk {end} {point}) {cost})")
                init.append(f"(= (time-to-walk {point} {end}) {cost})")
        metric = "minimize (+ (driven) (walked))"
    pname = name or (
        f"driverlog-{size.junctions}-{size.drivers}-{size.packages}-{size.trucks}-{seed}"
    )
    return _pddl_problem(pname, "driverlog", objects, init, goals, metric)


@dataclass(frozen=True)
class RoversSize:
    """Parameters of the IPC-2002 Rovers generator.

    Rovers, waypoints, objectives, cameras and goals.
    """

    rovers: int
    waypoints: int
    objectives: int
    cameras: int
    goals: int


def rovers_problem(size: RoversSize, seed: int, name: str = "") -> str:
    """A STRIPS Rovers problem as the IPC-2002 generator lays it out.

    Waypoints see each other along a random connected map; each rover traverses a connected
    part of it (a spanning tree plus random visible links), has one store and is equipped
    for soil, rock and imaging analysis with probability 1/2 each (rovers 0, 1, 2 modulo the
    rover count are sure to have one kind each). Soil and rock samples lie at random
    waypoints, cameras sit on imaging rovers with 1-3 modes and a calibration objective,
    objectives are visible from random waypoints, the lander at a random waypoint. Goals:
    ``goals`` distinct data to communicate, drawn from the soil and rock samples and the
    (objective, mode) images some camera can take.
    """
    if min(size.rovers, size.waypoints, size.objectives, size.cameras, size.goals) < 1:
        raise ValueError("need at least one rover, waypoint, objective, camera and goal")
    if size.waypoints < 2:
        raise ValueError("need two waypoints (the lander's and one that sees it)")
    rng = random.Random(seed)
    waypoints = [f"waypoint{i}" for i in range(size.waypoints)]
    rovers = [f"rover{i}" for i in range(size.rovers)]
    objectives = [f"objective{i}" for i in range(size.objectives)]
    modes = ("colour", "high_res", "low_res")
    visible = _random_map(waypoints, size.waypoints, rng)
    tree = visible[: size.waypoints - 1]
    init = [f"(visible {a} {b})" for x, y in visible for a, b in ((x, y), (y, x))]
    init += ["(at_lander general " + rng.choice(waypoints) + ")", "(channel_free general)"]
    kinds = ("soil", "rock", "imaging")
    equipped: dict[str, set[str]] = {kind: set() for kind in kinds}
    for i, rover in enumerate(rovers):
        init += [f"(at {rover} {rng.choice(waypoints)})", f"(available {rover})"]
        init += [f"(store_of {rover}store {rover})", f"(empty {rover}store)"]
        for k, kind in enumerate(kinds):
            if i == k % size.rovers or rng.random() < 0.5:
                equipped[kind].add(rover)
                analysis = "imaging" if kind == "imaging" else f"{kind}_analysis"
                init.append(f"(equipped_for_{analysis} {rover})")
        roads = tree + [e for e in visible[len(tree) :] if rng.random() < 0.5]
        init += [f"(can_traverse {rover} {a} {b})" for x, y in roads for a, b in ((x, y), (y, x))]
    candidates: list[str] = []
    for kind in ("soil", "rock"):
        for w in waypoints:
            if rng.random() < 0.5:
                init.append(f"(at_{kind}_sample {w})")
                candidates.append(f"(communicated_{kind}_data {w})")
    imaging = sorted(equipped["imaging"])
    supported: set[str] = set()
    for c in range(size.cameras):
        camera = f"camera{c}"
        init.append(f"(on_board {camera} {rng.choice(imaging)})")
        init.append(f"(calibration_target {camera} {rng.choice(objectives)})")
        for mode in rng.sample(modes, rng.randint(1, 3)):
            init.append(f"(supports {camera} {mode})")
            supported.add(mode)
    for objective in objectives:
        for w in rng.sample(waypoints, rng.randint(1, max(1, size.waypoints // 4))):
            init.append(f"(visible_from {objective} {w})")
    candidates += [
        f"(communicated_image_data {o} {m})" for o in objectives for m in sorted(supported)
    ]
    goals = rng.sample(candidates, min(size.goals, len(candidates)))
    objects = [
        "general - lander",
        " ".join(modes) + " - mode",
        " ".join(rovers) + " - rover",
        " ".join(f"{r}store" for r in rovers) + " - store",
        " ".join(waypoints) + " - waypoint",
        " ".join(f"camera{c}" for c in range(size.cameras)) + " - camera",
        " ".join(objectives) + " - objective",
    ]
    pname = name or (
        f"rovers-{size.rovers}-{size.waypoints}-{size.objectives}-{size.cameras}-"
        f"{size.goals}-{seed}"
    )
    return _pddl_problem(pname, "rover", objects, init, goals)


def distance(a: tuple[float, float, float], b: tuple[float, float, float]) -> float:
    """Euclidean distance (m)."""
    return math.dist(a, b)
