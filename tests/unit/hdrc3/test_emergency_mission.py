"""The emergency-services mission's texts: leg I, the leg II problem, its plan, leg II."""

from __future__ import annotations

import math
from typing import Any

import pytest

from hdrc3.emergency_mission import (
    DROP_OFFSET_M,
    Body,
    Box,
    EmergencyMission,
    assign_bands,
    box_drops,
    confirmed_bodies,
    deliveries_from_plan,
    delivery_problem,
    drop_point,
    kits_for,
    leg1_text,
    leg2_text,
)
from hdrc3_base.errors import ConfigError
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.goal_planning import control_text, domain_text
from hdrc3_tst.model import NodeKind

REGION = ((-180.0, -180.0), (-80.0, -180.0), (-80.0, -50.0), (-180.0, -50.0))
MISSION = EmergencyMission("revinge", ("uav0", "uav1"), REGION)
DEPOT = (-160.0, 100.0)
BOXES = (
    Box("box1", "food", 5.0, -166.0, 96.0),
    Box("box2", "food", 5.0, -160.0, 96.0),
    Box("box4", "medicine", 5.0, -166.0, 104.0),
    Box("box5", "medicine", 5.0, -160.0, 104.0),
)
BODIES = (Body("Body1", -100.0, -60.0, 0.9), Body("Body2", -150.0, -165.0, 0.8))


def _feature(**props: Any) -> dict[str, Any]:
    return {"type": "Feature", "properties": props}


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"agents": ()}, "at least one aircraft"),
        ({"region": ((0.0, 0.0), (1.0, 0.0))}, "three corners"),
        ({"scan_speed": 0.0}, "scan_speed"),
        ({"cruise_altitude": math.nan}, "cruise_altitude"),
    ],
)
def test_a_mission_refuses_bad_settings(changes: dict[str, Any], message: str) -> None:
    args: dict[str, Any] = {"world": "revinge", "agents": ("uav0",), "region": REGION}
    with pytest.raises(ConfigError, match=message):
        EmergencyMission(**{**args, **changes})


def test_leg1_gives_every_aircraft_its_band_and_checks() -> None:
    check = load_text(leg1_text(MISSION))
    assert check.status is CheckStatus.OK, [str(d) for d in check.diagnostics]
    assert check.tst is not None
    scans = [n for n in check.tst.tree.nodes.values() if n.action == "scan-area"]
    assert sorted(check.tst.agent_of(n.node_id) for n in scans) == ["uav0", "uav1"]


@pytest.mark.parametrize(
    ("features", "names"),
    [
        ([], ()),
        ([_feature(confirmed=False, east=1.0, north=2.0, p_body=0.9)], ()),
        (
            [
                _feature(confirmed=True, east=1.0, north=2.0, p_body=0.6),
                _feature(confirmed=True, east=5.0, north=6.0, p_body=0.9),
            ],
            ((5.0, 6.0), (1.0, 2.0)),
        ),
    ],
)
def test_confirmed_bodies_are_ordered_by_certainty(
    features: list[dict[str, Any]], names: tuple[tuple[float, float], ...]
) -> None:
    bodies = confirmed_bodies(features)
    assert tuple((b.east, b.north) for b in bodies) == names
    assert [b.name for b in bodies] == [f"Body{i + 1}" for i in range(len(names))]


@pytest.mark.parametrize(
    "feature",
    [{"type": "Feature"}, _feature(confirmed=True, east="x", north=1.0, p_body=1.0)],
)
def test_a_malformed_map_feature_is_refused(feature: dict[str, Any]) -> None:
    with pytest.raises(ConfigError, match="feature 0"):
        confirmed_bodies([feature])


def test_kits_go_to_the_most_certain_bodies_while_boxes_last() -> None:
    plan = kits_for((*BODIES, Body("Body3", 0.0, 0.0, 0.7)), BOXES, ("food", "medicine"))
    assert [(k.body.name, [b.tag for b in k.boxes]) for k in plan.kits] == [
        ("Body1", ["box1", "box4"]),
        ("Body2", ["box2", "box5"]),
    ]
    assert [b.name for b in plan.unserved] == ["Body3"]


