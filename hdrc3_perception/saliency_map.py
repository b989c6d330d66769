"""The saliency (certainty) map of Algorithm 4, lines 9-14 (§11.1.1).

Every salient location carries T_frame, the number of processed frames in which the location
was in view of both cameras, and T_body, the number of those frames in which the classifier said
"body" there; its certainty is p_body = T_body / T_frame. The chapter measures both as times; at
a fixed frame rate counts are the same ratio, and counting processed frames keeps the ratio
right when frames are dropped (a dropped frame adds to neither). A location is a body when
p_body > 0.5 (the chapter's flight-test value) and T_frame reaches a minimum observation
(chapter: "a desired minimal observation time"; here :attr:`MapParams.min_frames`). Detections
closer than the merge distance are one location, whose position is the mean of its
observations. Memory is bounded: past ``max_locations`` the least certain unconfirmed location
is dropped.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import pymap3d
from numpy.typing import NDArray

from hdrc3_base.errors import Hdrc3Error


class MapError(Hdrc3Error):
    """The map was misused (non-finite location, time running backwards)."""


class Origin(Protocol):
    """A geodetic origin (the world's, e.g. ``World.origin``): degrees and metres, WGS84."""

    @property
    def latitude(self) -> float: ...  # noqa: D102

    @property
    def longitude(self) -> float: ...  # noqa: D102

    @property
    def altitude(self) -> float: ...  # noqa: D102


@dataclass(frozen=True, slots=True)
class MapParams:
    """Certainty thresholds and merging."""

    merge_distance: float = 4.0
    """m: detections closer than this are one location (the chapter's ~2.5 m spread)."""
    p_threshold: float = 0.5
    min_frames: int = 3
    """T_frame needed before a location can be confirmed. A person is in view (1 m inside the
    thermal camera's 10 m along-track footprint) for 1.6 s of a 5 m/s scan at 30 m; the launched
    chain processed 2-9 pairs/s of that on the loaded 2-core machine, and one leg I run left
    body03 at T_frame 3 (2 positives) with 5 as the minimum. Three frames still need two
    positives, so a single weak classification is never confirmed."""
    max_locations: int = 5000


@dataclass(slots=True)
class Location:
    """One salient point: mean position (ENU, m) and its counters."""

    ident: int
    east: float
    north: float
    up: float
    t_frame: int
    t_body: int
    first_seen: float
    """Sim time of the first positive classification, s."""
    observations: int = 1

    @property
    def p_body(self) -> float:
        """Certainty T_body / T_frame."""
        return self.t_body / self.t_frame if self.t_frame else 0.0

    def confirmed(self, params: MapParams) -> bool:
        """True if the location counts as a body."""
        return self.p_body > params.p_threshold and self.t_frame >= params.min_frames


VisibleFn = Callable[[NDArray[np.float64]], NDArray[np.bool_]]
"""Mask of the ENU points (N, 3) in view of the frame's cameras."""


@dataclass(frozen=True, slots=True)
class FrameUpdate:
    """What one frame did to the map."""

    seen: int
    """Known locations in view (their T_frame grew)."""
    added: int
    merged: int


class SaliencyMap:
    """Locations with T_frame / T_body, merged by distance."""

    def __init__(self, params: MapParams | None = None) -> None:
        self.params = params or MapParams()
        self._locations: dict[int, Location] = {}
        self._next = 0
        self.last_time = -math.inf

    def __len__(self) -> int:
        return len(self._locations)

    @property
    def locations(self) -> list[Location]:
        """All locations, oldest first."""
        return list(self._locations.values())

    def confirmed(self) -> list[Location]:
        """Locations that count as bodies."""
        return [loc for loc in self._locations.values() if loc.confirmed(self.params)]

    def positions(self) -> NDArray[np.float64]:
        """(N, 3) ENU positions in :attr:`locations` order."""
        locs = self._locations.values()
        return np.array([(loc.east, loc.north, loc.up) for loc in locs]).reshape(-1, 3)

    def update(
        self, time: float, visible: VisibleFn, positives: Sequence[NDArray[np.float64]]
    ) -> FrameUpdate:
        """Account one processed frame (Algorithm 4, lines 9-14).

        Args:
            time: Sim time of the frame, s; must grow from frame to frame.
            visible: Which ENU points the frame's cameras saw.
            positives: Ground points (3,) the classifier said "body" at in this frame.

        Raises:
            MapError: time did not grow, or a positive is not finite.
        """
        if not time > self.last_time:
            raise MapError(f"frame time {time} not after the last frame's {self.last_time}")
        if any(p.shape != (3,) or not np.all(np.isfinite(p)) for p in positives):
            raise MapError("positives must be finite ENU points")
        self.last_time = time
        locs = list(self._locations.values())
        if locs:
            mask = visible(self.positions())
            for loc, seen in zip(locs, mask, strict=True):
                loc.t_frame += int(seen)
            seen_count = int(np.count_nonzero(mask))
        else:
            seen_count = 0
        added = merged = 0
        credited: set[int] = set()
        for point in positives:
            target = self._nearest(point)
            if target is None:
                credited.add(self._add(point, time))
                added += 1
                continue
            merged += 1
            if target.ident not in credited:  # two regions on one body count one frame
                credited.add(target.ident)
                target.t_body += 1
                target.t_frame = max(target.t_frame, target.t_body)
            n = target.observations + 1
            target.east += (float(point[0]) - target.east) / n
            target.north += (float(point[1]) - target.north) / n
            target.up += (float(point[2]) - target.up) / n
            target.observations = n
        return FrameUpdate(seen_count, added, merged)

    def absorb(self, locations: Sequence[Location]) -> None:
        """Merge another map's locations (another aircraft's): by distance, as detections are.

        A location within the merge distance of one of ours adds its frame and body counts to
        it (both aircraft saw the place) and moves it to the observation-weighted mean; any
        other is added.
        """
        for other in locations:
            target = self._nearest(np.array([other.east, other.north, other.up]))
            if target is None:
                ident = self._add(np.array([other.east, other.north, other.up]), other.first_seen)
                loc = self._locations[ident]
                loc.t_frame, loc.t_body = other.t_frame, other.t_body
                loc.observations = other.observations
                continue
            n = target.observations + other.observations
            for axis in ("east", "north", "up"):
                mean = (
                    getattr(target, axis) * target.observations
                    + getattr(other, axis) * other.observations
                ) / n
                setattr(target, axis, mean)
            target.t_frame += other.t_frame
            target.t_body += other.t_body
            target.first_seen = min(target.first_seen, other.first_seen)
            target.observations = n

    def _nearest(self, point: NDArray[np.float64]) -> Location | None:
        best: Location | None = None
        best_d = self.params.merge_distance
        for loc in self._locations.values():
            d = math.hypot(loc.east - point[0], loc.north - point[1])
            if d < best_d:
                best, best_d = loc, d
        return best

    def _add(self, point: NDArray[np.float64], time: float) -> int:
        if len(self._locations) >= self.params.max_locations:
            self._evict()
        loc = Location(self._next, float(point[0]), float(point[1]), float(point[2]), 1, 1, time)
        self._locations[loc.ident] = loc
        self._next += 1
        return loc.ident

    def _evict(self) -> None:
        params = self.params
        candidates = [loc for loc in self._locations.values() if not loc.confirmed(params)]
        pool = candidates or list(self._locations.values())
        victim = min(pool, key=lambda loc: (loc.p_body, loc.t_body, -loc.ident))
        del self._locations[victim.ident]


def to_geojson(
    saliency: SaliencyMap, origin: Origin, only_confirmed: bool = False
) -> dict[str, Any]:
    """The map as a GeoJSON FeatureCollection of Points (lon, lat of the world's origin)."""
    features = []
    for loc in saliency.locations:
        confirmed = loc.confirmed(saliency.params)
        if only_confirmed and not confirmed:
            continue
        lat, lon, alt = pymap3d.enu2geodetic(
            loc.east, loc.north, loc.up, origin.latitude, origin.longitude, origin.altitude
        )
        features.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [float(lon), float(lat)]},
                "properties": {
                    "id": loc.ident,
                    "lon": float(lon),
                    "lat": float(lat),
                    "alt": float(alt),
                    "east": loc.east,
                    "north": loc.north,
                    "up": loc.up,
                    "p_body": loc.p_body,
                    "t_frame": loc.t_frame,
                    "t_body": loc.t_body,
                    "first_seen": loc.first_seen,
                    "confirmed": confirmed,
                },
            }
        )
    return {"type": "FeatureCollection", "features": features}


