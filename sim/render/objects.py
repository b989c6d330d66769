"""The dynamic objects world_render draws, from world_sim's ``/world_sim/objects`` message.

The message carries id, kind, position, heading and size; the properties it lacks (surface
temperature, a car's paint and drive) come from the world file for objects it defines and from
the spawn defaults of their kind for spawned ones.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import replace
from typing import Any

from sim.sim_services import SPAWN_DEFAULTS
from sim.world import DynamicObject, ObjectKind, World


def objects_from_message(world: World, entries: Iterable[Any]) -> list[DynamicObject]:
    """Objects of a WorldObjects message; unknown kinds and non-finite positions are skipped."""
    known = {o.id: o for o in world.objects}
    kinds = {k.value: k for k in ObjectKind}
    objects = []
    for entry in entries:
        kind = kinds.get(str(entry.kind))
        values = (entry.east, entry.north, entry.heading, *entry.size)
        if kind is None or len(entry.size) != 3 or not all(math.isfinite(v) for v in values):
            continue
        size = (float(entry.size[0]), float(entry.size[1]), float(entry.size[2]))
        base = known.get(str(entry.id))
        if base is not None and base.kind is kind:
            obj = replace(
                base, east=entry.east, north=entry.north, heading=entry.heading, size=size
            )
        else:
            temperature = SPAWN_DEFAULTS[kind].get("temperature")
            obj = DynamicObject(
                str(entry.id),
                kind,
                entry.east,
                entry.north,
                entry.heading,
                size,
                temperature=float(temperature) if isinstance(temperature, float) else None,
            )
        objects.append(obj)
    return objects