def test_boxes_go_down_beside_the_body_towards_the_depot_each_at_its_own_point() -> None:
    body = BODIES[0]
    drops = box_drops(kits_for(BODIES, BOXES, MISSION.kits), DEPOT)
    mine = [point for tag, (name, point) in drops.items() if name == body.name]
    assert len(mine) == 2
    for e, n in mine:
        assert math.hypot(e - body.east, n - body.north) == pytest.approx(DROP_OFFSET_M)
        assert math.dist((e, n), DEPOT) < math.dist((body.east, body.north), DEPOT)
    assert math.dist(*mine) > DROP_OFFSET_M  # two aircraft never aim at one point
    # one box (or the body as a planning location): on the straight line to the depot
    single = drop_point(body, DEPOT)
    assert DROP_OFFSET_M + math.dist(single, DEPOT) == pytest.approx(
        math.dist((body.east, body.north), DEPOT)
    )


def test_talplanner_allocates_the_deliveries_and_leg2_checks() -> None:
    kits = kits_for(BODIES, BOXES, MISSION.kits)
    positions = {"uav0": (-150.0, -170.0, 30.0), "uav1": (-90.0, -60.0, 30.0)}
    problem = delivery_problem(positions, kits, DEPOT, MISSION.cruise_altitude)
    result = TaskPlanner().plan(PlanRequest(domain_text(), problem, control_text()), timeout=60)
    assert result.status is PlanStatus.SOLVED, result.reason
    labels = [o.label for o in result.plan]
    deliveries = deliveries_from_plan(
        labels, [o.agent or "" for o in result.plan], ("uav0", "uav1")
    )
    delivered = sorted(item for items in deliveries.values() for item in items)
    assert delivered == [("box1", "Body1"), ("box2", "Body2"), ("box4", "Body1"), ("box5", "Body2")]

    text = leg2_text(MISSION, deliveries, kits, DEPOT, {"uav0": "H1", "uav1": "H2"})
    check = load_text(text)
    assert check.status is CheckStatus.OK, [str(d) for d in check.diagnostics]
    assert check.tst is not None
    goals = [n for n in check.tst.tree.nodes.values() if n.kind is NodeKind.GOAL]
    assert len(goals) == 4
    lands = [n for n in check.tst.tree.nodes.values() if n.action == "land"]
    assert len(lands) == 2  # every aircraft lands, with deliveries or without


@pytest.mark.parametrize(
    ("labels", "agents"),
    [(["(drop-box uav2 box1 Body1)"], ["uav2"]), (["(drop-box uav0 box1)"], ["uav0"])],
)
def test_a_plan_that_is_not_this_missions_delivery_is_refused(
    labels: list[str], agents: list[str]
) -> None:
    with pytest.raises(ConfigError, match="not a delivery"):
        deliveries_from_plan(labels, agents, ("uav0", "uav1"))


@pytest.mark.parametrize(
    ("starts", "bands"),
    [
        ({"uav0": (-230.0, -140.0), "uav1": (-60.0, -140.0)}, {"uav0": 2, "uav1": 1}),
        ({"uav0": (-60.0, -140.0), "uav1": (-230.0, -140.0)}, {"uav0": 1, "uav1": 2}),
    ],
)
def test_each_aircraft_scans_the_band_on_its_side(
    starts: dict[str, tuple[float, float]], bands: dict[str, int]
) -> None:
    assert assign_bands(MISSION, starts) == bands
    text = leg1_text(MISSION, bands)
    line = next(x for x in text.splitlines() if x.startswith("  band1(P1"))  # P1 = uav0
    assert line.endswith(f"Region, 30, {bands['uav0']}, 2);")


def test_bands_need_every_aircrafts_start() -> None:
    with pytest.raises(ConfigError, match="no start position for uav1"):
        assign_bands(MISSION, {"uav0": (0.0, 0.0)})


def test_with_nothing_to_deliver_leg2_flies_every_aircraft_home() -> None:
    kits = kits_for((), BOXES, MISSION.kits)
    text = leg2_text(MISSION, {"uav0": [], "uav1": []}, kits, DEPOT, {"uav0": "H1", "uav1": "H2"})
    check = load_text(text)
    assert check.status is CheckStatus.OK, [str(d) for d in check.diagnostics]
    assert check.tst is not None
    actions = sorted(n.action for n in check.tst.tree.nodes.values() if n.action)
    assert actions == ["fly-to", "fly-to", "land", "land"]