def dumps_geojson(saliency: SaliencyMap, origin: Origin, only_confirmed: bool = False) -> str:
    """:func:`to_geojson` as text."""
    return json.dumps(to_geojson(saliency, origin, only_confirmed), indent=1)


_COUNTS = ("t_frame", "t_body")
_FLOATS = ("east", "north", "up", "first_seen")


def locations_from_geojson(data: Any) -> list[Location]:
    """The locations of a map written by :func:`to_geojson` (another node's, a file).

    Raises:
        MapError: not a FeatureCollection of this module's points, naming the first bad feature.
    """
    if not isinstance(data, dict) or data.get("type") != "FeatureCollection":
        raise MapError("not a GeoJSON FeatureCollection")
    features = data.get("features")
    if not isinstance(features, list):
        raise MapError("the FeatureCollection has no list of features")
    locations = []
    for index, feature in enumerate(features):
        props = feature.get("properties") if isinstance(feature, dict) else None
        if not isinstance(props, dict):
            raise MapError(f"feature {index}: no properties")
        numbers = [
            float(v)
            for key in _FLOATS
            if isinstance(v := props.get(key), int | float) and math.isfinite(v)
        ]
        counts = [v for key in _COUNTS if isinstance(v := props.get(key), int) and v >= 0]
        if len(numbers) != len(_FLOATS) or len(counts) != len(_COUNTS):
            raise MapError(f"feature {index}: needs finite {_FLOATS} and counts {_COUNTS} >= 0")
        east, north, up, first_seen = numbers
        t_frame, t_body = counts
        locations.append(
            Location(index, east, north, up, t_frame, t_body, first_seen, max(1, t_body))
        )
    return locations
