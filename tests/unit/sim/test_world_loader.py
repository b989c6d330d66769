"""World file loading: the shipped revinge world and table-driven bad worlds with file:line."""

from __future__ import annotations

import colorsys
import math
import random
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import unary_union

from sim.drive import DrivePlan
from sim.geodesy import enu_to_geodetic
from sim.render import bodies
from sim.render.materials import Material
from sim.world import BoxContents, DepotKind, ObjectKind
from sim.world_loader import (
    DEFAULT_SIZES,
    WorldError,
    load_world,
    load_world_sources,
    parse_world,
    shipped_worlds,
    world_path,
)

BASE = """\
[world]
name = "test"

[origin]
latitude = 55.7
longitude = 13.47
altitude = 95.0

[terrain]
east0 = -100.0
north0 = -100.0
spacing = 100.0
heights = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]
"""

BUILDING = """
[[building]]
name = "B1"
footprint = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
height = 8.0
"""

CARRIER = """
[[object]]
id = "c1"
type = "carrier"
position = [-20.0, 3.0]
capacity = 4
mass = 8.0
"""

# Each bad world marks the offending line with "# <-- error".
BAD_WORLDS = {
    "syntax": (BASE + "[[building]]\nname = = 'x'  # <-- error\n", "syntax error"),
    "building without height": (
        BASE + '[[building]]  # <-- error\nname = "B1"\nfootprint = [[0,0],[1,0],[1,1]]\n',
        "building 'B1' has no height",
    ),
    "building height zero": (
        BASE + BUILDING.replace("height = 8.0", "height = 0.0  # <-- error"),
        "height must be > 0.0",
    ),
    "height not a number": (
        BASE + BUILDING.replace("height = 8.0", 'height = "tall"  # <-- error'),
        "height must be a finite number",
    ),
    "footprint two vertices": (
        BASE + '[[building]]\nname = "B1"\nfootprint = [[0,0],[1,0]]  # <-- error\nheight = 3.0\n',
        "at least 3 points",
    ),
    "self-intersecting footprint": (
        BASE
        + '[[building]]\nname = "B1"\n'
        + "footprint = [[0,0],[10,10],[10,0],[0,10]]  # <-- error\nheight = 3.0\n",
        "Self-intersection",
    ),
    "overlapping pads": (
        BASE
        + '[[pad]]\nname = "H1"\nposition = [-50.0, -50.0]\nradius = 5.0\n'
        + '[[pad]]\nname = "H2"\nposition = [-42.0, -50.0]  # <-- error\nradius = 5.0\n',
        "pad 'H2' overlaps pad 'H1'",
    ),
    "pad pattern not a flag": (
        BASE
        + '[[pad]]\nname = "L1"\nposition = [-50.0, -50.0]\nradius = 3.0\n'
        + 'pattern = "yes"  # <-- error\n',
        "pad pattern must be true or false",
    ),
    "pad too small for the pattern": (
        BASE
        + '[[pad]]\nname = "L1"\nposition = [-50.0, -50.0]\nradius = 1.0  # <-- error\n'
        + "pattern = true\n",
        "needs radius >= 1.56 m",
    ),
    "pad inside building": (
        BASE
        + BUILDING
        + '[[pad]]\nname = "H1"\nposition = [5.0, 5.0]  # <-- error\nradius = 3.0\n',
        "pad 'H1' overlaps building 'B1'",
    ),
    "unknown object type": (
        BASE + '[[object]]\nid = "t1"\ntype = "tank"  # <-- error\nposition = [1.0, 2.0]\n',
        "unknown object type 'tank'",
    ),
    "object inside building": (
        BASE
        + BUILDING
        + '[[object]]\nid = "p1"\ntype = "person"\nposition = [2.0, 3.0]  # <-- error\n'
        + "temperature_c = 33.0\n",
        "person 'p1' is inside building 'B1'",
    ),
    "person without temperature": (
        BASE + '[[object]]  # <-- error\nid = "p1"\ntype = "person"\nposition = [-20.0, 3.0]\n',
        "person 'p1' has no temperature_c",
    ),
    "animal without temperature": (
        BASE + '[[object]]  # <-- error\nid = "a1"\ntype = "animal"\nposition = [-20.0, 3.0]\n',
        "animal 'a1' has no temperature_c",
    ),
    "property of a dummy": (
        BASE
        + '[[object]]\nid = "d1"\ntype = "dummy"\nposition = [-20.0, 3.0]\n'
        + "mass = 4.0  # <-- error\n",
        "mass does not apply to a dummy",
    ),
    "box contents": (
        BASE
        + '[[object]]\nid = "b1"\ntype = "box"\nposition = [-20.0, 3.0]\n'
        + 'contents = "gold"  # <-- error\nmass = 5.0\n',
        "unknown object contents 'gold'",
    ),
    "property of another kind": (
        BASE
        + '[[object]]\nid = "c1"\ntype = "car"\nposition = [-20.0, 3.0]\n'
        + "capacity = 4  # <-- error\n",
        "capacity does not apply to a car",
    ),
    "box on what is not a carrier": (
        BASE
        + '[[object]]\nid = "b1"\ntype = "box"\nposition = [-20.0, 3.0]\n'
        + 'contents = "food"\nmass = 5.0\non = "b1"  # <-- error\n',
        "box 'b1': 'b1' is not a carrier",
    ),
    "box beside its carrier": (
        BASE
        + CARRIER
        + '[[object]]\nid = "b1"\ntype = "box"\nposition = [-19.0, 3.0]  # <-- error\n'
        + 'contents = "food"\nmass = 5.0\non = "c1"\n',
        "box 'b1' does not lie within carrier 'c1'",
    ),
    "carrier over its capacity": (
        BASE
        + CARRIER.replace("capacity = 4", "capacity = 1")
        + '[[object]]\nid = "b1"\ntype = "box"\nposition = [-20.2, 3.3]\n'
        + 'contents = "food"\nmass = 5.0\non = "c1"\n'
        + '[[object]]\nid = "b2"\ntype = "box"\nposition = [-19.8, 3.3]\n'
        + 'contents = "food"\nmass = 5.0\non = "c1"  # <-- error\n',
        "carrier 'c1' holds 1 boxes; 'b2' is one more",
    ),
    "duplicate names": (
        BASE + BUILDING + '[[place]]\nname = "B1"  # <-- error\nposition = [-50.0, -50.0]\n',
        "duplicate name 'B1'",
    ),
    "origin out of range": (
        BASE.replace("latitude = 55.7", "latitude = 95.0  # <-- error"),
        "origin out of range",
    ),
    "unknown key": (
        BASE + BUILDING.replace("height = 8.0", "heigth = 8.0  # <-- error"),
        "unknown key 'heigth' in building",
    ),
    "unknown section": (BASE + "[[tree]]  # <-- error\nname = 'x'\n", "unknown section 'tree'"),
    "missing section": (
        BASE.split("[terrain]")[0].replace("[world]", "[world]  # <-- error", 1),
        "missing required section [terrain]",
    ),
    "no-fly ceiling below floor": (
        BASE
        + '[[no_fly_zone]]\nname = "z"\npolygon = [[0,0],[5,0],[5,5]]\nfloor = 50.0\n'
        + "ceiling = 10.0  # <-- error\n",
        "ceiling 10.0 must be above floor 50.0",
    ),
    "outside terrain": (
        BASE + '[[place]]\nname = "far"\nposition = [500.0, 0.0]  # <-- error\n',
        "outside the terrain grid",
    ),
    "ragged terrain": (
        BASE.replace(
            "heights = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]",
            "heights = [[0.0, 0.0], [0.0, 1.0, 0.0]]  # <-- error",
        ),
        "rectangular grid",
    ),
    "radiation source without dose rate": (
        BASE + '[[radiation_source]]  # <-- error\nname = "r"\nposition = [0.0, 0.0]\n',
        "radiation_source 'r' has no dose_rate",
    ),
    "radiation source dose rate zero": (
        BASE + '[[radiation_source]]\nname = "r"\nposition = [0.0, 0.0]\n'
        "dose_rate = 0.0  # <-- error\n",
        "dose_rate must be > 0.0",
    ),
    "negative background": (
        BASE.replace('name = "test"', 'name = "test"\nradiation_background = -1.0  # <-- error'),
        "radiation_background must be >= 0.0",
    ),
    "unknown depot type": (
        BASE + '[[depot]]\nname = "d"\ntype = "fuel"  # <-- error\nposition = [0.0, -50.0]\n'
        "radius = 5.0\n",
        "unknown depot type 'fuel'",
    ),
}


