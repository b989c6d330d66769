"""`hdrc3 world`: list the shipped worlds, check world files, generate seeded variations."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from hdrc3_base.errors import ConfigError
from sim.world import ObjectKind
from sim.world_generator import Population, generated_world
from sim.world_loader import WorldError, load_world, shipped_worlds


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``world`` subcommand."""
    parser = subparsers.add_parser("world", help="list shipped worlds, validate world files")
    actions = parser.add_subparsers(dest="world_action", metavar="ACTION", required=True)
    actions.add_parser("list", help="names of the shipped worlds").set_defaults(handler=_list)
    check = actions.add_parser("check", help="load and validate a world (name or .toml path)")
    check.add_argument("world", help="shipped world name (e.g. revinge) or path to a .toml file")
    check.set_defaults(handler=_check)
    generate = actions.add_parser(
        "generate",
        help="write a world with seeded random bodies and distractors (robustness runs)",
    )
    generate.add_argument("--seed", type=int, required=True, help="random seed (>= 0)")
    generate.add_argument("--out", type=Path, required=True, help="world file to write (.toml)")
    generate.add_argument("--base", default="revinge", help="base world (default revinge)")
    defaults = Population()
    for name in ("persons", "dummies", "animals", "cars"):
        generate.add_argument(
            f"--{name}", type=int, default=getattr(defaults, name), help=f"number of {name}"
        )
    generate.set_defaults(handler=_generate)


def _list(args: argparse.Namespace) -> int:
    for name in shipped_worlds():
        print(name)
    return 0


def _check(args: argparse.Namespace) -> int:
    try:
        world = load_world(args.world)
    except WorldError as exc:
        for issue in exc.issues:
            print(issue, file=sys.stderr)
        return 2
    e0, n0, e1, n1 = world.bounds
    counts = ", ".join(f"{len(world.objects_of(k))} {k.value}" for k in ObjectKind)
    print(f"{world.name}: ok")
    print(
        f"  origin {world.origin.latitude:.5f} N {world.origin.longitude:.5f} E "
        f"{world.origin.altitude:.1f} m; extent {e1 - e0:.0f} m x {n1 - n0:.0f} m"
    )
    print(
        f"  {len(world.buildings)} buildings, {len(world.roads)} roads, "
        f"{len(world.vegetation)} vegetation, {len(world.no_fly_zones)} no-fly zones"
    )
    print(
        f"  pads {', '.join(p.name for p in world.pads)}; depots "
        f"{', '.join(d.name for d in world.depots)}; objects: {counts}"
    )
    return 0


def _generate(args: argparse.Namespace) -> int:
    out: Path = args.out
    if out.suffix != ".toml" or not out.parent.resolve().is_dir():
        print(
            f"hdrc3 world generate: error: {out} must be a .toml file in an existing directory",
            file=sys.stderr,
        )
        return 2
    population = Population(args.persons, args.dummies, args.animals, args.cars)
    try:
        world = generated_world(args.seed, out, args.base, population)
    except (ConfigError, WorldError) as exc:
        print(f"hdrc3 world generate: error: {exc}", file=sys.stderr)
        return 2
    counts = ", ".join(f"{len(world.objects_of(k))} {k.value}" for k in ObjectKind)
    print(f"{out}: {world.name} ok; objects: {counts}", flush=True)
    return 0
