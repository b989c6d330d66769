"""Load a world file (TOML, see ``sim/worlds/README.md``) into a validated :class:`World`.

One loader for every consumer (simulator, GIS / path planner, renderer). Any syntax or semantic
problem raises :class:`WorldError` naming ``file:line`` and the reason; all problems found in one
pass are listed, the first one leads the message. A world may ``extends`` a base world: it then
lists only what it adds, and the merged world is validated as a whole.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

from hdrc3_base.errors import DataError
from sim.drive import MAX_SPEED, DrivePlan, drive_problem
from sim.geodesy import GeodeticOrigin
from sim.landing_pattern import PAD_HALF_WIDTH_M
from sim.terrain import Terrain
from sim.world import (
    AIR_ATTENUATION,
    DEFAULT_BACKGROUND,
    BoxContents,
    Building,
    Depot,
    DepotKind,
    Drive,
    DynamicObject,
    LandingPad,
    NoFlyZone,
    ObjectKind,
    Place,
    Point2,
    RadiationSource,
    Road,
    Vegetation,
    World,
)
from sim.world_index import LineIndex
from sim.world_validation import validate_world

_E = TypeVar("_E")
enum_t = TypeVar("enum_t", DepotKind, ObjectKind, BoxContents)

ZERO_CELSIUS = 273.15
DEFAULT_SIZES: dict[ObjectKind, tuple[float, float, float]] = {
    ObjectKind.PERSON: (1.8, 0.5, 0.3),
    ObjectKind.BOX: (0.4, 0.4, 0.3),
    ObjectKind.CARRIER: (1.2, 0.8, 0.4),
    ObjectKind.CAR: (4.5, 1.8, 1.5),
    ObjectKind.DUMMY: (1.8, 0.5, 0.3),
    ObjectKind.ANIMAL: (1.1, 0.4, 0.8),
}
"""Default object dimensions (length, width, height), m, when the file gives no ``size``."""

_TABLE_KEYS: dict[str, frozenset[str]] = {
    "world": frozenset({"name", "description", "radiation_background", "extends"}),
    "origin": frozenset({"latitude", "longitude", "altitude"}),
    "terrain": frozenset({"east0", "north0", "spacing", "heights"}),
}
_ARRAY_KEYS: dict[str, frozenset[str]] = {
    "building": frozenset({"name", "footprint", "height", "base"}),
    "road": frozenset({"name", "points", "width"}),
    "vegetation": frozenset({"name", "polygon", "height"}),
    "no_fly_zone": frozenset({"name", "polygon", "floor", "ceiling"}),
    "place": frozenset({"name", "position"}),
    "radiation_source": frozenset({"name", "position", "height", "dose_rate", "attenuation"}),
    "pad": frozenset({"name", "position", "radius", "heading_deg", "pattern"}),
    "depot": frozenset({"name", "type", "position", "radius"}),
    "object": frozenset(
        {
            "id",
            "type",
            "position",
            "heading_deg",
            "size",
            "temperature_c",
            "contents",
            "mass",
            "capacity",
            "on",
            "route",
            "speed",
            "loop",
            "depart",
            "paint",
        }
    ),
}
_ARRAY_FIELDS: dict[str, str] = {
    "building": "buildings",
    "road": "roads",
    "vegetation": "vegetation",
    "no_fly_zone": "no_fly_zones",
    "place": "places",
    "radiation_source": "radiation_sources",
    "pad": "pads",
    "depot": "depots",
    "object": "objects",
}
"""Array section -> the :class:`World` field holding its entries."""
_REQUIRED_TABLES = ("world", "origin", "terrain")
MAX_EXTENDS = 8
"""Most base worlds one world may stack up through ``extends``."""
_TOML_POSITION = re.compile(r"\(at (?:line (\d+), column (\d+)|end of document)\)")


@dataclass(frozen=True, slots=True)
class WorldIssue:
    """One problem in a world file."""

    path: str
    line: int
    column: int | None
    reason: str

    def __str__(self) -> str:
        """``file:line[:column]: reason``."""
        col = f":{self.column}" if self.column is not None else ""
        return f"{self.path}:{self.line}{col}: {self.reason}"


class WorldError(DataError):
    """A world file is unreadable, malformed or semantically invalid."""

    def __init__(self, issues: list[WorldIssue]) -> None:
        self.issues = tuple(issues)
        first = self.issues[0]
        more = f" (and {len(self.issues) - 1} more)" if len(self.issues) > 1 else ""
        super().__init__(f"{first}{more}")

    @property
    def line(self) -> int:
        """Line of the first issue."""
        return self.issues[0].line

    @property
    def reason(self) -> str:
        """Reason of the first issue."""
        return self.issues[0].reason


def world_path(name_or_path: str | Path) -> Path:
    """Resolve a shipped world name (``"revinge"``) or a file path to a path."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".toml" or candidate.exists():
        return candidate
    return _shipped_path(str(name_or_path))


