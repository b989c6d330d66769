"""Fixtures shared by the unit tests: the small navigation world, its GIS and a roadmap built once
per session (the navigation and the TST fly-to tests plan in it)."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_navigation.gis import Gis
from hdrc3_navigation.planner import PathPlanner
from hdrc3_navigation.roadmap import Roadmap, RoadmapCache
from sim.world import World
from sim.world_loader import load_world

SMALL_WORLD = Path(__file__).parent / "hdrc3_navigation" / "small_world.toml"
ROADMAP_NODES = 400


@pytest.fixture(scope="session")
def small_world() -> World:
    return load_world(SMALL_WORLD)


@pytest.fixture(scope="session")
def roadmap_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("roadmaps")


@pytest.fixture(scope="session")
def small_roadmap(small_world: World, roadmap_dir: Path) -> Roadmap:
    roadmap, _ = RoadmapCache(roadmap_dir).load_or_build(Gis(small_world), ROADMAP_NODES)
    return roadmap


@pytest.fixture
def planner(small_world: World, roadmap_dir: Path, small_roadmap: Roadmap) -> PathPlanner:
    """A planner on a fresh GIS (runtime updates stay in one test) and the session roadmap."""
    out = PathPlanner(Gis(small_world), roadmap_dir, roadmap_nodes=ROADMAP_NODES)
    assert out.roadmap()[0].key == small_roadmap.key
    return out
