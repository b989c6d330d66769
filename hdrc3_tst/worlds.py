"""What the resolver takes from a mission's world, and a cache of it per world file.

Loading revinge (TOML, validation) takes about 20 ms, a third of resolving a 1,000-node
mission. A :class:`WorldCache` keeps each world's facts and loads the world again only when
one of its files (the world's or a base's it ``extends``) changed: another modification time
or size, or a file gone. There is no cache unless a caller makes one and passes it
(``resolve(..., worlds=cache)``): a long-lived owner (a command's run, a server) keeps it.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

import shapely

if TYPE_CHECKING:
    from sim.world import World

STOCKED = ("box", "carrier")
"""Kinds of world objects a point may be placed at by name (``point box1 = box1 at 0``)."""


@dataclass(frozen=True)
class WorldFacts:
    """The world's extent and its named places (local ENU metres)."""

    extent: shapely.Polygon
    places: Mapping[str, tuple[float, float]]
    """Places, pads, depots, and where the world stocks its boxes and carriers."""


def world_facts(world: World) -> WorldFacts:
    """The facts of a loaded world."""
    places = {p.name: (p.east, p.north) for p in world.places}
    places.update({p.name: (p.east, p.north) for p in world.pads})
    places.update({d.name: (d.east, d.north) for d in world.depots})
    # where the world file stocks its boxes and carriers (the mission's depot plan)
    stocked = (o for o in world.objects if o.kind.value in STOCKED)
    places.update({o.id: (o.east, o.north) for o in stocked})
    return WorldFacts(shapely.box(*world.bounds), MappingProxyType(places))


Stamp = tuple[tuple[int, int] | None, ...]
"""Modification time (ns) and size of each file of a world; None for a file gone."""


def _stamp(files: tuple[Path, ...]) -> Stamp:
    out: list[tuple[int, int] | None] = []
    for path in files:
        try:
            st = os.stat(path)
        except OSError:
            out.append(None)
        else:
            out.append((st.st_mtime_ns, st.st_size))
    return tuple(out)


@dataclass
class WorldCache:
    """World facts by world file, loaded again when a file of the world changed."""

    _entries: dict[Path, tuple[tuple[Path, ...], Stamp, WorldFacts]] = field(default_factory=dict)
    _lock: threading.Lock = field(default_factory=threading.Lock)
    loads: int = 0
    """Worlds loaded so far (the misses)."""

    def facts(self, name_or_path: str | Path) -> WorldFacts:
        """The facts of a shipped world by name, or of a world file.

        Raises:
            sim.world_loader.WorldError: the world does not load.
        """
        from sim.world_loader import load_world_sources, world_path  # imported when first used

        path = world_path(name_or_path).absolute()
        with self._lock:
            entry = self._entries.get(path)
            if entry is not None and _stamp(entry[0]) == entry[1]:
                return entry[2]
        world, files = load_world_sources(path)
        # Stamped after loading (only then are the bases known): a file rewritten between its
        # read and its stamp is missed until it changes again.
        stamp = _stamp(files)
        facts = world_facts(world)
        with self._lock:
            self._entries[path] = (files, stamp, facts)
            self.loads += 1
        return facts
