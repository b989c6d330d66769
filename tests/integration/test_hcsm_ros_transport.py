"""HCSM external events over real rclpy/DDS between two computers (PFC and DRC)."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, NamedTuple

import pytest

from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.interpreter import Interpreter
from hdrc3_hcsm.loader import load_text
from hdrc3_hcsm.main_loop import MainLoop
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.trace import TraceRecord, TraceRecorder, fired_ids

pytestmark = pytest.mark.ros

MAX_SPINS = 400
SPIN_TIMEOUT = 0.05

PFC_MODEL = """
model Pfc on PFC;
computers PFC, DRC;
event Go-EV = 7001 from DRC;
event Done-EV = 7002 to DRC;
automaton A Pfc {
    init Idle-ST;
    state Busy-ST;
    A.1: Idle-ST -> Busy-ST on Go-EV / SEND Done-EV data cache to DRC;
}
root Pfc;
"""


class Rig(NamedTuple):
    executor: Any  # rclpy SingleThreadedExecutor
    pfc: Any  # RosTransport of the PFC
    drc: Any  # RosTransport of the DRC
    node: Any  # the PFC's rclpy Node


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from hdrc3_hcsm.ros_transport import RosTransport

    pfc_node: Any = Node("hcsm_pfc", context=ros_context)
    drc_node: Any = Node("hcsm_drc", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(pfc_node)
    executor.add_node(drc_node)
    pfc = RosTransport(pfc_node, "PFC")
    drc = RosTransport(drc_node, "DRC")
    try:
        yield Rig(executor, pfc, drc, pfc_node)
    finally:
        executor.shutdown()
        pfc_node.destroy_node()
        drc_node.destroy_node()


def spin_until(executor: Any, done: Callable[[], bool]) -> bool:
    for _ in range(MAX_SPINS):
        if done():
            return True
        executor.spin_once(timeout_sec=SPIN_TIMEOUT)
    return done()


def collect(transport: Any, into: list[WireEvent]) -> int:
    into.extend(transport.receive())
    return len(into)


def test_events_cross_dds_in_order_with_integrity(
    rig: Rig,
) -> None:
    executor, pfc, drc, _ = rig
    assert spin_until(executor, lambda: pfc.subscribers("DRC") > 0 and drc.subscribers("PFC") > 0)
    sent = [WireEvent(7000 + i, f"E{i}-EV", bytes([i]) * i, "DRC", "PFC") for i in range(10)]
    for event in sent:
        drc.send(event)
    got: list[WireEvent] = []
    assert spin_until(executor, lambda: collect(pfc, got) >= 10)
    assert [(e.name, e.data) for e in got] == [(e.name, e.data) for e in sent]
    assert [e.sequence for e in got] == list(range(1, 11))
    assert all(e.intact() for e in got)
    assert pfc.stats.received == 10 and pfc.stats.lost == 0 and pfc.stats.corrupt == 0


def test_corrupted_message_is_dropped(rig: Rig) -> None:
    from hdrc3_hcsm.ros_transport import DEFAULT_PREFIX, EVENT_QOS, to_msg
    from hdrc3_interfaces.msg import Event

    executor, pfc, drc, node = rig
    raw = node.create_publisher(Event, f"{DEFAULT_PREFIX}/PFC", EVENT_QOS)
    # both writers must be matched: the "ok" event comes from the DRC's, not from ``raw``
    assert spin_until(
        executor, lambda: raw.get_subscription_count() > 0 and drc.subscribers("PFC") > 0
    )
    bad = to_msg(WireEvent(7001, "Go-EV", b"abc", "DRC", "PFC").sealed(1))
    bad.data = b"abd"  # payload changed after sealing
    raw.publish(bad)
    unknown = to_msg(WireEvent(7001, "Go-EV", b"", "DRC", "PFC").sealed(1))
    unknown.source_computer = 77  # no such computer
    raw.publish(unknown)
    drc.send(WireEvent(7001, "Go-EV", b"ok", "DRC", "PFC"))
    got: list[WireEvent] = []
    assert spin_until(
        executor, lambda: collect(pfc, got) >= 1 and pfc.malformed >= 1 and pfc.stats.corrupt >= 1
    )
    assert pfc.stats.corrupt == 1 and pfc.malformed == 1
    assert [e.data for e in got] == [b"ok"]


def test_interpreter_round_trip_over_ros(rig: Rig) -> None:
    from hdrc3_hcsm.ros_transport import TracePublisher

    executor, pfc, drc, pfc_node = rig
    model = compile_model(load_text(PFC_MODEL, "pfc.hcsm"))
    trace = TraceRecorder()
    interp = Interpreter(model, {}, trace=trace)
    loop = MainLoop(interp, (), pfc)
    published: list[str] = []
    from std_msgs.msg import String

    trace_sub = pfc_node.create_subscription(
        String, "hcsm/trace", lambda m: published.append(m.data), 10
    )
    publisher = TracePublisher(pfc_node, "hcsm/trace")
    assert spin_until(
        executor,
        lambda: (
            drc.subscribers("PFC") > 0
            and pfc.subscribers("DRC") > 0
            and trace_sub.get_publisher_count() > 0
        ),
    )
    drc.send(WireEvent(7001, "Go-EV", b"wp-1", "DRC", "PFC"))
    now = 0.0
    replies: list[WireEvent] = []

    def step() -> bool:
        nonlocal now
        loop.iterate(now)
        now += 0.02
        replies.extend(drc.receive())
        return bool(replies)

    assert spin_until(executor, step)
    assert [(e.name, e.data, e.source) for e in replies] == [("Done-EV", b"wp-1", "PFC")]
    assert fired_ids(trace) == [("Go-EV", "A.1")]
    record = next(r for r in trace if r.transitions)
    publisher.record(record)
    assert spin_until(executor, lambda: bool(published))
    assert TraceRecord.from_json(published[0]) == record
