"""The certainty map: merging by distance, T_frame / T_body, thresholds, dropped frames, memory,
GeoJSON."""

from __future__ import annotations

import json
import math

import numpy as np
import pymap3d
import pytest

from hdrc3_perception.saliency_map import (
    MapError,
    MapParams,
    SaliencyMap,
    dumps_geojson,
    locations_from_geojson,
    to_geojson,
)
from sim.geodesy import GeodeticOrigin

A = np.array([10.0, 20.0, 0.0])
B = np.array([30.0, -5.0, 0.0])
D1 = np.array([1.5, -1.0, 0.0])
D2 = np.array([1.0, 1.0, 0.0])


def all_visible(points: np.ndarray) -> np.ndarray:
    return np.ones(len(points), dtype=bool)


def run(frames: list[list[np.ndarray]], params: MapParams | None = None) -> SaliencyMap:
    saliency = SaliencyMap(params)
    for i, positives in enumerate(frames):
        saliency.update(i * 0.04, all_visible, positives)
    return saliency


@pytest.mark.parametrize(
    ("frames", "expected"),
    [
        # (positives per frame, [(t_frame, t_body, confirmed)] per location)
        ([[A]] * 6, [(6, 6, True)]),
        ([[A]] * 3, [(3, 3, True)]),
        ([[A]] * 2, [(2, 2, False)]),  # not observed long enough
        ([[A], [A], []], [(3, 2, True)]),  # two positives in three frames
        ([[A], [], []], [(3, 1, False)]),  # one weak classification is never a body
        ([[A], [], [A], [], [A], []], [(6, 3, False)]),  # p_body 0.5 is not > 0.5
        ([[A], [A], [], [A], [], [A], [A]], [(7, 5, True)]),
        (
            [[A], [A + D1], [A - D2]] * 2,
            [(6, 6, True)],
        ),  # merged
        ([[A, B]] * 5 + [[B]] * 5, [(10, 5, False), (10, 10, True)]),
        (
            [[A, A + np.array((0.5, 0.0, 0.0))]] * 5,
            [(5, 5, True)],
        ),  # two regions on one body, one frame
    ],
)
def test_certainty(frames: list[list[np.ndarray]], expected: list[tuple[int, int, bool]]) -> None:
    saliency = run(frames)
    got = [(loc.t_frame, loc.t_body, loc.confirmed(saliency.params)) for loc in saliency.locations]
    assert got == expected
    assert all(loc.p_body == loc.t_body / loc.t_frame for loc in saliency.locations)


def test_the_position_is_the_mean_of_the_observations() -> None:
    offsets = [(1.0, 0.0, 0.0), (-1.0, 0.5, 0.0), (0.0, -0.5, 0.0), (0.4, 0.2, 0.0)]
    saliency = run([[A + o] for o in offsets])
    (loc,) = saliency.locations
    mean = A + np.mean(offsets, axis=0)
    assert (loc.east, loc.north, loc.up) == pytest.approx(tuple(mean))
    assert loc.observations == 4
    assert loc.first_seen == 0.0


def test_only_frames_that_see_a_location_count() -> None:
    saliency = SaliencyMap()
    saliency.update(0.0, all_visible, [A])
    for i in range(1, 10):
        saliency.update(i * 0.04, lambda p: np.zeros(len(p), dtype=bool), [])  # A out of view
    (loc,) = saliency.locations
    assert (loc.t_frame, loc.t_body) == (1, 1)


def test_dropped_frames_change_counts_not_certainty() -> None:
    pattern = [[A], [A], [], [A]] * 6
    full = run(pattern)
    dropped = run(pattern[::2])  # every other frame lost
    (f,), (d,) = full.locations, dropped.locations
    assert f.p_body == pytest.approx(0.75)
    assert d.p_body == pytest.approx(0.5)  # the frames that arrived: [A], [] repeated
    kept = run([p for i, p in enumerate(pattern) if i % 4 != 2])  # only the empty frames lost
    assert kept.locations[0].p_body == 1.0
    assert full.locations[0].confirmed(full.params) and kept.locations[0].confirmed(kept.params)