def _marked_line(text: str) -> int:
    lines = text.splitlines()
    return next(i for i, line in enumerate(lines, start=1) if "# <-- error" in line)


@pytest.mark.parametrize("case", sorted(BAD_WORLDS))
def test_bad_world_is_rejected_with_line_and_reason(case: str, tmp_path: Path) -> None:
    text, reason = BAD_WORLDS[case]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    error = caught.value
    assert error.line == _marked_line(text), str(error)
    assert reason in error.reason, str(error)
    assert str(error).startswith(f"{path}:{error.line}:")


def test_syntax_error_has_column(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(BASE + "x = [1, 2\n")
    with pytest.raises(WorldError) as caught:
        load_world(path)
    assert caught.value.issues[0].column is not None


def test_all_issues_are_listed_in_line_order() -> None:
    text = BASE + BUILDING.replace("height = 8.0", "height = -1.0") + '[[object]]\nid = "x"\n'
    with pytest.raises(WorldError) as caught:
        parse_world(text, "mem.toml")
    lines = [i.line for i in caught.value.issues]
    assert len(lines) == 2 and lines == sorted(lines)
    assert "(and 1 more)" in str(caught.value)


def test_missing_file_is_a_world_error(tmp_path: Path) -> None:
    with pytest.raises(WorldError, match="cannot read"):
        load_world(tmp_path / "nope.toml")


def test_minimal_world_loads_with_defaults() -> None:
    world = parse_world(BASE + BUILDING, "mem.toml")
    (building,) = world.buildings
    # Lowest terrain under the footprint: the hill (1 m at 0,0) is 0.81 m high at (10, 10).
    assert building.base == pytest.approx(0.81)
    assert building.top == pytest.approx(8.81)
    assert world.description == ""


def test_revinge_is_shipped_and_meets_the_brief() -> None:
    assert "revinge" in shipped_worlds()
    world = load_world("revinge")
    assert world.name == "revinge"
    assert abs(world.origin.latitude - 55.70) < 0.02 and abs(world.origin.longitude - 13.47) < 0.02
    assert 20 <= len(world.buildings) <= 40
    assert all(3.0 <= b.height <= 15.0 for b in world.buildings)
    e0, n0, e1, n1 = world.bounds
    assert e1 - e0 == pytest.approx(600.0, rel=0.1) and n1 - n0 == pytest.approx(400.0, rel=0.1)
    assert {p.name for p in world.pads} >= {"H1", "H2", "L1"}
    assert [p.name for p in world.pads if p.pattern] == ["L1"]
    assert {d.kind for d in world.depots} == {DepotKind.SUPPLY, DepotKind.CARRIER}
    assert len(world.roads) >= 3 and world.vegetation and world.no_fly_zones and world.places
    persons = world.objects_of(ObjectKind.PERSON)
    assert len(persons) == 11 and all(p.temperature is not None for p in persons)
    boxes = world.objects_of(ObjectKind.BOX)
    assert {b.contents for b in boxes} >= {BoxContents.FOOD, BoxContents.MEDICINE}
    depots = {d.kind: d for d in world.depots}
    for box in boxes:  # loose boxes at the supply depot, loaded ones on a carrier at the other
        depot = depots[DepotKind.CARRIER if box.on else DepotKind.SUPPLY]
        assert math.hypot(box.east - depot.east, box.north - depot.north) < depot.radius
    assert world.objects_of(ObjectKind.CARRIER) and world.objects_of(ObjectKind.CAR)


def test_revinge_extent_in_wgs84() -> None:
    world = load_world("revinge")
    e0, n0, e1, n1 = world.bounds
    sw = enu_to_geodetic(world.origin, e0, n0, 0.0)
    ne = enu_to_geodetic(world.origin, e1, n1, 0.0)
    # 600 m east at 55.7 N is about 0.0096 deg of longitude; 400 m north about 0.0036 deg.
    assert ne.longitude - sw.longitude == pytest.approx(
        600.0 / (111_320.0 * math.cos(math.radians(55.7))), rel=0.01
    )
    assert ne.latitude - sw.latitude == pytest.approx(400.0 / 111_200.0, rel=0.01)


def test_readme_example_is_a_valid_world() -> None:
    readme = Path(__file__).parents[3] / "sim" / "worlds" / "README.md"
    example = readme.read_text().split("```toml\n")[1].split("```")[0]
    world = parse_world(example, "README.md")
    assert world.name == "tiny" and world.objects[0].temperature == pytest.approx(306.65)


def test_mutated_worlds_never_crash_the_loader() -> None:
    # Deterministic mutations of the shipped file: deleted, duplicated and corrupted lines must
    # load or raise WorldError, never anything else.
    lines = (Path(__file__).parents[3] / "sim" / "worlds" / "revinge.toml").read_text().splitlines()
    rng = random.Random(0)
    outcomes = {"ok": 0, "error": 0}
    for _ in range(150):
        mutated = list(lines)
        k = rng.randrange(len(mutated))
        op = rng.randrange(3)
        if op == 0:
            del mutated[k]
        elif op == 1:
            mutated.insert(k, rng.choice(mutated))
        else:
            old = rng.choice(["1", ".", '"', "[", "]", "=", "0"])
            new = rng.choice(["", "-", "[]", '"x"', "true", "1e999", "nan"])
            mutated[k] = mutated[k].replace(old, new, 1)
        try:
            parse_world("\n".join(mutated), "fuzz.toml")
            outcomes["ok"] += 1
        except WorldError as exc:
            assert exc.issues and all(i.line >= 1 for i in exc.issues)
            outcomes["error"] += 1
    assert outcomes["ok"] > 0 and outcomes["error"] > 0


def test_dummies_and_animals_load_with_default_sizes() -> None:
    text = (
        BASE
        + '[[object]]\nid = "d1"\ntype = "dummy"\nposition = [-20.0, 3.0]\n'
        + '[[object]]\nid = "a1"\ntype = "animal"\nposition = [-30.0, 3.0]\n'
        + "temperature_c = 30.0\nmass = 25.0\n"
    )
    world = parse_world(text, "distractors")
    dummy, animal = world.objects
    assert (dummy.kind, dummy.temperature, dummy.size) == (
        ObjectKind.DUMMY, None, DEFAULT_SIZES[ObjectKind.DUMMY]
    )  # fmt: skip
    assert animal.kind is ObjectKind.ANIMAL and animal.mass == 25.0
    assert animal.temperature == pytest.approx(303.15)


def test_revinge_has_dummies_and_animals() -> None:
    world = load_world("revinge")
    assert len(world.objects_of(ObjectKind.DUMMY)) >= 2
    assert len(world.objects_of(ObjectKind.ANIMAL)) >= 3


def test_a_box_may_rest_on_a_carrier_from_the_start() -> None:
    text = (
        BASE
        + CARRIER
        + '[[object]]\nid = "b1"\ntype = "box"\nposition = [-20.2, 3.3]\n'
        + 'contents = "water"\nmass = 5.0\non = "c1"\n'
    )
    carrier, box = parse_world(text, "loaded").objects
    assert (carrier.on, box.on) == (None, "c1")


BASE_WORLD = (
    BASE.replace(
        'name = "test"', 'name = "base"\ndescription = "the base"\nradiation_background = 0.2'
    )
    + BUILDING
    + '\n[[pad]]\nname = "H1"\nposition = [-50.0, -50.0]\nradius = 5.0\n'
)
VARIANT = '[world]\nname = "variant"\nextends = "../base.toml"\n'
B2 = BUILDING.replace('"B1"', '"B2"').replace("0.0, 0.0], [10.0, 0.0", "0.0, 20.0], [10.0, 20.0")
FLAT_TERRAIN = """
[terrain]
east0 = -100.0
north0 = -100.0
spacing = 200.0
heights = [[5.0, 5.0], [5.0, 5.0]]
"""


def _variant(tmp_path: Path, text: str, others: dict[str, str] | None = None) -> Path:
    """Write base.toml, and the variant (and any ``others``) into a subfolder; the variant path."""
    (tmp_path / "base.toml").write_text(BASE_WORLD)
    folder = tmp_path / "variants"
    folder.mkdir()
    for name, other in (others or {}).items():
        (folder / name).write_text(other)
    path = folder / "variant.toml"
    path.write_text(text)
    return path


def test_variant_appends_to_and_inherits_from_its_base(tmp_path: Path) -> None:
    path = _variant(tmp_path, VARIANT + B2 + '[[place]]\nname = "spot"\nposition = [50.0, 50.0]\n')
    world, base = load_world(path), load_world(tmp_path / "base.toml")
    assert (world.name, world.source) == ("variant", path)
    assert [b.name for b in world.buildings] == ["B1", "B2"]
    assert [p.name for p in world.places] == ["spot"] and world.pads == base.pads
    assert (world.origin, world.terrain) == (base.origin, base.terrain)
    assert (world.description, world.radiation_background) == ("the base", 0.2)


def test_the_sources_of_a_world_are_its_file_then_its_bases(tmp_path: Path) -> None:
    path = _variant(tmp_path, VARIANT)
    world, files = load_world_sources(path)
    assert world == load_world(path)
    assert [f.resolve() for f in files] == [path.resolve(), (tmp_path / "base.toml").resolve()]
    assert load_world_sources("revinge")[1] == (world_path("revinge"),)


def test_variant_overrides_what_it_gives(tmp_path: Path) -> None:
    text = (
        VARIANT
        + 'description = "mine"\nradiation_background = 0.5\n'
        + "[origin]\nlatitude = 58.4\nlongitude = 15.6\naltitude = 100.0\n"
        + FLAT_TERRAIN
    )
    world = load_world(_variant(tmp_path, text))
    assert (world.origin.latitude, world.description, world.radiation_background) == (
        58.4, "mine", 0.5
    )  # fmt: skip
    # The base's building stands on the variant's (flat, 5 m) terrain.
    assert world.terrain.height(0.0, 0.0) == 5.0 and world.buildings[0].base == 5.0


def test_variant_of_a_shipped_world_by_name() -> None:
    world = parse_world('[world]\nname = "v"\nextends = "revinge"\n', "v.toml")
    assert world.name == "v" and world.buildings == load_world("revinge").buildings


# Each bad variant marks the offending line of variant.toml with "# <-- error".
BAD_VARIANTS: dict[str, tuple[str, dict[str, str], str]] = {
    "unknown base file": (
        VARIANT.replace('"../base.toml"', '"nowhere.toml"  # <-- error'),
        {},
        "cannot load base world 'nowhere.toml'",
    ),
    "unknown shipped world": (
        VARIANT.replace('"../base.toml"', '"atlantis"  # <-- error'),
        {},
        "cannot load base world 'atlantis'",
    ),
    "extends not a string": (
        VARIANT.replace('"../base.toml"', "3  # <-- error"),
        {},
        "world extends must be a world name or path",
    ),
    "extends itself": (
        VARIANT.replace('"../base.toml"', '"variant.toml"  # <-- error'),
        {},
        "world extends itself: variant.toml -> variant.toml",
    ),
    "cycle": (
        VARIANT.replace('"../base.toml"', '"a.toml"  # <-- error'),
        {"a.toml": '[world]\nname = "a"\nextends = "variant.toml"\n'},
        "world extends itself: variant.toml -> a.toml -> variant.toml",
    ),
    "invalid base": (
        VARIANT.replace('"../base.toml"', '"bad.toml"  # <-- error'),
        {"bad.toml": BASE + BUILDING.replace("height = 8.0", "height = 0.0")},
        "bad.toml:18: building 'B1': height must be > 0.0",
    ),
    "no name": (
        VARIANT.replace("[world]", "[world]  # <-- error").replace('name = "variant"\n', ""),
        {},
        "world has no name",
    ),
    "error in the variant": (
        VARIANT + B2.replace("height = 8.0", "height = 0.0  # <-- error"),
        {},
        "building 'B2': height must be > 0.0",
    ),
    "duplicate name with the base": (
        VARIANT + '[[place]]\nname = "B1"  # <-- error\nposition = [50.0, 50.0]\n',
        {},
        "duplicate name 'B1' (already used by a building)",
    ),
    "base entry clashes with the variant": (
        VARIANT.replace('"../base.toml"', '"../base.toml"  # <-- error')
        + '[[building]]\nname = "shed"\nheight = 3.0\n'
        + "footprint = [[-52.0, -52.0], [-48.0, -52.0], [-50.0, -48.0]]\n",
        {},
        "pad 'H1' overlaps building 'shed' (base world entry at ",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD_VARIANTS))
def test_bad_variant_is_rejected_at_its_line(case: str, tmp_path: Path) -> None:
    text, others, reason = BAD_VARIANTS[case]
    path = _variant(tmp_path, text, others)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    error = caught.value
    assert str(error).startswith(f"{path}:{_marked_line(text)}:"), str(error)
    assert reason in error.reason, str(error)


def test_too_deep_extends_is_rejected(tmp_path: Path) -> None:
    (tmp_path / "w0.toml").write_text(BASE_WORLD)
    for k in range(1, 11):
        (tmp_path / f"w{k}.toml").write_text(f'[world]\nname = "w{k}"\nextends = "w{k - 1}.toml"\n')
    assert load_world(tmp_path / "w8.toml").name == "w8"
    with pytest.raises(WorldError, match="more than 8 nested base worlds"):
        load_world(tmp_path / "w10.toml")


def test_revinge_changed_is_revinge_with_a_container_and_new_trees() -> None:
    assert "revinge_changed" in shipped_worlds()
    world, revinge = load_world("revinge_changed"), load_world("revinge")
    assert world.name == "revinge_changed" and world.source is not None
    assert world.source.name == "revinge_changed.toml" and "11.2" in world.description
    assert world.buildings[: len(revinge.buildings)] == revinge.buildings
    assert [b.name for b in world.buildings[len(revinge.buildings) :]] == ["C1"]
    assert [v.name for v in world.vegetation[len(revinge.vegetation) :]] == ["V-new"]
    assert (world.origin, world.terrain, world.objects) == (
        revinge.origin, revinge.terrain, revinge.objects
    )  # fmt: skip
    container = world.buildings[-1]
    east = [e for e, _ in container.footprint]
    north = [n for _, n in container.footprint]
    assert max(east) - min(east) == pytest.approx(2.5)
    assert max(north) - min(north) == pytest.approx(12.2)
    assert container.height == pytest.approx(2.6)


CAR = """
[[object]]
id = "k1"
type = "car"
route = [[-50.0, -50.0], [50.0, -50.0], [50.0, 50.0]]
speed = 8.0
"""
ROUTE = "route = [[-50.0, -50.0], [50.0, -50.0], [50.0, 50.0]]"

BAD_CARS = {
    "route of a person": (
        BASE
        + '[[object]]\nid = "p1"\ntype = "person"\nposition = [-20.0, 3.0]\ntemperature_c = 33.0\n'
        + "route = [[0.0, 0.0], [5.0, 0.0]]  # <-- error\n",
        "object 'p1': route does not apply to a person",
    ),
    "paint of a dummy": (
        BASE
        + '[[object]]\nid = "d1"\ntype = "dummy"\nposition = [-20.0, 3.0]\n'
        + "paint = [1.0, 0.0, 0.0]  # <-- error\n",
        "paint does not apply to a dummy",
    ),
    "speed of a parked car": (
        BASE
        + '[[object]]\nid = "k1"\ntype = "car"\nposition = [-20.0, 3.0]\n'
        + "speed = 5.0  # <-- error\n",
        "car 'k1': speed applies to a car with a route",
    ),
    "position of a driving car": (
        BASE + CAR + "position = [-50.0, -50.0]  # <-- error\n",
        "car 'k1' drives a route: its start is the route's, leave out position",
    ),
    "route of one point": (
        BASE + CAR.replace(ROUTE, "route = [[0.0, -50.0]]  # <-- error"),
        "route needs at least 2 points, got 1",
    ),
    "route not finite": (
        BASE + CAR.replace(ROUTE, "route = [[0.0, -50.0], [nan, 0.0]]  # <-- error"),
        "route must be a list of [east, north] pairs",
    ),
    "no speed": (
        BASE + CAR.replace("[[object]]", "[[object]]  # <-- error").replace("speed = 8.0\n", ""),
        "car 'k1' has a route but no speed",
    ),
    "speed zero": (
        BASE + CAR.replace("speed = 8.0", "speed = 0.0  # <-- error"),
        "car 'k1': speed must be a number > 0 and <= 15.0 m/s, got 0.0",
    ),
    "speed too high": (
        BASE + CAR.replace("speed = 8.0", "speed = 16.0  # <-- error"),
        "speed must be a number > 0 and <= 15.0 m/s, got 16.0",
    ),
    "speed infinite": (
        BASE + CAR.replace("speed = 8.0", "speed = inf  # <-- error"),
        "speed must be a number > 0 and <= 15.0 m/s, got inf",
    ),
    "loop not a flag": (
        BASE + CAR + 'loop = "yes"  # <-- error\n',
        "car 'k1': loop must be true or false",
    ),
    "negative depart": (
        BASE + CAR + "depart = -1.0  # <-- error\n",
        "car 'k1': depart must be a number of seconds >= 0, got -1.0",
    ),
    "paint out of range": (
        BASE + CAR + "paint = [1.2, 0.0, 0.0]  # <-- error\n",
        "object 'k1': paint must be [red, green, blue], each 0..1",
    ),
    "paint of two colours": (
        BASE + CAR + "paint = [0.5, 0.5]  # <-- error\n",
        "paint must be [red, green, blue]",
    ),
    "loop of two waypoints": (
        BASE
        + CAR.replace(ROUTE, "route = [[-50.0, -50.0], [50.0, -50.0]]  # <-- error")
        + "loop = true\n",
        "car 'k1': a looping route needs at least 3 distinct waypoints, got 2",
    ),
    "u-turn": (
        BASE
        + CAR.replace(ROUTE, "route = [[0.0, -50.0], [50.0, -50.0], [0.0, -51.0]]  # <-- error"),
        "car 'k1': route turns by 179 deg at waypoint 1 (at most 150)",
    ),
    "route outside the world": (
        BASE + CAR.replace(ROUTE, "route = [[-50.0, -50.0], [500.0, -50.0]]  # <-- error"),
        "object 'k1' lies outside the terrain grid",
    ),
    "route through a building": (
        BASE + BUILDING + CAR.replace(ROUTE, "route = [[-50.0, 5.0], [50.0, 5.0]]  # <-- error"),
        "car 'k1': route crosses building 'B1'",
    ),
    "loop closing through a building": (
        BASE
        + BUILDING
        + CAR.replace(
            ROUTE, "route = [[20.0, 5.0], [20.0, -50.0], [-50.0, -50.0], [-50.0, 5.0]]  # <-- error"
        )
        + "loop = true\n",
        "car 'k1': route crosses building 'B1'",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD_CARS))
def test_bad_car_is_rejected_with_line_and_reason(case: str, tmp_path: Path) -> None:
    text, reason = BAD_CARS[case]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    error = caught.value
    assert error.line == _marked_line(text), str(error)
    assert reason in error.reason, str(error)
    assert len(error.issues) == 1, str(error)


def test_a_driving_car_starts_on_its_route_with_its_paint() -> None:
    world = parse_world(BASE + CAR + "loop = true\ndepart = 3.0\npaint = [0.1, 0.2, 1]\n", "mem")
    (car,) = world.objects
    assert car.drive is not None and car.drive.loop and car.drive.depart == 3.0
    assert car.drive.route == ((-50.0, -50.0), (50.0, -50.0), (50.0, 50.0))
    assert car.drive.speed == 8.0 and car.paint == (0.1, 0.2, 1.0)
    # the loop's first waypoint is a 135 degree corner: the car waits past its 5 m arc (12 m)
    assert car.north == pytest.approx(-50.0) and car.east == pytest.approx(
        -50.0 + 5.0 * math.tan(math.radians(67.5))
    )
    assert car.heading == pytest.approx(math.pi / 2.0)
    parked = parse_world(
        BASE + CAR.replace(ROUTE, "position = [1.0, 2.0]").replace("speed", "#"), "m"
    )
    assert parked.objects[0].drive is None and parked.objects[0].paint is None


def _hue(rgb: tuple[float, float, float]) -> tuple[float, float]:
    """Hue (deg) and saturation of a colour."""
    hue, saturation, _ = colorsys.rgb_to_hsv(*rgb)
    return hue * 360.0, saturation


def test_revinge_chase_is_revinge_with_a_car_driving_laps_on_its_roads() -> None:
    assert "revinge_chase" in shipped_worlds()
    world, revinge = load_world("revinge_chase"), load_world("revinge")
    assert world.objects[: len(revinge.objects)] == revinge.objects
    (chase,) = world.objects[len(revinge.objects) :]
    assert (world.buildings, world.roads) == (revinge.buildings, revinge.roads)
    assert chase.id == "chase1" and chase.kind is ObjectKind.CAR
    assert chase.drive is not None and chase.drive.loop and chase.drive.speed == 10.0
    plan = DrivePlan.of(chase.drive)
    assert 60.0 <= plan.lap_time <= 120.0 and plan.start_time + 0.5 * plan.lap_time < 180.0
    roads = unary_union([LineString(r.points).buffer(r.width / 2.0) for r in world.roads])
    buildings = unary_union([Polygon(b.footprint) for b in world.buildings])
    trees = unary_union([Polygon(v.polygon) for v in world.vegetation])
    length, width, _ = chase.size
    for t in np.arange(0.0, plan.start_time + plan.lap_time, 0.25):
        pose = plan.pose(float(t))
        body = _footprint(pose.east, pose.north, pose.heading, length, width)
        assert roads.contains(body), f"t = {t}: {pose}"
        assert body.distance(buildings) > 8.0 and body.distance(trees) > 8.0
    persons = [o for o in world.objects if o.kind in (ObjectKind.PERSON, ObjectKind.DUMMY)]
    path = LineString([*chase.drive.route, chase.drive.route[0]])
    assert min(path.distance(Point(o.east, o.north)) for o in persons) > 4.0


def test_revinge_chase_paint_is_a_hue_nothing_else_has() -> None:
    world = load_world("revinge_chase")
    (chase,) = [o for o in world.objects if o.id == "chase1"]
    assert chase.paint is not None
    hue, saturation = _hue(chase.paint)
    assert saturation > 0.9
    palette = [*bodies.SHIRTS, *bodies.TROUSERS, *bodies.SKINS, *bodies.FURS, *bodies.CAR_PAINTS]
    palette += [m.surface.albedo for m in Material]
    palette += [(0.55, 0.40, 0.22), (0.4, 0.42, 0.45)]  # boxes and carriers
    palette += [o.paint for o in world.objects if o.paint is not None and o is not chase]
    for colour in palette:
        other, other_saturation = _hue(colour)
        gap = abs((hue - other + 180.0) % 360.0 - 180.0)
        assert other_saturation < 0.2 or gap > 45.0, colour


def _footprint(east: float, north: float, heading: float, length: float, width: float) -> Polygon:
    s, c = math.sin(heading), math.cos(heading)
    corners = [(a * length / 2.0, b * width / 2.0) for a, b in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
    return Polygon([(east + a * s - b * c, north + a * c + b * s) for a, b in corners])
