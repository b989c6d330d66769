import math

import pytest

from hdrc3_dyknow.coordinator import MonitorStatus, StreamReasoningCoordinator
from hdrc3_dyknow.fakes import FakeHelicopterState
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.progression import Verdict
from hdrc3_dyknow.semantic_matching import SemanticMatcher, StreamSemantics
from hdrc3_dyknow.semantic_spec import SpecError, parse_spec
from hdrc3_dyknow.sources import StreamCatalog, difference, distance, xy_dist

LAT0, LON0 = 58.4, 15.6  # near Linköping
DEG_LAT_M = 111_000.0  # metres per degree of latitude, roughly

SPEC = """
object av1 : RMAX;
object uav2, uav3 : UAV;
stream a/pos contains Position(av1) from topic "/av1/helicopter_state" field position;
stream b/pos contains Position(uav2) from topic "/uav2/helicopter_state" field position;
stream c/pos contains Position(uav3) from topic "/uav3/helicopter_state" field position;
stream b/alt contains altitude(uav2) from topic "/uav2/helicopter_state" field altitude;
stream p/ba contains XYDist(uav2, av1) = xy_dist(b/pos, a/pos) with period 100 ms, max_delay 100 ms;
stream p/ca contains XYDist(uav3, av1) = xy_dist(c/pos, a/pos) with period 100 ms, max_delay 100 ms;
"""


def make() -> tuple[StreamCatalog, StreamReasoningCoordinator]:
    host, onto, semantics = KnowledgeProcessHost(), Ontology.load(), StreamSemantics()
    catalog = StreamCatalog(host, onto, semantics)
    catalog.load(parse_spec(SPEC))
    return catalog, StreamReasoningCoordinator(host, SemanticMatcher(onto, semantics))


def fly(
    catalog: StreamCatalog, coordinator: StreamReasoningCoordinator, north_m: dict[str, list[float]]
) -> None:
    """Each AV reports its position north of LAT0 every 100 ms from t=1 s, 10 ms late."""
    steps = len(next(iter(north_m.values())))
    for i in range(steps):
        t = 1000 + i * 100
        for av, norths in north_m.items():
            msg = FakeHelicopterState.at(t, LAT0 + norths[i] / DEG_LAT_M, LON0, 100.0)
            catalog.on_message(f"/{av}/helicopter_state", msg, t + 10)
        catalog.host.advance(t + 10)
    catalog.host.advance(1000 + steps * 100 + 500)


@pytest.mark.parametrize(
    ("uav3_north", "verdict"),
    [
        ([50.0, 40.0, 30.0, 20.0, 15.0], Verdict.UNDECIDED),
        ([50.0, 40.0, 30.0, 5.0, 15.0], Verdict.FALSE),
    ],
)
def test_xydist_demo_over_data_interface_messages(
    uav3_north: list[float], verdict: Verdict
) -> None:
    catalog, coordinator = make()
    formula = "forall x in AV: x != av1 implies always XYDist(x, av1) > 10"
    result = coordinator.start("sep", formula, period_ms=100, max_delay_ms=150)
    assert result.status is MonitorStatus.STARTED and result.streams == ("p/ba", "p/ca")
    fly(catalog, coordinator, {"av1": [0.0] * 5, "uav2": [100.0] * 5, "uav3": uav3_north})
    unit = coordinator.unit("sep")
    assert unit is not None and unit.errors == 0
    assert unit.verdict is verdict
    events = coordinator.drain()
    assert events[0].time == 1000
    assert events[-1].time == (1300 if verdict is Verdict.FALSE else 1000)


def test_catalog_status_and_topics() -> None:
    catalog, _ = make()
    assert catalog.topics() == [
        "/av1/helicopter_state",
        "/uav2/helicopter_state",
        "/uav3/helicopter_state",
    ]
    assert [(s.label, s.annotation) for s in catalog.host.status()][:3] == [
        ("a/pos", "Position[av1]"),
        ("b/alt", "altitude[uav2]"),
        ("b/pos", "Position[uav2]"),
    ]


def test_non_finite_values_are_rejected_and_counted() -> None:
    catalog, _ = make()
    msg = FakeHelicopterState.at(0, math.nan, LON0, 100.0)
    assert catalog.on_message("/uav2/helicopter_state", msg, 0) == 1  # only altitude published
    assert catalog.rejected == {"b/pos": 1}
    assert catalog.on_message("/unknown", msg, 0) == 0


