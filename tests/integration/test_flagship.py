"""The flagship in miniature on the real node chain: ``hdrc3 demo --short`` (chapter 11.1).

Two RMAXes scan a 40 m x 40 m rectangle next to the pads with their cameras (leg I), the
merged saliency map's confirmed bodies get a food box each, TALplanner on uav0's
``task_planner`` allocates the deliveries, and leg II flies them as goal nodes under execution
monitoring, then both aircraft land. Checked from the products and the recording: both legs
succeeded, the one person in the rectangle (body04) was found within 3 m with no false positive,
the box lies on the ground at its drop point, no violation was left unrecovered, and the report
page with its map and timeline exists. Minutes of sim time with cameras: ``make flights``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.integration.flight_runs import SEED

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]


@pytest.mark.timeout(2400)
def test_the_short_flagship_finds_the_body_and_delivers_its_box(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> None:
    from hdrc3.cli.demo import MISSIONS, SHORT_KITS
    from hdrc3.emergency_mission import box_drops, confirmed_bodies, kits_for
    from hdrc3.emergency_report import evaluate
    from hdrc3.emergency_spec import load_mission
    from hdrc3.flagship import depot_stock

    out = tmp_path / "demo"
    run = hdrc3_cli(
        "demo", "--short", "--speed", "1", "--out", str(out), "--domain-id", str(ros_domain),
        "--seed", SEED,
    )  # fmt: skip
    code = run.finish(timeout=2300.0)
    text = "\n".join(run.lines)
    assert code == 0, text[-4000:]
    assert "mission leg1 succeeded" in text and "mission leg2 succeeded" in text

    bodies = confirmed_bodies(json.loads((out / "saliency.geojson").read_text())["features"])
    mission = load_mission(Path(str(MISSIONS.joinpath("emergency_short.talf"))), SHORT_KITS).mission
    assert mission is not None
    depot, boxes = depot_stock(mission.world, mission.depot)
    drops = box_drops(kits_for(bodies, boxes, mission.kits), depot)
    ev = evaluate(out / "run.mcap", mission.world, mission.region, bodies, drops)
    assert [p[0] for p in ev.people] == ["body04"]
    assert set(ev.found) == {"body04"} and not ev.false_positives, ev.summary()
    assert ev.deliveries and all(d.delivered for d in ev.deliveries), ev.deliveries
    assert not ev.unrecovered, ev.unrecovered
    for name in ("index.html", "map.png", "timeline.png"):
        assert (out / "report" / name).stat().st_size > 0
    assert {modes[-1][1] for modes in ev.modes.values()} == {"ground idle"}  # both landed
    assert math.isfinite(ev.min_separation)