@pytest.mark.parametrize(
    ("time", "positives"),
    [(0.0, []), (-1.0, []), (1.0, [np.array([1.0, math.nan, 0.0])]), (1.0, [np.zeros(2)])],
)
def test_misuse_raises(time: float, positives: list[np.ndarray]) -> None:
    saliency = SaliencyMap()
    saliency.update(0.0, all_visible, [A])
    with pytest.raises(MapError):
        saliency.update(time, all_visible, positives)
    assert len(saliency) == 1 and saliency.last_time == 0.0


def test_memory_is_bounded_and_keeps_the_confirmed() -> None:
    saliency = SaliencyMap(MapParams(max_locations=10, min_frames=2))
    t = 0.0
    for _ in range(3):
        t += 0.04
        saliency.update(t, all_visible, [A])
    for i in range(50):  # a stream of one-off false positives far apart
        t += 0.04
        saliency.update(
            t, lambda p: np.zeros(len(p), dtype=bool), [np.array([100.0 + 10 * i, 0, 0])]
        )
    assert len(saliency) == 10
    assert [loc.east for loc in saliency.confirmed()] == [A[0]]


def test_geojson() -> None:
    origin = GeodeticOrigin(55.72, 13.54, 60.0)
    saliency = run([[A, B]] * 6 + [[A]] * 6)
    doc = json.loads(dumps_geojson(saliency, origin))
    assert doc["type"] == "FeatureCollection"
    features = doc["features"]
    assert [f["properties"]["confirmed"] for f in features] == [True, False]
    props = features[0]["properties"]
    assert (props["t_frame"], props["t_body"], props["p_body"]) == (12, 12, 1.0)
    lon, lat = features[0]["geometry"]["coordinates"]
    assert (props["lon"], props["lat"]) == (lon, lat)
    east, north, _ = pymap3d.geodetic2enu(lat, lon, props["alt"], 55.72, 13.54, 60.0)
    assert (east, north) == pytest.approx((A[0], A[1]), abs=1e-6)
    only = json.loads(dumps_geojson(saliency, origin, only_confirmed=True))
    assert len(only["features"]) == 1


def test_maps_of_two_aircraft_merge_where_both_saw_a_body() -> None:
    origin = GeodeticOrigin(55.72, 13.54, 60.0)
    west = run([[A]] * 3 + [[]] * 2)  # uav0 saw A at the edge of its band: 5 frames, 3 positive
    east = run([[A + D1, B]] * 2 + [[A + D1]] * 2)  # uav1 saw A (1.8 m off) and B
    merged = SaliencyMap()
    for one in (west, east):
        merged.absorb(locations_from_geojson(json.loads(dumps_geojson(one, origin))))
    counts = sorted((loc.t_frame, loc.t_body) for loc in merged.locations)
    assert counts == [(4, 2), (9, 7)]
    a = next(loc for loc in merged.locations if loc.t_frame == 9)
    # the mean of the 3 + 4 observations
    assert (a.east, a.north) == pytest.approx(tuple((3 * A + 4 * (A + D1))[:2] / 7))
    assert len(merged.confirmed()) == 1  # A: 7 of 9 frames; B: 2 of 4 (p_body 0.5)
    assert to_geojson(merged, origin)["features"][0]["properties"]["up"] == pytest.approx(0.0)


@pytest.mark.parametrize(
    ("data", "words"),
    [
        ([], "FeatureCollection"),
        ({"type": "FeatureCollection"}, "list of features"),
        ({"type": "FeatureCollection", "features": [{"type": "Feature"}]}, "feature 0"),
        (
            {"type": "FeatureCollection", "features": [{"properties": {"east": 1.0}}]},
            "feature 0: needs finite",
        ),
    ],
)
def test_a_bad_map_is_refused_with_a_reason(data: object, words: str) -> None:
    with pytest.raises(MapError, match=words):
        locations_from_geojson(data)