def _shipped_path(name: str) -> Path:
    return Path(str(resources.files("sim.worlds").joinpath(f"{name}.toml")))


def _base_path(extends: str, source: Path | None) -> Path:
    """Resolve ``extends`` like :func:`world_path`; a relative path is from ``source``'s folder."""
    candidate = Path(extends) if source is None else source.parent / extends
    if candidate.suffix == ".toml" or candidate.exists():
        return candidate
    return _shipped_path(extends)


def shipped_worlds() -> tuple[str, ...]:
    """Names of the worlds shipped in ``sim/worlds``."""
    folder = resources.files("sim.worlds")
    return tuple(sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml")))


def load_world(name_or_path: str | Path) -> World:
    """Load and validate a world by shipped name or file path.

    Raises:
        WorldError: the file is missing, unreadable, or has a syntax or semantic error.

    """
    return _with_bases(_load(world_path(name_or_path), ()).world)


def load_world_sources(name_or_path: str | Path) -> tuple[World, tuple[Path, ...]]:
    """:func:`load_world`, and the files it read: the world's, then its bases' in order.

    For a cache of loaded worlds: the world is the same as long as none of them changed.
    """
    parsed = _load(world_path(name_or_path), ())
    files: list[Path] = []
    layer: _Parsed | None = parsed
    while layer is not None:
        files.append(Path(layer.label))
        layer = layer.base
    return _with_bases(parsed.world), tuple(files)


def parse_world(text: str, label: str, source: Path | None = None) -> World:
    """Parse and validate world-file text; ``label`` names it in error messages."""
    return _with_bases(_parse(text, label, source, ()).world)


@dataclass(frozen=True, slots=True)
class _Parsed:
    """A validated world (building bases not yet filled in) and where its entries are written."""

    world: World
    label: str
    index: LineIndex
    base: _Parsed | None

    def locate(self, table: str, entry: int, key: str | None) -> tuple[_Parsed, int]:
        """The file (this or a base) and line of ``key`` of the ``entry``-th ``table`` entry."""
        if self.base is not None:
            inherited = len(getattr(self.base.world, _ARRAY_FIELDS[table]))
            if entry < inherited:
                return self.base.locate(table, entry, key)
            entry -= inherited
        return self, self.index.line(table, entry, key)


def _load(path: Path, chain: tuple[Path, ...]) -> _Parsed:
    """Read and parse the world file ``path``; ``chain`` holds the files extending it."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise WorldError(
            [WorldIssue(str(path), 0, None, f"cannot read world file: {exc}")]
        ) from exc
    return _parse(text, str(path), path, chain)


def _parse(text: str, label: str, source: Path | None, chain: tuple[Path, ...]) -> _Parsed:
    """Parse and validate world-file text, merged with its base world if it extends one."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        found = _TOML_POSITION.search(message)
        if found and found.group(1):
            line, col = int(found.group(1)), int(found.group(2))
        else:  # "at end of document": point past the last character
            lines = text.splitlines() or [""]
            line, col = len(lines), len(lines[-1]) + 1
        reason = _TOML_POSITION.sub("", message).strip()
        raise WorldError([WorldIssue(label, line, col, f"syntax error: {reason}")]) from exc
    if source is not None:
        chain = (*chain, source.resolve())
    reader = _Reader(label, LineIndex.of(text), chain)
    parsed = reader.world(data, source)
    # Validation reports entries by index, which only matches the file when every entry was read.
    if parsed is not None and not reader.issues:
        for table, entry, key, reason in validate_world(parsed.world):
            owner, line = parsed.locate(table, entry, key)
            if owner is not parsed:  # a base entry clashing with this file's additions
                reason = f"{reason} (base world entry at {owner.label}:{line})"
                line = reader.index.line("world", 0, "extends")
            reader.issues.append(WorldIssue(label, line, None, reason))
    if reader.issues:
        raise WorldError(sorted(reader.issues, key=lambda i: i.line))
    assert parsed is not None  # no issues implies every part was read
    return parsed


class _Skip(Exception):
    """An entry could not be read; its issue is already recorded."""


class _Reader:
    """Turns parsed TOML into world dataclasses, recording issues with their lines."""

    def __init__(self, label: str, index: LineIndex, chain: tuple[Path, ...]) -> None:
        self.label = label
        self.index = index
        self.chain = chain
        self.issues: list[WorldIssue] = []

    def fail(self, table: str | None, entry: int, key: str | None, reason: str) -> _Skip:
        """Record an issue; return the exception that skips the current entry."""
        self.issues.append(WorldIssue(self.label, self.index.line(table, entry, key), None, reason))
        return _Skip()

    def world(self, data: dict[str, Any], source: Path | None) -> _Parsed | None:
        """Read the whole document, merged with its base; None if a required part is unusable."""
        for key in data:
            if key not in _TABLE_KEYS and key not in _ARRAY_KEYS:
                known = ", ".join(sorted([*_TABLE_KEYS, *_ARRAY_KEYS]))
                self.fail(key, 0, None, f"unknown section '{key}' (expected one of: {known})")
        head: dict[str, Any] = data["world"] if isinstance(data.get("world"), dict) else {}
        extends = "extends" in head
        base = self._guard(lambda: self._base(head["extends"], source)) if extends else None
        parts: dict[str, Any] = {}
        for table in _REQUIRED_TABLES:
            try:  # with a base, a missing [origin] or [terrain] is inherited
                parts[table] = self._table(data, table) if table in data or not extends else None
            except _Skip:
                parts[table] = None
        origin = self._guard(lambda: self._origin(parts["origin"]))
        terrain = self._guard(lambda: self._terrain(parts["terrain"]))
        name = self._guard(lambda: self._string(parts["world"], "world", 0, "name"))
        description = self._guard(
            lambda: self._string(parts["world"], "world", 0, "description", required=False)
        )
        background = self._guard(
            lambda: self._number(
                parts["world"],
                "world",
                0,
                "radiation_background",
                base.world.radiation_background if base else DEFAULT_BACKGROUND,
                0.0,
            )
        )
        readers: dict[str, Callable[[dict[str, Any], int], Any]] = {
            "building": self._building,
            "road": self._road,
            "vegetation": self._vegetation,
            "no_fly_zone": self._no_fly_zone,
            "place": self._place,
            "radiation_source": self._radiation_source,
            "pad": self._pad,
            "depot": self._depot,
            "object": self._object,
        }
        entries: dict[str, Any] = {
            field: (getattr(base.world, field) if base else ())
            + tuple(self._entries(data, table, readers[table]))
            for table, field in _ARRAY_FIELDS.items()
        }
        if base is not None:
            origin = origin if "origin" in data else base.world.origin
            terrain = terrain if "terrain" in data else base.world.terrain
            description = description if "description" in head else base.world.description
        if origin is None or terrain is None or name is None:
            return None
        world = World(
            name=name,
            origin=origin,
            terrain=terrain,
            **entries,
            radiation_background=DEFAULT_BACKGROUND if background is None else background,
            description=description or "",
            source=source,
        )
        return _Parsed(world, self.label, self.index, base)

    def _base(self, extends: object, source: Path | None) -> _Parsed:
        """Load the base world named by ``[world] extends``."""
        if not isinstance(extends, str) or not extends.strip():
            raise self.fail("world", 0, "extends", "world extends must be a world name or path")
        path = _base_path(extends, source)
        if path.resolve() in self.chain:
            cycle = " -> ".join(p.name for p in (*self.chain, path.resolve()))
            raise self.fail("world", 0, "extends", f"world extends itself: {cycle}")
        if len(self.chain) > MAX_EXTENDS:
            raise self.fail(
                "world", 0, "extends", f"more than {MAX_EXTENDS} nested base worlds (extends)"
            )
        try:
            return _load(path, self.chain)
        except WorldError as exc:
            raise self.fail(
                "world", 0, "extends", f"cannot load base world {extends!r}: {exc}"
            ) from None

    def _guard(self, read: Callable[[], _E]) -> _E | None:
        try:
            return read()
        except _Skip:
            return None

    # -- structure --------------------------------------------------------------------------

    def _table(self, data: dict[str, Any], table: str) -> dict[str, Any]:
        value = data.get(table)
        if value is None:
            raise self.fail(None, 0, None, f"missing required section [{table}]")
        if not isinstance(value, dict):
            raise self.fail(None, 0, table, f"'{table}' must be a table [{table}]")
        self._known_keys(value, table, 0, _TABLE_KEYS[table])
        return value

    def _known_keys(
        self, value: dict[str, Any], table: str, entry: int, keys: frozenset[str]
    ) -> None:
        for key in value:
            if key not in keys:
                raise self.fail(
                    table,
                    entry,
                    key,
                    f"unknown key '{key}' in {table} (expected one of: {', '.join(sorted(keys))})",
                )

    def _entries(
        self, data: dict[str, Any], table: str, read: Callable[[dict[str, Any], int], _E]
    ) -> Iterator[_E]:
        value = data.get(table, [])
        if not isinstance(value, list):
            self.fail(None, 0, table, f"'{table}' must be an array of tables [[{table}]]")
            return
        for entry, item in enumerate(value):
            if not isinstance(item, dict):
                self.fail(table, entry, None, f"{table} entry must be a table")
                continue
            try:
                self._known_keys(item, table, entry, _ARRAY_KEYS[table])
                yield read(item, entry)
            except _Skip:
                continue

    # -- scalars ----------------------------------------------------------------------------

    def _string(
        self, value: dict[str, Any] | None, table: str, entry: int, key: str, required: bool = True
    ) -> str:
        if value is None:
            raise _Skip()
        raw = value.get(key)
        if raw is None and not required:
            return ""
        if raw is None:
            raise self.fail(table, entry, None, f"{table} has no {key}")
        if not isinstance(raw, str) or (required and not raw.strip()):
            raise self.fail(table, entry, key, f"{table} {key} must be a non-empty string")
        return raw

    def _number(
        self,
        value: dict[str, Any] | None,
        table: str,
        entry: int,
        key: str,
        default: float | None = None,
        minimum: float | None = None,
        exclusive: bool = False,
    ) -> float:
        if value is None:
            raise _Skip()
        raw = value.get(key)
        what = f"{table} '{value['name']}'" if isinstance(value.get("name"), str) else table
        if raw is None:
            if default is not None:
                return default
            raise self.fail(table, entry, None, f"{what} has no {key}")
        if isinstance(raw, bool) or not isinstance(raw, int | float) or not math.isfinite(raw):
            raise self.fail(
                table, entry, key, f"{what}: {key} must be a finite number, got {raw!r}"
            )
        number = float(raw)
        if minimum is not None and (number <= minimum if exclusive else number < minimum):
            relation = ">" if exclusive else ">="
            raise self.fail(
                table, entry, key, f"{what}: {key} must be {relation} {minimum}, got {raw}"
            )
        return number

    def _points(
        self, value: dict[str, Any], table: str, entry: int, key: str, minimum: int
    ) -> tuple[Point2, ...]:
        raw = value.get(key)
        what = f"{table} '{value.get('name', value.get('id', '?'))}'"
        if raw is None:
            raise self.fail(table, entry, None, f"{what} has no {key}")
        if not isinstance(raw, list) or not all(_is_point(p) for p in raw):
            raise self.fail(
                table, entry, key, f"{what}: {key} must be a list of [east, north] pairs"
            )
        if len(raw) < minimum:
            raise self.fail(
                table, entry, key, f"{what}: {key} needs at least {minimum} points, got {len(raw)}"
            )
        return tuple((float(p[0]), float(p[1])) for p in raw)

    def _point(self, value: dict[str, Any], table: str, entry: int) -> Point2:
        raw = value.get("position")
        if raw is None:
            raise self.fail(table, entry, None, f"{table} has no position")
        if not _is_point(raw):
            raise self.fail(table, entry, "position", f"{table} position must be [east, north]")
        return float(raw[0]), float(raw[1])

    def _enum(
        self, value: dict[str, Any], table: str, entry: int, key: str, kind: type[enum_t]
    ) -> enum_t:
        raw = value.get(key)
        if raw is None:
            raise self.fail(table, entry, None, f"{table} has no {key}")
        options = ", ".join(m.value for m in kind)
        try:
            return kind(raw)
        except ValueError:
            raise self.fail(
                table, entry, key, f"unknown {table} {key} {raw!r} (expected one of: {options})"
            ) from None

    # -- sections ---------------------------------------------------------------------------

    def _origin(self, value: dict[str, Any] | None) -> GeodeticOrigin:
        lat = self._number(value, "origin", 0, "latitude")
        lon = self._number(value, "origin", 0, "longitude")
        alt = self._number(value, "origin", 0, "altitude")
        try:
            return GeodeticOrigin(lat, lon, alt)
        except ValueError as exc:
            key = "latitude" if "latitude" in str(exc) else "longitude"
            key = "altitude" if "altitude" in str(exc) else key
            raise self.fail("origin", 0, key, f"origin out of range: {exc}") from None

    def _terrain(self, value: dict[str, Any] | None) -> Terrain:
        east0 = self._number(value, "terrain", 0, "east0")
        north0 = self._number(value, "terrain", 0, "north0")
        spacing = self._number(value, "terrain", 0, "spacing", minimum=0.0, exclusive=True)
        assert value is not None  # _number skipped otherwise
        heights = value.get("heights")
        if not isinstance(heights, list) or not all(
            isinstance(r, list) and all(_is_number(h) for h in r) for r in heights
        ):
            raise self.fail(
                "terrain", 0, "heights", "terrain heights must be a list of rows of numbers"
            )
        try:
            grid = tuple(tuple(float(h) for h in row) for row in heights)
            return Terrain(east0, north0, spacing, grid)
        except ValueError as exc:
            raise self.fail("terrain", 0, "heights", f"bad terrain grid: {exc}") from None

    def _building(self, value: dict[str, Any], entry: int) -> Building:
        name = self._string(value, "building", entry, "name")
        footprint = self._points(value, "building", entry, "footprint", 3)
        height = self._number(value, "building", entry, "height", minimum=0.0, exclusive=True)
        base = (
            self._number(value, "building", entry, "base", default=math.nan)
            if "base" in value
            else math.nan
        )
        return Building(name, footprint, height, base)

    def _road(self, value: dict[str, Any], entry: int) -> Road:
        name = self._string(value, "road", entry, "name")
        points = self._points(value, "road", entry, "points", 2)
        width = self._number(value, "road", entry, "width", minimum=0.0, exclusive=True)
        return Road(name, points, width)

    def _vegetation(self, value: dict[str, Any], entry: int) -> Vegetation:
        name = self._string(value, "vegetation", entry, "name")
        polygon = self._points(value, "vegetation", entry, "polygon", 3)
        height = self._number(value, "vegetation", entry, "height", minimum=0.0, exclusive=True)
        return Vegetation(name, polygon, height)

    def _no_fly_zone(self, value: dict[str, Any], entry: int) -> NoFlyZone:
        name = self._string(value, "no_fly_zone", entry, "name")
        polygon = self._points(value, "no_fly_zone", entry, "polygon", 3)
        floor = self._number(value, "no_fly_zone", entry, "floor")
        ceiling = self._number(value, "no_fly_zone", entry, "ceiling")
        if ceiling <= floor:
            raise self.fail(
                "no_fly_zone",
                entry,
                "ceiling",
                f"no_fly_zone '{name}': ceiling {ceiling} must be above floor {floor}",
            )
        return NoFlyZone(name, polygon, floor, ceiling)

    def _place(self, value: dict[str, Any], entry: int) -> Place:
        name = self._string(value, "place", entry, "name")
        east, north = self._point(value, "place", entry)
        return Place(name, east, north)

    def _radiation_source(self, value: dict[str, Any], entry: int) -> RadiationSource:
        table = "radiation_source"
        name = self._string(value, table, entry, "name")
        east, north = self._point(value, table, entry)
        height = self._number(value, table, entry, "height", default=1.0, minimum=0.0)
        dose = self._number(value, table, entry, "dose_rate", minimum=0.0, exclusive=True)
        attenuation = self._number(
            value, table, entry, "attenuation", default=AIR_ATTENUATION, minimum=0.0
        )
        return RadiationSource(name, east, north, height, dose, attenuation)

    def _pad(self, value: dict[str, Any], entry: int) -> LandingPad:
        name = self._string(value, "pad", entry, "name")
        east, north = self._point(value, "pad", entry)
        radius = self._number(value, "pad", entry, "radius", minimum=0.0, exclusive=True)
        heading = self._number(value, "pad", entry, "heading_deg", default=0.0)
        pattern = value.get("pattern", False)
        if not isinstance(pattern, bool):
            raise self.fail("pad", entry, "pattern", "pad pattern must be true or false")
        if pattern and radius < PAD_HALF_WIDTH_M * math.sqrt(2.0):
            raise self.fail(
                "pad",
                entry,
                "radius",
                f"a pad with the landing pattern needs radius >= "
                f"{PAD_HALF_WIDTH_M * math.sqrt(2.0):.2f} m (the pattern's plate)",
            )
        return LandingPad(name, east, north, radius, math.radians(heading) % math.tau, pattern)

    def _depot(self, value: dict[str, Any], entry: int) -> Depot:
        name = self._string(value, "depot", entry, "name")
        kind = self._enum(value, "depot", entry, "type", DepotKind)
        east, north = self._point(value, "depot", entry)
        radius = self._number(value, "depot", entry, "radius", minimum=0.0, exclusive=True)
        return Depot(name, kind, east, north, radius)

    def _object(self, value: dict[str, Any], entry: int) -> DynamicObject:
        ident = self._string(value, "object", entry, "id")
        kind = self._enum(value, "object", entry, "type", ObjectKind)
        driving = kind is ObjectKind.CAR and "route" in value
        if driving:  # a driving car waits at its route's start, facing along it
            for key in ("position", "heading_deg"):
                if key in value:
                    raise self.fail(
                        "object",
                        entry,
                        key,
                        f"car '{ident}' drives a route: its start is the route's, leave out {key}",
                    )
            east, north, heading = 0.0, 0.0, 0.0
        else:
            east, north = self._point(value, "object", entry)
            heading = math.radians(self._number(value, "object", entry, "heading_deg", default=0.0))
        size = DEFAULT_SIZES[kind]
        if "size" in value:
            raw = value["size"]
            if not (
                isinstance(raw, list)
                and len(raw) == 3
                and all(_is_number(v) and v > 0 for v in raw)
            ):
                raise self.fail(
                    "object",
                    entry,
                    "size",
                    f"object '{ident}': size must be [length, width, height] > 0",
                )
            size = (float(raw[0]), float(raw[1]), float(raw[2]))
        allowed = _KIND_KEYS[kind]
        for key in ("temperature_c", "contents", "mass", "capacity", "on", *_CAR_KEYS):
            if key in value and key not in allowed:
                raise self.fail(
                    "object",
                    entry,
                    key,
                    f"object '{ident}': {key} does not apply to a {kind.value}",
                )
            if key not in value and key in _KIND_REQUIRED[kind]:
                raise self.fail("object", entry, None, f"{kind.value} '{ident}' has no {key}")
        temperature = (
            self._number(value, "object", entry, "temperature_c", minimum=-ZERO_CELSIUS)
            + ZERO_CELSIUS
            if "temperature_c" in value
            else None
        )
        contents = (
            self._enum(value, "object", entry, "contents", BoxContents)
            if "contents" in value
            else None
        )
        mass = (
            self._number(value, "object", entry, "mass", minimum=0.0, exclusive=True)
            if "mass" in value
            else None
        )
        capacity = None
        if "capacity" in value:
            raw_capacity = value["capacity"]
            if (
                isinstance(raw_capacity, bool)
                or not isinstance(raw_capacity, int)
                or raw_capacity < 1
            ):
                raise self.fail(
                    "object",
                    entry,
                    "capacity",
                    f"object '{ident}': capacity must be an integer >= 1",
                )
            capacity = raw_capacity
        on = self._string(value, "object", entry, "on") if "on" in value else None
        drive = self._drive(value, entry, ident) if kind is ObjectKind.CAR else None
        if drive is not None:
            start = DrivePlan.of(drive).pose(0.0)
            east, north, heading = start.east, start.north, start.heading
        paint = self._paint(value, entry, ident) if "paint" in value else None
        return DynamicObject(
            ident,
            kind,
            east,
            north,
            heading % math.tau,
            size,
            temperature,
            contents,
            mass,
            capacity,
            on,
            drive=drive,
            paint=paint,
        )

    def _drive(self, value: dict[str, Any], entry: int, ident: str) -> Drive | None:
        """A car's ``route``, ``speed``, ``loop`` and ``depart``; None for a parked car."""
        if "route" not in value:
            for key in ("speed", "loop", "depart"):
                if key in value:
                    raise self.fail(
                        "object", entry, key, f"car '{ident}': {key} applies to a car with a route"
                    )
            return None
        route = self._points(value, "object", entry, "route", 2)
        if "speed" not in value:
            raise self.fail("object", entry, None, f"car '{ident}' has a route but no speed")
        speed = value["speed"]
        if not _is_number(speed) or not 0.0 < speed <= MAX_SPEED:
            raise self.fail(
                "object",
                entry,
                "speed",
                f"car '{ident}': speed must be a number > 0 and <= {MAX_SPEED} m/s, got {speed!r}",
            )
        loop = value.get("loop", False)
        if not isinstance(loop, bool):
            raise self.fail("object", entry, "loop", f"car '{ident}': loop must be true or false")
        depart = value.get("depart", 0.0)
        if not _is_number(depart) or depart < 0.0:
            raise self.fail(
                "object",
                entry,
                "depart",
                f"car '{ident}': depart must be a number of seconds >= 0, got {depart!r}",
            )
        drive = Drive(route, float(speed), loop, float(depart))
        problem = drive_problem(drive)
        if problem is not None:
            raise self.fail("object", entry, "route", f"car '{ident}': {problem}")
        return drive

    def _paint(self, value: dict[str, Any], entry: int, ident: str) -> tuple[float, float, float]:
        raw = value["paint"]
        if not (
            isinstance(raw, list)
            and len(raw) == 3
            and all(_is_number(c) and 0 <= c <= 1 for c in raw)
        ):
            raise self.fail(
                "object",
                entry,
                "paint",
                f"object '{ident}': paint must be [red, green, blue], each 0..1, got {raw!r}",
            )
        return float(raw[0]), float(raw[1]), float(raw[2])


_CAR_KEYS = ("route", "speed", "loop", "depart", "paint")
"""Keys of a car only: its drive and its paint."""
_KIND_KEYS: dict[ObjectKind, frozenset[str]] = {
    ObjectKind.PERSON: frozenset({"temperature_c"}),
    ObjectKind.BOX: frozenset({"contents", "mass", "on"}),
    ObjectKind.CARRIER: frozenset({"capacity", "mass"}),
    ObjectKind.CAR: frozenset({"temperature_c", "mass", *_CAR_KEYS}),
    ObjectKind.DUMMY: frozenset({"temperature_c"}),
    ObjectKind.ANIMAL: frozenset({"temperature_c", "mass"}),
}
_KIND_REQUIRED: dict[ObjectKind, frozenset[str]] = {
    ObjectKind.PERSON: frozenset({"temperature_c"}),
    ObjectKind.BOX: frozenset({"contents", "mass"}),
    ObjectKind.CARRIER: frozenset({"capacity", "mass"}),
    ObjectKind.CAR: frozenset(),
    ObjectKind.DUMMY: frozenset(),
    ObjectKind.ANIMAL: frozenset({"temperature_c"}),
}


def _is_number(raw: object) -> bool:
    return isinstance(raw, int | float) and not isinstance(raw, bool) and math.isfinite(raw)


def _is_point(raw: object) -> bool:
    return isinstance(raw, list) and len(raw) == 2 and all(_is_number(v) for v in raw)


def _with_bases(world: World) -> World:
    """Fill in missing building bases with the lowest terrain height under the footprint."""
    buildings = tuple(
        b
        if math.isfinite(b.base)
        else replace(b, base=min(world.terrain.height(e, n) for e, n in b.footprint))
        for b in world.buildings
    )
    return replace(world, buildings=buildings)
