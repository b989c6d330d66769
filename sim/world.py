"""The simulated world: static geometry and dynamic objects, as loaded from a world file.

All coordinates are metres in the world's local ENU frame (east, north, up) relative to
:attr:`World.origin`; heights ``up`` are relative to the origin's altitude. Angles are radians;
headings clockwise from north. See ``sim/worlds/README.md`` for the file format and
:mod:`sim.world_loader` for loading and validation.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon

from sim.geodesy import GeodeticOrigin
from sim.terrain import Terrain

Point2 = tuple[float, float]
"""(east, north) in metres."""
AIR_ATTENUATION = 0.0093
"""1/m, default linear attenuation of a radiation source's gamma rays in air (Cs-137, 662 keV:
0.0775 cm2/g x 1.205 kg/m3)."""
DEFAULT_BACKGROUND = 0.1
"""microsievert per hour, default natural background of a world."""


class ObjectKind(enum.Enum):
    """Kinds of dynamic objects (mission items of chapter section 11.1)."""

    PERSON = "person"
    BOX = "box"
    CARRIER = "carrier"
    CAR = "car"
    DUMMY = "dummy"
    """Person-shaped mannequin without body heat (a false target for body detection)."""
    ANIMAL = "animal"
    """A warm four-legged animal (a thermal distractor, section 11.1.1)."""


class BoxContents(enum.Enum):
    """What a supply box holds (section 11.1.2: food and medical supplies)."""

    FOOD = "food"
    MEDICINE = "medicine"
    WATER = "water"


class DepotKind(enum.Enum):
    """Depot types of section 11.1.2 (Figure 37)."""

    SUPPLY = "supply"
    CARRIER = "carrier"


@dataclass(frozen=True, slots=True)
class Building:
    """A building: footprint polygon extruded from ``base`` up to ``base + height``."""

    name: str
    footprint: tuple[Point2, ...]
    height: float
    base: float
    """Ground elevation under the building, m (local up)."""

    @property
    def top(self) -> float:
        """Roof elevation, m (local up)."""
        return self.base + self.height


@dataclass(frozen=True, slots=True)
class Road:
    """A road: centre polyline with a width."""

    name: str
    points: tuple[Point2, ...]
    width: float


@dataclass(frozen=True, slots=True)
class Vegetation:
    """Trees or bushes: a polygon with a canopy height above the ground."""

    name: str
    polygon: tuple[Point2, ...]
    height: float


@dataclass(frozen=True, slots=True)
class NoFlyZone:
    """A forbidden region (section 7.1.2): polygon between floor and ceiling (local up, m)."""

    name: str
    polygon: tuple[Point2, ...]
    floor: float
    ceiling: float


@dataclass(frozen=True, slots=True)
class Place:
    """A named point of interest."""

    name: str
    east: float
    north: float


@dataclass(frozen=True, slots=True)
class LandingPad:
    """A helicopter start/landing pad (H1, H2 in Figure 33B)."""

    name: str
    east: float
    north: float
    radius: float
    heading: float
    """Preferred heading on the pad, rad clockwise from north."""
    pattern: bool = False
    """Whether the pad carries the vision landing pattern (``sim.landing_pattern``, §5.4)."""


@dataclass(frozen=True, slots=True)
class Depot:
    """A supply or carrier depot: a circular area where boxes or carriers are stored."""

    name: str
    kind: DepotKind
    east: float
    north: float
    radius: float


@dataclass(frozen=True, slots=True)
class RadiationSource:
    """A gamma point source (the chapter's damaged reactor, section 9.4's Fukushima examples)."""

    name: str
    east: float
    north: float
    height: float
    """m above the ground under it."""
    dose_rate: float
    """microsievert per hour at 1 m, before air attenuation."""
    attenuation: float
    """1/m, linear attenuation of the gamma rays in air (0.0093 for Cs-137's 662 keV)."""


@dataclass(frozen=True, slots=True)
class Drive:
    """A car's drive along a route of road waypoints (kinematics: :mod:`sim.drive`).

    The car sets off from rest at the first waypoint at sim time ``depart``, cruises at
    ``speed`` on straights, slows for the rounded corners and stops at the last waypoint, or,
    with ``loop``, drives on from the last waypoint back to the first, lap after lap.
    """

    route: tuple[Point2, ...]
    """Waypoints (east, north), m: road centre-line points, at least 2 (3 for a loop)."""
    speed: float
    """Cruise speed on straights, m/s (0 < speed <= ``sim.drive.MAX_SPEED``)."""
    loop: bool = False
    depart: float = 0.0
    """Sim time the car sets off, s (>= 0); it waits at the first waypoint until then."""


@dataclass(frozen=True, slots=True)
class DynamicObject:
    """A movable object: person, dummy or animal on the ground, supply box, carrier or car.

    Kind-specific properties are ``None`` where they do not apply: ``temperature`` (surface
    temperature seen by the thermal camera, K) for persons, dummies, animals and cars,
    ``contents`` for boxes, ``capacity`` (boxes) for carriers; ``mass`` for boxes, carriers,
    cars and animals; ``on`` for a box that rests on a carrier at the start; ``drive`` and
    ``paint`` for cars. A driving car's ``east``, ``north`` and ``heading`` are its pose when
    it waits to set off (sim time 0); :meth:`sim.world_sim.WorldSim.object_poses` gives it now.
    """

    id: str
    kind: ObjectKind
    east: float
    north: float
    heading: float
    size: tuple[float, float, float]
    """Length, width, height in metres (length along ``heading``)."""
    temperature: float | None = None
    contents: BoxContents | None = None
    mass: float | None = None
    capacity: int | None = None
    on: str | None = None
    """The carrier a box rests on at the start (its position is a place on that carrier)."""
    drive: Drive | None = None
    """How a car drives (None: it stays where it is)."""
    paint: tuple[float, float, float] | None = None
    """A car's body colour, linear RGB in [0, 1] (None: the renderer picks one by its id)."""


@dataclass(frozen=True, slots=True)
class World:
    """A complete world: origin, terrain, static geometry, named places and dynamic objects."""

    name: str
    origin: GeodeticOrigin
    terrain: Terrain
    buildings: tuple[Building, ...] = ()
    roads: tuple[Road, ...] = ()
    vegetation: tuple[Vegetation, ...] = ()
    no_fly_zones: tuple[NoFlyZone, ...] = ()
    places: tuple[Place, ...] = ()
    pads: tuple[LandingPad, ...] = ()
    depots: tuple[Depot, ...] = ()
    objects: tuple[DynamicObject, ...] = ()
    radiation_sources: tuple[RadiationSource, ...] = ()
    radiation_background: float = DEFAULT_BACKGROUND
    """microsievert per hour everywhere (natural background)."""
    description: str = ""
    source: Path | None = field(default=None, compare=False)
    """File the world was loaded from (None for worlds built in code)."""

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(east_min, north_min, east_max, north_max): the terrain grid's extent."""
        return self.terrain.bounds

    def vegetation_top(self, vegetation: Vegetation) -> tuple[float, float]:
        """Base and canopy top of a vegetation area, m: the ground at its centroid + height."""
        centroid = Polygon(vegetation.polygon).centroid
        base = self.terrain.height(centroid.x, centroid.y)
        return base, base + vegetation.height

    def surface_heights(
        self, east: NDArray[np.float64], north: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Top of whatever stands at each point (terrain, a roof, a canopy), m local up.

        The surface a laser sees from above and an elevation map is compared with (section
        11.2). Vectorised over points of any shape.
        """
        e, n = np.asarray(east, dtype=np.float64), np.asarray(north, dtype=np.float64)
        top = np.asarray(self.terrain.heights_at(e.ravel(), n.ravel()), dtype=np.float64)
        solids = [(Polygon(b.footprint), b.top) for b in self.buildings]
        solids += [(Polygon(v.polygon), self.vegetation_top(v)[1]) for v in self.vegetation]
        for polygon, height in solids:
            inside = shapely.contains_xy(polygon, e.ravel(), n.ravel())
            top[inside] = np.maximum(top[inside], height)
        return top.reshape(e.shape)

    def pad(self, name: str) -> LandingPad:
        """Return the landing pad called ``name`` (KeyError if none)."""
        for pad in self.pads:
            if pad.name == name:
                return pad
        raise KeyError(name)

    def place(self, name: str) -> Place:
        """Return the named place called ``name`` (KeyError if none)."""
        for place in self.places:
            if place.name == name:
                return place
        raise KeyError(name)

    def depot(self, name: str) -> Depot:
        """Return the depot called ``name`` (KeyError if none)."""
        for depot in self.depots:
            if depot.name == name:
                return depot
        raise KeyError(name)

    def objects_of(self, kind: ObjectKind) -> tuple[DynamicObject, ...]:
        """All dynamic objects of one kind, in file order."""
        return tuple(o for o in self.objects if o.kind is kind)
