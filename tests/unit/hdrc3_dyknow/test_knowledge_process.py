import pytest

from hdrc3_dyknow.knowledge_process import (
    FunctionUnit,
    KnowledgeProcessHost,
    MergeUnit,
    OperatorUnit,
    ProcessStatus,
    StepContext,
)
from hdrc3_dyknow.operators import MapOp, MergeOp
from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.sample import Sample, StreamError
from hdrc3_dyknow.state_sync import StateSynchronizer


class Recorder:
    """A sink process that remembers what it received."""

    def __init__(self) -> None:
        self.received: list[tuple[int, str, object]] = []

    def step(self, ctx: StepContext) -> None:
        for label, samples in ctx.inputs.items():
            self.received += [(ctx.now, label, s.value) for s in samples]


class Exploding:
    def step(self, ctx: StepContext) -> None:
        if any(ctx.inputs.values()):
            raise ValueError("boom")


def test_source_to_unit_to_sink_pipeline_is_asynchronous() -> None:
    host = KnowledgeProcessHost()
    host.declare("alt", Policy(), "Altitude[uav0]")
    host.add_process(
        "feet",
        OperatorUnit("alt", "alt_ft", MapOp(lambda v: v * 3.28084)),
        {"alt": Policy()},
        ["alt_ft"],
    )  # type: ignore[operator]
    sink = Recorder()
    host.add_process("sink", sink, {"alt_ft": Policy()})
    host.publish("alt", Sample(0, 0, 10.0))
    assert sink.received == []  # nothing is delivered before the host advances
    host.advance(1)
    assert sink.received == [(1, "alt_ft", pytest.approx(32.8084))]
    assert [s.label for s in host.status()] == ["alt", "alt_ft"]


def test_function_unit_combines_synchronised_inputs() -> None:
    host = KnowledgeProcessHost()
    for label in ("x", "y"):
        host.declare(label)
    sync = StateSynchronizer(["x", "y"], period_ms=100, max_delay_ms=50)
    unit = FunctionUnit(["x", "y"], "sum", lambda values: sum(values), sync)  # type: ignore[arg-type, return-value]
    host.add_process("sum", unit, {"x": Policy(), "y": Policy()}, ["sum"])
    sink = Recorder()
    host.add_process("sink", sink, {"sum": Policy()})
    host.publish("x", Sample(0, 0, 1.0))
    host.publish("y", Sample(0, 3, 2.0))
    host.advance(3)
    host.publish("x", Sample(100, 100, 5.0))
    host.advance(149)
    host.advance(150)
    assert sink.received == [(3, "sum", 3.0), (150, "sum", 7.0)]


def test_failing_process_is_isolated() -> None:
    host = KnowledgeProcessHost()
    host.declare("x")
    host.add_process("bad", Exploding(), {"x": Policy()})
    good = Recorder()
    host.add_process("good", good, {"x": Policy()})
    host.publish("x", Sample(0, 0, 1))
    host.advance(0)
    status, reason = host.process_status("bad")
    assert status is ProcessStatus.FAILED and "boom" in reason
    assert good.received == [(0, "x", 1)]


def test_process_may_publish_only_on_its_outputs() -> None:
    class Rogue:
        def step(self, ctx: StepContext) -> None:
            ctx.publish("x", Sample(ctx.now, ctx.now, 0))

    host = KnowledgeProcessHost()
    host.declare("x")
    host.add_process("rogue", Rogue(), {})
    host.advance(0)
    assert host.process_status("rogue")[0] is ProcessStatus.FAILED


def test_remove_process_unsubscribes() -> None:
    host = KnowledgeProcessHost()
    host.declare("x")
    sink = Recorder()
    host.add_process("sink", sink, {"x": Policy()})
    host.remove_process("sink")
    host.publish("x", Sample(0, 0, 1))
    host.advance(0)
    assert sink.received == [] and host.generator("x").status().subscribers == 0


def test_cycle_is_bounded() -> None:
    class Echo:
        def step(self, ctx: StepContext) -> None:
            for s in ctx.inputs.get("loop", []):
                ctx.publish("loop", Sample(s.valid_time + 1, s.available_time, s.value))

    host = KnowledgeProcessHost()
    host.declare("loop")
    host.add_process("echo", Echo(), {"loop": Policy()}, ["loop"])
    host.publish("loop", Sample(0, 0, 1))
    host.advance(0)  # terminates despite the cycle
    assert host.generator("loop").status().stats.samples_in > 1


@pytest.mark.parametrize(
    "action",
    [
        lambda h: h.publish("nope", Sample(0, 0, 1)),
        lambda h: h.subscribe("nope"),
        lambda h: h.add_process("p", Recorder(), {"nope": Policy()}),
        lambda h: h.process_status("nope"),
    ],
)
def test_unknown_names_raise(action: object) -> None:
    host = KnowledgeProcessHost()
    with pytest.raises(StreamError, match="unknown"):
        action(host)  # type: ignore[operator]


def test_duplicate_process_name() -> None:
    host = KnowledgeProcessHost()
    host.add_process("p", Recorder(), {})
    with pytest.raises(StreamError, match="already exists"):
        host.add_process("p", Recorder(), {})


def test_redeclaring_keeps_subscribers() -> None:
    host = KnowledgeProcessHost()
    host.declare("x", Policy(), "Altitude[a]")
    sink = Recorder()
    host.add_process("sink", sink, {"x": Policy()})
    host.declare("x", Policy(change_only=True), "Altitude[b]")
    host.publish("x", Sample(0, 0, 1))
    host.publish("x", Sample(10, 10, 1))
    host.advance(10)
    assert sink.received == [(10, "x", 1)]
    assert host.generator("x").status().annotation == "Altitude[b]"


def test_merge_unit_orders_two_sources() -> None:
    host = KnowledgeProcessHost()
    host.declare("car1/pos")
    host.declare("car2/pos")
    unit = MergeUnit(["car1/pos", "car2/pos"], "cars", MergeOp(2, max_delay_ms=100))
    host.add_process("merge", unit, {"car1/pos": Policy(), "car2/pos": Policy()}, ["cars"])
    sink = Recorder()
    host.add_process("sink", sink, {"cars": Policy(ordered=False)})
    host.publish("car1/pos", Sample(10, 10, "a10"))
    host.publish("car1/pos", Sample(30, 30, "a30"))
    host.publish("car2/pos", Sample(20, 25, "b20"))
    host.advance(30)
    host.advance(200)
    assert [value for _, _, value in sink.received] == ["a10", "b20", "a30"]
