from __future__ import annotations

import os
from pathlib import Path

import pytest

from hdrc3_tst.worlds import WorldCache, world_facts
from sim.world_loader import WorldError, load_world, world_path

BASE = (world_path("revinge")).read_text(encoding="utf-8")
VARIANT = '[world]\nname = "variant"\nextends = "base.toml"\n'
SPOT = '[[place]]\nname = "spot"\nposition = [50.0, 50.0]\n'


def _bump(path: Path, text: str) -> None:
    """Rewrite a file with a later modification time (the tick may be coarse)."""
    before = path.stat().st_mtime_ns
    path.write_text(text, encoding="utf-8")
    os.utime(path, ns=(before + 10**9, before + 10**9))


def test_the_facts_are_the_loaded_world_s() -> None:
    facts = WorldCache().facts("revinge")
    world = load_world("revinge")
    assert facts == world_facts(world)
    assert facts.extent.bounds == world.bounds
    assert {p.name for p in world.pads} <= set(facts.places)


@pytest.mark.parametrize(
    ("change", "loads"),
    [
        ("nothing", 1),
        ("the world file", 2),
        ("its base", 2),
    ],
)
def test_a_world_is_loaded_again_only_when_one_of_its_files_changed(
    tmp_path: Path, change: str, loads: int
) -> None:
    base, variant = tmp_path / "base.toml", tmp_path / "variant.toml"
    base.write_text(BASE, encoding="utf-8")
    variant.write_text(VARIANT, encoding="utf-8")
    cache = WorldCache()
    first = cache.facts(variant)
    assert "spot" not in first.places
    if change == "the world file":
        _bump(variant, VARIANT + SPOT)
    elif change == "its base":
        _bump(base, BASE + SPOT)
    second = cache.facts(str(variant))
    assert cache.loads == loads
    assert ("spot" in second.places) is (change != "nothing")
    assert (second is first) is (change == "nothing")


def test_a_world_whose_base_is_gone_no_longer_loads(tmp_path: Path) -> None:
    base, variant = tmp_path / "base.toml", tmp_path / "variant.toml"
    base.write_text(BASE, encoding="utf-8")
    variant.write_text(VARIANT, encoding="utf-8")
    cache = WorldCache()
    cache.facts(variant)
    base.unlink()
    with pytest.raises(WorldError):
        cache.facts(variant)


def test_a_world_that_does_not_load_is_not_kept(tmp_path: Path) -> None:
    cache = WorldCache()
    with pytest.raises(WorldError):
        cache.facts(tmp_path / "missing.toml")
    assert cache.loads == 0
