"""Seeded world variations: valid, reproducible, bodies in the open and apart."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import pytest
from shapely.geometry import Point, Polygon

from hdrc3_base.errors import ConfigError
from sim.world import ObjectKind
from sim.world_generator import CLEARANCE_M, SPACING_M, Population, generate_world
from sim.world_loader import load_world, parse_world

TINY = """
[world]
name = "tiny"
[origin]
latitude = 55.70
longitude = 13.47
altitude = 95.0
[terrain]
east0 = -100.0
north0 = -100.0
spacing = 100.0
heights = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]
"""
GENERATED = (ObjectKind.PERSON, ObjectKind.DUMMY, ObjectKind.ANIMAL, ObjectKind.CAR)


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_generated_worlds_are_valid_and_populated(seed: int) -> None:
    world = parse_world(generate_world(seed), "generated")
    base = load_world("revinge")
    assert world.name == f"revinge-s{seed}"
    assert world.buildings == base.buildings and world.pads == base.pads
    counts = {k: len(world.objects_of(k)) for k in GENERATED}
    assert counts == {ObjectKind.PERSON: 11, ObjectKind.DUMMY: 3, ObjectKind.ANIMAL: 4,
                      ObjectKind.CAR: 4}  # fmt: skip
    assert world.objects_of(ObjectKind.BOX) == base.objects_of(ObjectKind.BOX)
    new = [o for o in world.objects if o.kind in GENERATED]
    for a, b in itertools.combinations(new, 2):
        assert math.hypot(a.east - b.east, a.north - b.north) >= SPACING_M
    obstacles = [Polygon(b.footprint) for b in world.buildings]
    obstacles += [Polygon(v.polygon) for v in world.vegetation]
    for obj in new:
        point = Point(obj.east, obj.north)
        assert all(shape.distance(point) >= CLEARANCE_M - 1e-6 for shape in obstacles), obj.id
    persons = world.objects_of(ObjectKind.PERSON)
    dummies = world.objects_of(ObjectKind.DUMMY)
    assert min(p.temperature or 0.0 for p in persons) > max(d.temperature or 0.0 for d in dummies)


def test_same_seed_same_world_other_seed_other_world() -> None:
    assert generate_world(7) == generate_world(7)
    assert generate_world(7) != generate_world(8)


@pytest.mark.parametrize(
    ("seed", "population", "message"),
    [
        (-1, Population(), "seed must be an integer >= 0"),
        (0, Population(persons=-1), "object counts must be 0..200"),
        (0, Population(persons=200, dummies=200, animals=200, cars=200), "no free spot left"),
    ],
)
def test_bad_requests_are_config_errors(
    seed: int, population: Population, message: str, tmp_path: Path
) -> None:
    tiny = tmp_path / "tiny.toml"
    tiny.write_text(TINY)
    with pytest.raises(ConfigError, match=message):
        generate_world(seed, base=tiny, population=population)


def test_generated_file_loads(tmp_path: Path) -> None:
    out = tmp_path / "w.toml"
    out.write_text(generate_world(5, population=Population(2, 1, 1, 0)))
    world = load_world(out)
    assert len(world.objects_of(ObjectKind.PERSON)) == 2
