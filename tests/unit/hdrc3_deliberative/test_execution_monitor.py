"""Execution monitor core: the chapter's Examples 9.1-9.4, the robust speed limits of 9.3.2,
activation and retirement of operator-specific formulas, refusals and stale data."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from hdrc3_deliberative.execution_monitor import EventKind, MonitorEvent, StartStatus
from hdrc3_deliberative.monitor_fakes import MonitorRig

PERIOD = 100
STATES = "states period 100 ms, max_delay 200 ms, stale 1000 ms;\n"
Profile = Callable[[int], float]


def fly(rig: MonitorRig, until: int, speed: Profile, altitude: Profile = lambda t: 0.0) -> None:
    """Data Interface messages every 40 ms (25 Hz) with the given speed and altitude."""
    for now in range(0, until + 1, 20):
        if now % 40 == 0:
            rig.state(now, velocity_north=speed(now), altitude=altitude(now))
        rig.advance(now)


def violations(rig: MonitorRig) -> list[tuple[str, int]]:
    return [(e.monitor_id, e.time_ms) for e in rig.of(EventKind.VIOLATED)]


# --- Example 9.1: power ------------------------------------------------------------------------
POWER = STATES + (
    "monitor power: always forall av in AV: (power(av) > 100 implies"
    " power(av) < 1.5 * 100 until[0,2000] always[0,1000] power(av) <= 100);"
)


@pytest.mark.parametrize(
    ("name", "profile", "violated_at"),
    [
        ("nominal", lambda t: 90.0, None),
        ("overshoot 1 s then normal", lambda t: 130.0 if 1000 <= t < 2000 else 90.0, None),
        ("above f*M", lambda t: 160.0 if 1000 <= t < 1500 else 90.0, 1000),
        # over M for 3 s: the normal period cannot begin within tau = 2 s of the first excess
        ("overshoot 3 s", lambda t: 130.0 if 1000 <= t < 4000 else 90.0, 3000),
        # back to normal in time but not for tau' = 1 s
        # normal for 500 ms and 600 ms within tau, never for tau' = 1 s: the last attempt
        # that could begin in time fails at 3.2 s
        (
            "normal too briefly",
            lambda t: 90.0 if t < 1000 or 1500 <= t < 2000 or 2600 <= t < 3200 else 130.0,
            3200,
        ),
    ],
)
def test_example_9_1_power(name: str, profile: Profile, violated_at: int | None) -> None:
    rig = MonitorRig(POWER)
    assert rig.start().status is StartStatus.STARTED
    for now in range(0, 6001, 50):
        if now % 100 == 0:
            rig.power(now, voltage=10.0, current=profile(now) / 10.0)
        rig.advance(now)
    expected = [] if violated_at is None else [("power", violated_at)]
    assert violations(rig) == expected, name


# --- Example 9.2: pick-up within 5000 ms, held 1000 ms ------------------------------------------
PICKUP = STATES + (
    "monitor pickup for pickup-box(av, box) recovery retry_pickup:"
    " eventually[0,5000] always[0,1000] carrying(av, box);"
)


@pytest.mark.parametrize(
    ("name", "carrying", "kind", "time"),
    [
        ("held from 4 s", lambda t: t >= 4000, EventKind.SATISFIED, 5000),
        ("only a 500 ms blip", lambda t: 2000 <= t < 2500, EventKind.VIOLATED, 5600),
        ("never", lambda t: False, EventKind.VIOLATED, 5600),
        # detected at 5.2 s, but the 1000 ms cannot complete: violated when it drops
        ("late and brief", lambda t: 5200 <= t < 5800, EventKind.VIOLATED, 5800),
    ],
)
def test_example_9_2_pickup(
    name: str, carrying: Callable[[int], bool], kind: EventKind, time: int
) -> None:
    rig = MonitorRig(PICKUP)
    rig.start()
    rig.flag(600, "n7", "pickup-box", True, box="box1")
    for now in range(0, 9001, 50):
        if now % 100 == 0:
            rig.sample("payload/carrying1", now, carrying(now))
            rig.sample("payload/carrying2", now, True)  # another box: must not count
        rig.advance(now)
    (activated,) = rig.of(EventKind.ACTIVATED)
    assert activated.formula == "eventually[0,5000] always[0,1000] carrying(uav0, box1)"
    (decided,) = [e for e in rig.events if e.kind in (EventKind.SATISFIED, EventKind.VIOLATED)]
    assert (decided.kind, decided.time_ms, decided.monitor_id) == (kind, time, "pickup@n7"), name
    assert decided.decl is not None and decided.decl.recovery == "retry_pickup"
    assert decided.arguments == (("box", "box1"),)


def test_an_operator_formula_without_its_arguments_is_refused_by_name() -> None:
    rig = MonitorRig(PICKUP)
    rig.start()
    rig.flag(600, "n7", "pickup-box", True, carrier="c1")
    (refused,) = rig.of(EventKind.REFUSED)
    assert refused.monitor_id == "pickup@n7"
    assert "parameter(s) box" in refused.reason and "carrier" in refused.reason
    assert rig.monitor.active == []


def test_activation_with_an_object_that_has_no_stream_is_refused() -> None:
    rig = MonitorRig(PICKUP)
    rig.start()
    rig.flag(600, "n7", "pickup-box", True, box="box9")
    (refused,) = rig.of(EventKind.REFUSED)
    assert "box9" in refused.reason


# --- Example 9.3: climb ------------------------------------------------------------------------
CLIMB = STATES + "monitor climbed for climb(av): EXEC until altitude(av) >= 7.0;"


@pytest.mark.parametrize(
    ("name", "stop", "kind", "time"),
    [
        # altitude = t / 500: 7 m at 3.5 s, in the state after the sample at 3.5 s
        ("reaches 7 m while climbing", 4000, EventKind.SATISFIED, 3600),
        ("climb ends at 6 m", 3000, EventKind.VIOLATED, 3000),
    ],
)
def test_example_9_3_climb(name: str, stop: int, kind: EventKind, time: int) -> None:
    rig = MonitorRig(CLIMB)
    rig.start()
    rig.flag(1000, "n2", "climb", True)
    for now in range(0, 5001, 20):
        if now == stop:
            rig.flag(now, "n2", "climb", False)
        if now % 40 == 0:
            rig.state(now, altitude=now / 500)
        rig.advance(now)
    (activated,) = rig.of(EventKind.ACTIVATED)
    assert activated.formula == "executing-climb(uav0) until altitude(uav0) >= 7"
    (decided,) = [e for e in rig.events if e.kind in (EventKind.SATISFIED, EventKind.VIOLATED)]
    assert (decided.kind, decided.time_ms) == (kind, time), name
    assert rig.monitor.active == []


def test_an_undecided_operator_formula_is_retired_after_its_step() -> None:
    rig = MonitorRig(STATES + "monitor slow for fly-to(av): always speed(av) < 20;")
    rig.start()
    rig.flag(1000, "n3", "fly-to", True, x="10")
    for now in range(0, 3001, 20):
        if now == 2000:
            rig.flag(now, "n3", "fly-to", False)
        if now % 40 == 0:
            rig.state(now, velocity_north=5.0)
        rig.advance(now)
    (retired,) = rig.of(EventKind.RETIRED)
    assert (retired.monitor_id, retired.time_ms, retired.reason) == (
        "slow@n3",
        2000,
        "its step ended",
    )
    assert retired.states == 11  # 1000, 1100, ..., 2000
    assert rig.monitor.active == []


# --- Example 9.4: carrying until put down --------------------------------------------------------
CARRY = STATES + (
    "monitor held for pickup-box(av, box) persistent:"
    " EXEC until[0,5000] (carrying(av, box) until executing-putdown-box(av, box));"
)


@pytest.mark.parametrize(
    ("name", "carrying", "kind", "time"),
    [
        ("carried until put down", lambda t: 1500 <= t < 8500, EventKind.SATISFIED, 8000),
        ("dropped in flight", lambda t: 1500 <= t < 6000, EventKind.VIOLATED, 6000),
        ("never picked up", lambda t: False, EventKind.VIOLATED, 3000),
    ],
)
def test_example_9_4_carrying_until_putdown(
    name: str, carrying: Callable[[int], bool], kind: EventKind, time: int
) -> None:
    rig = MonitorRig(CARRY)
    rig.start()
    for now in range(0, 10001, 50):
        if now == 1000:
            rig.flag(now, "p1", "pickup-box", True, box="box1")
        if now == 3000:
            rig.flag(now, "p1", "pickup-box", False, box="box1")
        if now == 8000:
            rig.flag(now, "d1", "putdown-box", True, box="box1")
        if now % 100 == 0:
            rig.sample("payload/carrying1", now, carrying(now))
        rig.advance(now)
    (decided,) = [e for e in rig.events if e.kind in (EventKind.SATISFIED, EventKind.VIOLATED)]
    assert (decided.kind, decided.time_ms) == (kind, time), name
    assert rig.of(EventKind.RETIRED) == []


# --- the default spec's box_held (Example 9.4 over the carrying sensor, recovery box-lost) -------
@pytest.mark.parametrize(
    ("name", "held", "put_down", "kind", "time"),
    [
        ("dropped in flight", lambda t: "box1" if 2500 <= t < 6000 else "", "", "V", 6000),
        ("put down", lambda t: "box1" if 2500 <= t < 8500 else "", "drop-box", "S", 8000),
        (
            "put on a carrier",
            lambda t: "box1" if 2500 <= t < 8500 else "",
            "put-on-carrier",
            "S",
            8000,
        ),
        ("the wrong box", lambda t: "box2" if 2500 <= t < 8500 else "", "drop-box", "V", 3000),
    ],
)
def test_the_default_box_held_formula_reads_the_carrying_sensor(
    name: str, held: Callable[[int], str], put_down: str, kind: str, time: int
) -> None:
    from hdrc3_deliberative.monitor_spec import DEFAULT_SPEC

    rig = MonitorRig(
        DEFAULT_SPEC.read_text(), extra_streams="", loads=(("box1", "Box"), ("box2", "Box"))
    )
    assert rig.start().status is StartStatus.STARTED
    for now in range(0, 10001, 50):
        if now == 1000:
            rig.flag(now, "g/2", "pick-up-box", True, box="box1")
        if now == 3000:
            rig.flag(now, "g/2", "pick-up-box", False, box="box1")
        if now == 8000 and put_down:
            rig.flag(now, "g/4", put_down, True, box="box1", place="Field")
        if now % 100 == 0:
            rig.hook(now, held(now))
        rig.advance(now)
    decided = [
        e
        for e in rig.events
        if e.kind in (EventKind.SATISFIED, EventKind.VIOLATED) and e.monitor_id.startswith("box_")
    ]
    assert [(e.kind.name[0], e.time_ms) for e in decided] == [(kind, time)], name
    assert decided[0].arguments == (("box", "box1"),)
    assert decided[0].decl is not None and decided[0].decl.recovery == "box-lost"


# --- the default spec's carrier_lifted (a load too heavy: recovery carrier-too-heavy) -----------
@pytest.mark.parametrize(
    ("name", "stalled", "violated_at"),
    [
        ("stalls under its load", lambda t: t >= 2000, 3000),
        ("a moment at lift-off", lambda t: 2000 <= t < 2300, None),
        ("lifts", lambda t: False, None),
    ],
)
def test_the_default_carrier_lifted_formula_reads_the_winch(
    name: str, stalled: Callable[[int], bool], violated_at: int | None
) -> None:
    from hdrc3_deliberative.monitor_spec import DEFAULT_SPEC
    from hdrc3_platform_server.hook_api import Winch

    rig = MonitorRig(DEFAULT_SPEC.read_text(), extra_streams="", loads=(("c3", "Carrier"),))
    assert rig.start().status is StartStatus.STARTED
    for now in range(0, 6001, 50):
        if now == 1000:
            rig.flag(now, "g/2", "attach-carrier", True, carrier="c3")
        if now == 5000:
            rig.flag(now, "g/2", "attach-carrier", False, carrier="c3")
        if now % 100 == 0:
            winch = Winch.STALLED if stalled(now) else Winch.RAISING
            rig.hook(now, "c3" if now >= 1500 else "", winch=int(winch))
        rig.advance(now)
    violated = [e for e in rig.events if e.kind is EventKind.VIOLATED]
    assert [(e.monitor_id, e.time_ms) for e in violated] == (
        [] if violated_at is None else [("carrier_lifted@g/2", violated_at)]
    ), name
    if violated:
        assert violated[0].arguments == (("carrier", "c3"),)
        assert violated[0].decl is not None and violated[0].decl.recovery == "carrier-too-heavy"


# --- 9.3.2: robust speed limits ------------------------------------------------------------------
NAIVE = "monitor naive: always forall av in AV: speed(av) <= 10;"
WEAK = "monitor weak: always forall av in AV: eventually[0,1000] speed(av) <= 10;"
STRONG = (
    "monitor strong: always forall av in AV:"
    " (speed(av) > 10 implies eventually[0,1000] always[0,500] speed(av) <= 10);"
)


@pytest.mark.parametrize(
    ("name", "speed", "expected"),
    [
        ("nominal", lambda t: 8.0, []),
        # one outlier message: the naive limit fires, the robust ones do not
        ("single outlier", lambda t: 25.0 if t == 2000 else 8.0, [("naive", 2000)]),
        # sustained overspeed from 2 s: all fire, the robust ones within tau + one period
        (
            "sustained",
            lambda t: 14.0 if t >= 2000 else 8.0,
            [("naive", 2000), ("strong", 3000), ("weak", 3000)],
        ),
        # under the limit once every 400 ms: the weak form is satisfied, the strong one not
        (
            "oscillating",
            lambda t: 8.0 if t >= 2000 and t % 400 == 0 else (14.0 if t >= 2000 else 8.0),
            [("naive", 2100), ("strong", 3100)],
        ),
    ],
)
def test_robust_speed_limits(name: str, speed: Profile, expected: list[tuple[str, int]]) -> None:
    rig = MonitorRig(STATES + NAIVE + WEAK + STRONG)
    rig.start()
    fly(rig, 6000, speed)
    assert sorted(violations(rig)) == expected, name


# --- Definition 9.2 ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("formula", "violated"),
    [
        ("always speed(uav0) - 2 * 3 < altitude(uav0)", True),  # value terms, arithmetic
        ("always -speed(uav0) < 0", False),
        ("always on_ground(uav0)", True),  # boolean fluent
        ("always not on_ground(uav0)", False),
        ("always 5000 < 7000", False),  # temporal terms (ms) compare like numbers
        ("exists av in AV: eventually[0,500] altitude(av) > 3", False),  # quantification
        ("forall av in AV: av == uav0", False),  # object values
    ],
)
def test_definition_9_2_formulas(formula: str, violated: bool) -> None:
    rig = MonitorRig(STATES + f"monitor m: {formula};")
    assert rig.start().status is StartStatus.STARTED, rig.start()
    for now in range(0, 2001, 20):
        if now % 40 == 0:
            rig.state(now, velocity_north=7.0, altitude=now / 100, on_ground_flag=False)
        rig.advance(now)
    assert bool(rig.of(EventKind.VIOLATED)) is violated


# --- refusals ------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("spec", "named"),
    [
        ("monitor ok: always true;\nmonitor g: always fuel(uav0) > 3;", ":3:1: monitor 'g'"),
        ("monitor g: always fuel(uav0) > 3;", "unknown fluent 'fuel'"),
        ("monitor g for climb(av): always fuel(av) > 3;", "unknown fluent 'fuel'"),
        ("monitor g: always altitude(uav5) > 3;", "unknown object 'uav5'"),
        ("monitor g: forall x in Boat: altitude(x) > 3;", "unknown sort 'Boat'"),
        ("monitor g: always EXEC;", "EXEC is only meaningful"),
        ("monitor g: always position(uav0) > 3;", "no stream contains position[uav0]"),
    ],
)
def test_formulas_over_unknown_symbols_refuse_to_start(spec: str, named: str) -> None:
    rig = MonitorRig(STATES + spec)
    result = rig.start()
    assert result.status is StartStatus.UNKNOWN_SYMBOL
    assert named in result.reason
    assert rig.monitor.active == []
    assert rig.monitor.advance(1000) == []


def test_start_twice() -> None:
    rig = MonitorRig(STATES + NAIVE)
    assert rig.start().status is StartStatus.STARTED
    assert rig.start().status is StartStatus.ALREADY_STARTED


# --- stale data ----------------------------------------------------------------------------------
def test_a_stream_that_stops_raises_a_stale_alarm_and_no_false_violation() -> None:
    rig = MonitorRig(STATES + STRONG)
    rig.start()
    for now in range(0, 6001, 20):
        if now % 40 == 0 and not 2000 < now < 4000:
            rig.state(now, velocity_north=8.0)
        rig.advance(now)
    stale, resumed = (
        e for e in rig.events if e.kind in (EventKind.STALE_DATA, EventKind.DATA_RESUMED)
    )
    assert (stale.kind, stale.monitor_id, stale.time_ms) == (
        EventKind.STALE_DATA,
        "uav0/di/speed",
        3100,
    )
    assert "speed(uav0)" in stale.reason and "at 2000 ms" in stale.reason
    assert (resumed.kind, resumed.time_ms) == (EventKind.DATA_RESUMED, 4000)
    assert violations(rig) == []
    assert rig.monitor.active == ["strong"]


def _events_of(rig: MonitorRig, kind: EventKind) -> list[MonitorEvent]:
    return rig.of(kind)


def test_late_samples_within_max_delay_are_used() -> None:
    """Samples 150 ms late (max delay 200 ms) still decide their own states."""
    rig = MonitorRig(STATES + NAIVE)
    rig.start()
    for now in range(0, 3001, 10):
        sent = now - 150
        if sent >= 0 and sent % 40 == 0:
            rig.state(sent, delay_ms=150, velocity_north=14.0 if sent >= 2000 else 8.0)
        rig.advance(now)
    (violated,) = _events_of(rig, EventKind.VIOLATED)
    assert violated.time_ms == 2000


# --- semantic matching across agents, fusion -----------------------------------------------------
OTHER_UAS = """
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix dk: <https://hdrc3.example.org/dyknow#> .
@prefix u2: <https://uas2.example.org/ontology#> .
u2:Height a owl:Class ; owl:equivalentClass dk:Altitude .
u2:Aircraft a owl:Class ; owl:equivalentClass dk:AV .
u2:me a owl:NamedIndividual, u2:Aircraft ; owl:sameAs dk:uav0 .
"""


def test_streams_of_another_ontology_are_matched_and_fused(tmp_path: Path) -> None:
    """A second altitude source annotated in another UAS's vocabulary fills the own stream's
    dropout: the monitor reads the freshest of both; the own stream's alarm is raised, but the
    fluent never goes missing and the formula keeps being progressed."""
    (tmp_path / "u2.ttl").write_text(OTHER_UAS)
    rig = MonitorRig(STATES + "monitor high: always altitude(uav0) > 5;", extra_streams="")
    rig.streams.ontology.merge(tmp_path / "u2.ttl")
    rig.streams.load("stream u2/height contains Height(me);", "<u2 streams>")
    assert rig.start().status is StartStatus.STARTED
    for now in range(0, 4001, 20):
        if now % 40 == 0 and not 1000 < now < 3000:
            rig.state(now, altitude=10.0)
        if now % 100 == 0:
            rig.sample("u2/height", now, 9.0)
        rig.advance(now)
    (stale,) = rig.of(EventKind.STALE_DATA)
    assert stale.monitor_id == "uav0/di/altitude" and violations(rig) == []
    assert rig.monitor.synthesizer.states == 41  # 0..4000 ms
    rig.sample("u2/height", 4100, 2.0)
    rig.advance(4400)
    assert violations(rig) == [("high", 4100)]


# --- nested fluent terms (Definition 9.2) --------------------------------------------------------
NESTED_FEATURES = """
@prefix dk: <https://hdrc3.example.org/dyknow#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
dk:Place a owl:Class ; rdfs:subClassOf dk:Property ; rdfs:label "place" .
dk:WindAt a owl:Class ; rdfs:subClassOf dk:Property ; rdfs:label "wind" .
"""
NESTED_STREAMS = """
object depot1, depot2 : Location;
stream nav/at contains place(uav0) with missing last_value;
stream wind/d1 contains wind(depot1) with missing last_value;
stream wind/d2 contains wind(depot2) with missing last_value;
"""


@pytest.mark.parametrize(
    ("formula", "violated_at"),
    [
        # the wind where the AV is: depot1 calm, depot2 windy; the AV moves at 1 s
        ("always wind(place(uav0)) < 10", 1000),
        ("always wind(place(uav0)) < 20", None),
        ("always (place(uav0) == depot1 implies wind(place(uav0)) < 10)", None),
    ],
)
def test_nested_fluent_terms_read_the_fluent_their_argument_names(
    tmp_path: Path, formula: str, violated_at: int | None
) -> None:
    (tmp_path / "wind.ttl").write_text(NESTED_FEATURES)
    rig = MonitorRig(STATES + f"monitor m: {formula};", extra_streams="")
    rig.streams.ontology.merge(tmp_path / "wind.ttl")
    rig.streams.load(NESTED_STREAMS, "<nested>")
    assert rig.start().status is StartStatus.STARTED
    for now in range(0, 2001, 50):
        if now % 100 == 0:
            rig.sample("nav/at", now, "depot1" if now < 1000 else "depot2")
            rig.sample("wind/d1", now, 5.0)
            rig.sample("wind/d2", now, 15.0)
        rig.advance(now)
    expected = [] if violated_at is None else [("m", violated_at)]
    assert violations(rig) == expected


def test_a_nested_term_with_no_stream_for_any_value_is_refused() -> None:
    rig = MonitorRig(STATES + "monitor m: always carrying(uav0, altitude(uav0));", "")
    result = rig.start()
    assert result.status is StartStatus.UNKNOWN_SYMBOL
    assert "no stream contains carrying(uav0, altitude(uav0)) for any object" in result.reason


def test_an_operator_formula_over_an_unknown_sort_refuses_to_start() -> None:
    rig = MonitorRig(STATES + "monitor g for climb(av): forall b in Boat: altitude(av) > 3;")
    result = rig.start()
    assert result.status is StartStatus.UNKNOWN_SYMBOL and "unknown sort 'Boat'" in result.reason


def test_global_activations_are_reported_with_the_first_advance() -> None:
    rig = MonitorRig(STATES + NAIVE)
    rig.start(500)
    (activated,) = rig.advance(500)
    assert (activated.kind, activated.monitor_id, activated.time_ms) == (
        EventKind.ACTIVATED,
        "naive",
        500,
    )
    assert activated.formula == "always speed(uav0) <= 10"
