"""Section 11.2 on the real node chain: a laser mapping TST finds what the stack's map lacks.

``hdrc3 tst run examples/tst/lrf_mapping.tst --launch --world revinge --sim-world
revinge_changed`` flies uav0 over revinge's town block with the rotating laser collecting; the
simulator's world has a container (C1) in the corridor between B04 and B05 and new trees (V-new)
that the stack's model (revinge) lacks. Checked from the recording: the laser_mapper's map
against the simulated world's surface, its overlay with the model (C1 and V-new found, nothing
else), the map stored in the path planner's GIS, and the low flight through the corridor planned
afterwards 6 m clear of the true world, container included (a straight line would pass 4.4 m
above it), and flown clear of it (ground truth, which only scores the run).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import shapely
from shapely.geometry import Polygon

from hdrc3_base.stamps import stamp_s
from tests.integration.flight_runs import SEED, recorded

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "tst" / "lrf_mapping.tst"
RMS_LIMIT = 0.5
"""m: the issue's target for the height error, met on the cells at least 2 m from a height step
(over all mapped cells the bleed of roofs into the cells beside walls makes it about 1.5 m)."""
FLAGS = "/uav0/execution_flags"
PLANNED = "/uav0/planned_path"
MARGIN = 6.0
"""m: the path planner's safety margin (section 11.2)."""
MAP_ERROR = 1.0
"""m: how far the mapped container may stand inside the true one: the alignment onto the model
places sharp edges only to within a cell, and the heading error blurs them. (The surface itself
covers every mapped cell to its edges.)"""
CLEARANCE = 5.0
"""m: the true track's least distance from the container: the margin less the path follower's
and the navigation's errors; the straight line at 7 m would pass 4.4 m above it."""


def box_distance(point: tuple[float, float, float], footprint: Polygon, top: float) -> float:
    """Distance from a point to a prism from the ground to ``top`` over ``footprint``."""
    horizontal = shapely.distance(footprint, shapely.Point(point[0], point[1]))
    vertical = max(0.0, point[2] - top)
    return math.hypot(float(horizontal), vertical)


@pytest.mark.timeout(1500)
def test_a_laser_mapping_mission_finds_the_container_and_the_planner_avoids_it(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> None:
    from hdrc3_navigation.audit import WorldAudit
    from hdrc3_navigation.messages import elevation_map_from_msg, segment_from_msg
    from sim.world_loader import load_world

    out = tmp_path / "run"
    run = hdrc3_cli(
        "tst", "run", str(EXAMPLE), "--launch", "--agents", "uav0", "--world", "revinge",
        "--sim-world", "revinge_changed", "--out", str(out), "--domain-id", str(ros_domain),
        "--mission", "lrf", "--seed", SEED,
    )  # fmt: skip
    assert run.finish(timeout=1400.0) == 0, "\n".join(run.lines)
    topics = (
        "/uav0/laser_mapper/status",
        "/uav0/laser_mapper/changes",
        "/uav0/laser_mapper/elevation_map",
        "/uav0/path_planner/gis_state",
        "/uav0/ground_truth/state",
        FLAGS,
        PLANNED,
    )
    messages = recorded(out / "run.mcap", *topics)
    status = json.loads(messages["/uav0/laser_mapper/status"][-1].data)
    assert status["status"] == "stored", status
    assert status["map"] in messages["/uav0/path_planner/gis_state"][-1].elevation_maps

    (msg,) = messages["/uav0/laser_mapper/elevation_map"]
    m = elevation_map_from_msg(msg)
    assert not isinstance(m, str), m
    changed = load_world("revinge_changed")
    score = m.score(changed.surface_heights)
    assert score.cells > 5000 and score.away_cells > 0.8 * score.cells, score
    assert score.away_rms <= RMS_LIMIT, score

    new = {b.name: Polygon(b.footprint) for b in changed.buildings if b.name == "C1"}
    new |= {v.name: Polygon(v.polygon) for v in changed.vegetation if v.name == "V-new"}
    found: dict[str, int] = {}
    changes = json.loads(messages["/uav0/laser_mapper/changes"][-1].data)["changes"]
    for change in changes:
        region = shapely.box(*change["bounds"])
        hits = [name for name, footprint in new.items() if region.intersects(footprint)]
        assert change["kind"] == "new" and len(hits) == 1, change  # nothing else changed
        found[hits[0]] = found.get(hits[0], 0) + 1
    assert found == {"C1": 1, "V-new": 1}, changes

    # both corridor legs were planned clear of the true world, container included, by the
    # margin less the map's own error (the straight line is 4.4 m above the container)
    paths = [[segment_from_msg(p) for p in path.segments] for path in messages[PLANNED]]
    assert len(paths) >= 2  # south, then north (a replan adds one)
    for path in paths:
        assert WorldAudit(changed).check_segments(path, MARGIN - MAP_ERROR) == []
    # and the aircraft, on its own navigation, flew clear of it
    flags = {(f.node_id, f.executing): stamp_s(f.header.stamp) for f in messages[FLAGS]}
    start, end = flags["north", True], flags["north", False]
    (container,) = (b for b in changed.buildings if b.name == "C1")
    track = [
        s.position_enu
        for s in messages["/uav0/ground_truth/state"]
        if start <= stamp_s(s.header.stamp) <= end
    ]
    assert len(track) > 100 and track[-1][1] > 0.0  # through to the corridor's north end
    clearance = min(box_distance(p, Polygon(container.footprint), container.top) for p in track)
    assert clearance >= CLEARANCE, clearance
