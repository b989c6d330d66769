"""PRM roadmap (chapter section 7.1.1): built offline on OMPL, cached on disk per world.

The roadmap is OMPL's PRM grown in the GIS's planning volume against the static geometry only
(terrain, buildings, vegetation with the safety margin); no-fly zones, runtime obstacles and
altitude/rate limits are query-time constraints. The cache file is keyed on the world file's
content, the margin and the build parameters; a file that does not load, does not match its key
or fails its checksum is rebuilt, never trusted.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
import zipfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import shapely
from numpy.typing import NDArray
from ompl import base as ob
from ompl import geometric as og
from scipy.spatial import cKDTree

from hdrc3_navigation.gis import Gis
from hdrc3_navigation.ompl_space import OmplSpace

DEFAULT_NODES = 2000
DEFAULT_NEIGHBOURS = 10
_FORMAT = 1


@dataclass(frozen=True, eq=False)
class Roadmap:
    """An undirected roadmap: node positions and edges (index pairs, i < j)."""

    nodes: NDArray[np.float64]
    """(n, 3) positions, local ENU m."""
    edges: NDArray[np.int64]
    """(m, 2) node index pairs."""
    key: str
    build_seconds: float
    tree: cKDTree = field(init=False, repr=False)
    adjacency: list[list[tuple[int, int, bool]]] = field(init=False, repr=False)
    """Per node: (neighbour, edge index, True if the edge is stored in this direction)."""
    lines: NDArray[np.object_] = field(init=False, repr=False)
    """The edges' ground projections as shapely line strings (for vectorised zone tests)."""

    def __post_init__(self) -> None:
        """Build the neighbour index."""
        object.__setattr__(self, "tree", cKDTree(self.nodes))
        adjacency: list[list[tuple[int, int, bool]]] = [[] for _ in range(len(self.nodes))]
        for k, (i, j) in enumerate(self.edges.tolist()):
            adjacency[i].append((j, k, True))
            adjacency[j].append((i, k, False))
        object.__setattr__(self, "adjacency", adjacency)
        ends = self.nodes[self.edges][:, :, :2] if len(self.edges) else np.empty((0, 2, 2))
        object.__setattr__(self, "lines", shapely.linestrings(ends))

    @property
    def size(self) -> tuple[int, int]:
        """(nodes, edges)."""
        return len(self.nodes), len(self.edges)

    def checksum(self) -> str:
        """Hash of the node and edge arrays."""
        h = hashlib.sha256(np.ascontiguousarray(self.nodes).tobytes())
        h.update(np.ascontiguousarray(self.edges).tobytes())
        return h.hexdigest()


BuildProgress = Callable[[int, int], None]
"""Hears (milestones so far, milestones wanted) while a roadmap grows, about every 0.1 s."""


def build_roadmap(
    gis: Gis,
    nodes: int = DEFAULT_NODES,
    neighbours: int = DEFAULT_NEIGHBOURS,
    progress: BuildProgress | None = None,
) -> Roadmap:
    """Grow OMPL's PRM until it has ``nodes`` milestones; return its graph."""
    start = time.perf_counter()
    space = OmplSpace(gis)
    prm = og.PRM(space.si)
    prm.setMaxNearestNeighbors(neighbours)
    prm.setProblemDefinition(ob.ProblemDefinition(space.si))
    prm.setup()
    while prm.milestoneCount() < nodes:
        prm.growRoadmap(0.1)
        if progress is not None:
            progress(min(int(prm.milestoneCount()), nodes), nodes)
    data = ob.PlannerData(space.si)
    prm.getPlannerData(data)
    n = data.numVertices()
    pts = np.empty((n, 3))
    for i in range(n):
        s = data.getVertex(i).getState()
        pts[i] = (s[0], s[1], s[2])
    pairs = {(min(i, j), max(i, j)) for i in range(n) for j in data.getEdges(i) if i != j}
    edges = np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2)
    return Roadmap(pts, edges, cache_key(gis, nodes, neighbours), time.perf_counter() - start)


def cache_key(gis: Gis, nodes: int, neighbours: int) -> str:
    """Key of a roadmap: world content, margin, volume and build parameters."""
    h = hashlib.sha256(f"{gis.static_key()}|{nodes}|{neighbours}|{_FORMAT}".encode())
    return h.hexdigest()[:24]


class RoadmapCache:
    """Roadmaps on disk, one ``.npz`` per key, in a cache directory."""

    def __init__(self, directory: Path) -> None:
        self.directory = directory

    def path(self, key: str) -> Path:
        """File of one key."""
        return self.directory / f"roadmap-{key}.npz"

    def load(self, key: str) -> Roadmap | None:
        """The cached roadmap of ``key``, or None if absent or not trustworthy."""
        path = self.path(key)
        try:
            with np.load(path, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                roadmap = Roadmap(
                    np.asarray(data["nodes"], dtype=np.float64),
                    np.asarray(data["edges"], dtype=np.int64),
                    str(meta["key"]),
                    float(meta["build_seconds"]),
                )
        except (OSError, ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile):
            return None
        if meta.get("format") != _FORMAT or roadmap.key != key:
            return None
        nodes, edges = roadmap.nodes, roadmap.edges
        if nodes.ndim != 2 or nodes.shape[1] != 3 or not np.isfinite(nodes).all():
            return None
        if edges.ndim != 2 or edges.shape[1] != 2 or (edges.size and edges.max() >= len(nodes)):
            return None
        if meta.get("checksum") != roadmap.checksum():
            return None
        return roadmap

    def save(self, roadmap: Roadmap) -> Path:
        """Write a roadmap atomically (temporary file, then rename)."""
        self.directory.mkdir(parents=True, exist_ok=True)
        path = self.path(roadmap.key)
        meta = {
            "format": _FORMAT,
            "key": roadmap.key,
            "build_seconds": roadmap.build_seconds,
            "checksum": roadmap.checksum(),
        }
        tmp = path.with_suffix(f".{os.getpid()}.tmp.npz")
        np.savez(tmp, nodes=roadmap.nodes, edges=roadmap.edges, meta=np.array(json.dumps(meta)))
        tmp.replace(path)
        return path

    def load_or_build(
        self,
        gis: Gis,
        nodes: int = DEFAULT_NODES,
        neighbours: int = DEFAULT_NEIGHBOURS,
        rebuild: bool = False,
        progress: BuildProgress | None = None,
    ) -> tuple[Roadmap, bool]:
        """The cached roadmap, or a freshly built (and saved) one; True if built."""
        key = cache_key(gis, nodes, neighbours)
        cached = None if rebuild else self.load(key)
        if cached is not None:
            return cached, False
        roadmap = build_roadmap(gis, nodes, neighbours, progress)
        self.save(roadmap)
        return roadmap, True


def default_cache_dir() -> Path:
    """``$HDRC3_CACHE_DIR`` or ``$XDG_CACHE_HOME/hdrc3/roadmaps`` (``~/.cache`` by default)."""
    explicit = os.environ.get("HDRC3_CACHE_DIR")
    if explicit:
        return Path(explicit) / "roadmaps"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "hdrc3" / "roadmaps"
