"""The saliency map of a whole mission: every aircraft's map merged into one GeoJSON file.

Each agent's ``saliency`` node publishes its map (latched, GeoJSON) on
``/<agent>/saliency/map``; an area scanned by several aircraft has bodies near the band edges
that both saw. :func:`collect` takes the last map of every agent, merges them by distance
(:meth:`SaliencyMap.absorb`: frame and body counts add up) and writes the merged map with a
``confirmed`` property per point (``hdrc3 tst run --out DIR`` -> ``DIR/saliency.geojson``).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rclpy.node import Node
from std_msgs.msg import String

from hdrc3_base.ros_runtime import RosProcess
from hdrc3_perception.image_gate import LATCHED
from hdrc3_perception.saliency_map import (
    MapError,
    SaliencyMap,
    dumps_geojson,
    locations_from_geojson,
)
from sim.world_loader import load_world

MAP_WAIT_S = 10.0
"""Wall seconds to wait for the agents' latched maps."""


@dataclass(frozen=True, slots=True)
class Collected:
    """What :func:`collect` wrote."""

    path: Path
    locations: int
    confirmed: int
    missing: tuple[str, ...]
    """Agents whose map did not come (no saliency node, or it never processed an image)."""
    refused: tuple[str, ...]
    """Agents whose map was malformed (with the reason)."""


def collect(
    process: RosProcess, node: Node, agents: Sequence[str], world: str, path: Path
) -> Collected:
    """Merge the agents' latest maps into ``path``; who had none or a bad one is listed."""
    texts: dict[str, str] = {}

    def keep(agent: str) -> Callable[[String], None]:
        return lambda msg: texts.__setitem__(agent, msg.data)

    for agent in agents:
        node.create_subscription(String, f"/{agent}/saliency/map", keep(agent), LATCHED)
    process.spin_until(lambda: len(texts) == len(agents), MAP_WAIT_S)
    merged, refused = SaliencyMap(), []
    for agent in agents:
        if agent not in texts:
            continue
        try:
            data: Any = json.loads(texts[agent])
            merged.absorb(locations_from_geojson(data))
        except (ValueError, MapError) as exc:
            refused.append(f"{agent}: {exc}")
    path.write_text(dumps_geojson(merged, load_world(world).origin), encoding="utf-8")
    missing = tuple(a for a in agents if a not in texts)
    return Collected(path, len(merged), len(merged.confirmed()), missing, tuple(refused))
