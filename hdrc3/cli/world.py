"""`hdrc3 world`: list the shipped worlds and check world files (sim/worlds/README.md)."""

from __future__ import annotations

import argparse
import sys

from sim.world import ObjectKind
from sim.world_loader import WorldError, load_world, shipped_worlds


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``world`` subcommand."""
    parser = subparsers.add_parser("world", help="list shipped worlds, validate world files")
    actions = parser.add_subparsers(dest="world_action", metavar="ACTION", required=True)
    actions.add_parser("list", help="names of the shipped worlds").set_defaults(handler=_list)
    check = actions.add_parser("check", help="load and validate a world (name or .toml path)")
    check.add_argument("world", help="shipped world name (e.g. revinge) or path to a .toml file")
    check.set_defaults(handler=_check)


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