def test_zero_stamp_uses_available_time() -> None:
    catalog, _ = make()
    catalog.on_message("/uav2/helicopter_state", FakeHelicopterState(altitude=5.0), 1234)
    catalog.host.advance(1234)
    assert catalog.host.generator("b/alt").status().last_valid_time == 1234


HOOK = """
object box1, box2 : Box;
stream h/1 contains Carrying(av1, box1) from topic "/av1/sensors/carrying" type HookState
    field object_id == "box1";
stream h/any contains Carrying(av1, box2) from topic "/av1/sensors/carrying" type HookState
    field carrying;
"""


@pytest.mark.parametrize(
    ("held", "expected"),
    [
        ("box1", {"h/1": True, "h/any": True}),
        ("box2", {"h/1": False, "h/any": True}),
        ("", {"h/1": False, "h/any": False}),
    ],
)
def test_hook_state_fields_and_tag_comparisons(held: str, expected: dict[str, bool]) -> None:
    from hdrc3_dyknow.fakes import FakeHookState

    catalog, _ = make()
    catalog.load(parse_spec(HOOK))
    assert catalog.topic_types()["/av1/sensors/carrying"] == "hdrc3_interfaces/msg/HookState"
    assert catalog.topic_types()["/av1/helicopter_state"] == (
        "hdrc3_interfaces/msg/HelicopterState"
    )
    assert catalog.on_message("/av1/sensors/carrying", FakeHookState.holding(100, held), 100) == 2
    catalog.host.advance(100)
    values = {
        label: sample.value
        for label in ("h/1", "h/any")
        if (sample := catalog.host.generator(label).last) is not None
    }
    assert values == expected


def test_redeclaring_a_label_replaces_it() -> None:
    catalog, _ = make()
    catalog.load(
        parse_spec('stream b/alt contains altitude(uav2) from topic "/other" field altitude;')
    )
    assert "/other" in catalog.topics()
    assert (
        catalog.on_message("/uav2/helicopter_state", FakeHelicopterState.at(5, LAT0, LON0, 1.0), 5)
        == 1
    )


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("object x : Spaceship;", "unknown sort 'Spaceship'"),
        ("stream s contains Temperature(av1);", "unknown feature 'Temperature'"),
        ("stream s contains XYDist(av1);", "XYDist takes 2 objects"),
        ("stream s contains altitude(zz9);", "unknown object 'zz9'"),
        ('stream s contains altitude(av1) from topic "/t" field colour;', "unknown field 'colour'"),
        ("stream s contains XYDist(av1, uav2) = warp(a/pos, b/pos);", "unknown function 'warp'"),
        ("stream s contains XYDist(av1, uav2) = xy_dist(a/pos);", "takes 2 input streams"),
        (
            "stream s contains XYDist(av1, uav2) = xy_dist(a/pos, nowhere);",
            "unknown input stream 'nowhere'",
        ),
        (
            'stream s contains altitude(av1) from topic "/t" type Telemetry field altitude;',
            "unknown message type 'Telemetry'",
        ),
        (
            'stream s contains altitude(av1) from topic "/t" type HookState field altitude;',
            "unknown field 'altitude'; HookState fields: cable_length, carrying",
        ),
        (  # a topic has one type: /av1/helicopter_state is already read as HelicopterState
            'stream s contains carrying(av1, av1) from topic "/av1/helicopter_state"'
            " type HookState field carrying;",
            "topic '/av1/helicopter_state' carries HelicopterState, not HookState",
        ),
    ],
)
def test_bad_specs_are_rejected_whole(text: str, fragment: str) -> None:
    catalog, _ = make()
    before = catalog.host.labels()
    with pytest.raises(SpecError, match=fragment) as info:
        catalog.load(parse_spec("stream fresh contains altitude(av1);\n" + text, "extra.spec"))
    assert str(info.value).startswith("extra.spec:")
    assert catalog.host.labels() == before


@pytest.mark.parametrize(
    ("function", "values", "expected"),
    [
        (xy_dist, [(LAT0 + 0.001, LON0, 500.0), (LAT0, LON0, 0.0)], 111.3),
        (distance, [(LAT0, LON0, 30.0), (LAT0, LON0, 0.0)], 30.0),
        (difference, [5.0, 2.0], 3.0),
    ],
)
def test_functions(function: object, values: list[object], expected: float) -> None:
    assert function(values) == pytest.approx(expected, abs=0.5)  # type: ignore[operator]
