import pytest

from hdrc3_dyknow.coordinator import (
    MonitorPlan,
    MonitorResult,
    MonitorStatus,
    StreamReasoningCoordinator,
)
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.progression import Verdict
from hdrc3_dyknow.sample import FeatureTerm, Sample
from hdrc3_dyknow.semantic_matching import SemanticMatcher, StreamSemantics

# Section 8.5: all AVs except av1 should always be more than 10 m away from av1.
XYDIST_FORMULA = "forall x in AV: x != av1 implies always XYDist(x, av1) > 10"

# Stream labels deliberately say nothing about their content: only annotations do.
STREAMS = {
    "kp/7": FeatureTerm("XYDist", ("uav2", "av1")),
    "fusion/0042": FeatureTerm("HorizontalDistance", ("uav3", "av1")),  # equivalent feature
    "kp/8": FeatureTerm("XYDist", ("av1", "uav2")),  # wrong argument order: not used
    "kp/9": FeatureTerm("Altitude", ("uav2",)),
    "kp/10": FeatureTerm("Speed", ("uav2",)),
}


def make() -> StreamReasoningCoordinator:
    onto = Ontology.load()
    for name, sort in [("av1", "RMAX"), ("uav2", "UAV"), ("uav3", "Quadrotor"), ("car1", "Car")]:
        onto.add_object(name, sort)
    semantics = StreamSemantics()
    host = KnowledgeProcessHost()
    for label, term in STREAMS.items():
        host.declare(label, Policy(), str(term))
        semantics.annotate(label, term)
    return StreamReasoningCoordinator(host, SemanticMatcher(onto, semantics))


def test_xydist_formula_is_matched_to_streams_by_meaning() -> None:
    plan = make().plan(XYDIST_FORMULA)
    assert isinstance(plan, MonitorPlan)
    assert plan.streams == {"XYDist(uav2,av1)": "kp/7", "XYDist(uav3,av1)": "fusion/0042"}
    assert plan.scope.domains["AV"] == ("av1", "uav2", "uav3")


@pytest.mark.parametrize(
    ("d2", "d3", "verdict", "states"),
    [
        ([30.0, 25.0, 20.0, 15.0], [40.0, 35.0, 12.0, 11.0], Verdict.UNDECIDED, 4),
        ([30.0, 25.0, 20.0, 15.0], [40.0, 35.0, 9.5, 11.0], Verdict.FALSE, 3),
        ([30.0, 8.0, 20.0, 15.0], [40.0, 35.0, 12.0, 11.0], Verdict.FALSE, 2),
    ],
)
def test_xydist_monitor_verdicts(
    d2: list[float], d3: list[float], verdict: Verdict, states: int
) -> None:
    coordinator = make()
    result = coordinator.start("sep", XYDIST_FORMULA, period_ms=100, max_delay_ms=50)
    assert result == MonitorResult(
        MonitorStatus.STARTED, f"monitoring {XYDIST_FORMULA}", ("fusion/0042", "kp/7")
    )
    for i, (a, b) in enumerate(zip(d2, d3, strict=True)):
        t = i * 100
        coordinator.host.publish("kp/7", Sample(t, t + 5, a))
        coordinator.host.publish("fusion/0042", Sample(t, t + 20, b))  # a slower stream
        coordinator.host.advance(t + 20)
    unit = coordinator.unit("sep")
    assert unit is not None and unit.verdict is verdict and unit.states == states
    events = coordinator.drain()
    assert events[0].verdict is Verdict.UNDECIDED and events[0].time == 0 and events[0].residual
    assert events[-1].verdict is verdict
    assert coordinator.drain() == []


def test_stop_releases_subscriptions() -> None:
    coordinator = make()
    coordinator.start("m", "always altitude(uav2) > 5", 100, 0)
    assert coordinator.host.generator("kp/9").status().subscribers == 1
    assert coordinator.stop("m").status is MonitorStatus.STOPPED
    assert coordinator.host.generator("kp/9").status().subscribers == 0
    assert coordinator.monitors() == []


@pytest.mark.parametrize(
    ("monitor_id", "formula", "period", "status", "fragments"),
    [
        ("m", "always (", 100, MonitorStatus.PARSE_ERROR, ["<formula>:1:"]),
        (
            "m",
            "forall x in Dragon: always XYDist(x, av1) > 1",
            100,
            MonitorStatus.UNKNOWN_SYMBOL,
            ["'Dragon'"],
        ),
        (
            "m",
            "always temperature(uav2) < 50",
            100,
            MonitorStatus.UNKNOWN_SYMBOL,
            ["'temperature'", "kp/7"],
        ),
        (
            "m",
            "always XYDist(uav9, av1) > 10",
            100,
            MonitorStatus.UNKNOWN_SYMBOL,
            ["'uav9'", "fusion/0042"],
        ),
        (
            "m",
            "always XYDist(car1, av1) > 10",
            100,
            MonitorStatus.UNKNOWN_SYMBOL,
            ["XYDist[car1, av1]", "kp/10"],
        ),
        ("m", "always altitude(uav2) > 5", 0, MonitorStatus.BAD_REQUEST, ["period"]),
        ("", "always altitude(uav2) > 5", 100, MonitorStatus.BAD_REQUEST, ["empty"]),
        ("m", "always 1 < 2", 100, MonitorStatus.BAD_REQUEST, ["reads no fluent"]),
    ],
)
def test_bad_requests_are_results(
    monitor_id: str, formula: str, period: int, status: MonitorStatus, fragments: list[str]
) -> None:
    result = make().start(monitor_id, formula, period, 0)
    assert result.status is status
    for fragment in fragments:
        assert fragment in result.reason


def test_duplicate_id_and_unknown_stop() -> None:
    coordinator = make()
    assert coordinator.start("m", "always speed(uav2) < 50", 100, 0).status is MonitorStatus.STARTED
    assert (
        coordinator.start("m", "always speed(uav2) < 50", 100, 0).status
        is MonitorStatus.BAD_REQUEST
    )
    result = coordinator.stop("nope")
    assert result.status is MonitorStatus.NOT_FOUND and "running: m" in result.reason


def test_bad_values_are_counted_not_fatal() -> None:
    coordinator = make()
    coordinator.start("m", "always speed(uav2) < 50", 100, 0)
    coordinator.host.publish("kp/10", Sample(0, 0, "fast"))
    coordinator.host.advance(0)
    coordinator.host.publish("kp/10", Sample(100, 100, 10.0))
    coordinator.host.advance(100)
    unit = coordinator.unit("m")
    assert unit is not None and unit.errors == 1 and "fast" in unit.last_error and unit.states == 1
