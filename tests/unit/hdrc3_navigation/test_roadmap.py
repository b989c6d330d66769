from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from hdrc3_navigation.gis import Gis
from hdrc3_navigation.roadmap import Roadmap, RoadmapCache, build_roadmap, cache_key
from sim.world import World
from sim.world_loader import load_world


def test_roadmap_nodes_and_edges_are_clear_of_the_static_world(
    small_world: World, small_roadmap: Roadmap
) -> None:
    gis = Gis(small_world)
    n, m = small_roadmap.size
    assert n >= 400 and m > n
    assert all(gis.point_free(p) for p in small_roadmap.nodes)
    rng = np.random.default_rng(0)
    for k in rng.choice(m, 200, replace=False):
        i, j = small_roadmap.edges[k]
        assert gis.segment_free(small_roadmap.nodes[i], small_roadmap.nodes[j])


def test_cache_round_trip(small_roadmap: Roadmap, tmp_path: Path) -> None:
    cache = RoadmapCache(tmp_path)
    cache.save(small_roadmap)
    loaded = cache.load(small_roadmap.key)
    assert loaded is not None
    assert np.array_equal(loaded.nodes, small_roadmap.nodes)
    assert np.array_equal(loaded.edges, small_roadmap.edges)
    assert cache.load("another-key") is None


def _garbage(path: Path) -> None:
    path.write_bytes(b"not a roadmap")


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[:200])


def _tamper(path: Path) -> None:
    with np.load(path) as data:
        nodes, edges, meta = data["nodes"].copy(), data["edges"], data["meta"]
    nodes[0, 2] += 100.0  # checksum no longer matches
    np.savez(path, nodes=nodes, edges=edges, meta=meta)


def _wrong_key(path: Path) -> None:
    with np.load(path) as data:
        nodes, edges, meta = data["nodes"], data["edges"], json.loads(str(data["meta"]))
    meta["key"] = "x"
    np.savez(path, nodes=nodes, edges=edges, meta=np.array(json.dumps(meta)))


@pytest.mark.parametrize("damage", [_garbage, _truncate, _tamper, _wrong_key])
def test_a_corrupt_cache_is_rebuilt_not_trusted(
    small_world: World, small_roadmap: Roadmap, tmp_path: Path, damage: Callable[[Path], None]
) -> None:
    gis = Gis(small_world)
    cache = RoadmapCache(tmp_path)
    path = cache.save(small_roadmap)
    damage(path)
    assert cache.load(small_roadmap.key) is None
    rebuilt, built = cache.load_or_build(gis, 60)
    assert built and rebuilt.size[0] >= 60
    again, built_again = cache.load_or_build(gis, 60)
    assert not built_again and np.array_equal(again.nodes, rebuilt.nodes)


def test_the_key_follows_the_world_content_and_parameters(
    small_world: World, tmp_path: Path
) -> None:
    gis = Gis(small_world)
    assert cache_key(gis, 400, 10) == cache_key(Gis(small_world), 400, 10)
    assert cache_key(gis, 400, 10) != cache_key(gis, 500, 10)
    assert cache_key(gis, 400, 10) != cache_key(Gis(small_world, margin=5.0), 400, 10)
    assert small_world.source is not None
    changed = tmp_path / "changed.toml"
    changed.write_text(small_world.source.read_text().replace("height = 25.0", "height = 26.0"))
    assert cache_key(Gis(load_world(changed)), 400, 10) != cache_key(gis, 400, 10)


def test_build_grows_to_the_requested_size(small_world: World) -> None:
    heard: list[tuple[int, int]] = []
    roadmap = build_roadmap(
        Gis(small_world), nodes=50, neighbours=5, progress=lambda n, w: heard.append((n, w))
    )
    assert roadmap.size[0] >= 50
    assert heard and heard[-1] == (50, 50) and all(w == 50 and n <= 50 for n, w in heard)
    assert roadmap.build_seconds > 0.0
    assert all(len(a) > 0 for a in roadmap.adjacency[:10]) or roadmap.size[1] > 0
