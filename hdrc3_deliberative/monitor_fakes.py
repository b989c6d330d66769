"""A test and benchmark rig for the execution monitor core, without ROS.

:class:`MonitorRig` builds the DyKnow streams of one agent's Data Interface plus payload and
power streams (fed directly, as the payload sensor and the power unit would), an
:class:`~hdrc3_deliberative.execution_monitor.ExecutionMonitor` over a specification text, and
offers ``state``/``sample``/``flag``/``advance`` calls on an explicit millisecond clock.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdrc3_deliberative.execution_monitor import (
    EventKind,
    ExecutionMonitor,
    FlagUpdate,
    MonitorEvent,
    StartResult,
)
from hdrc3_deliberative.monitor_spec import MonitorSpecParser
from hdrc3_deliberative.monitor_streams import DATA_INTERFACE_TOPIC, HOOK_TOPIC, MonitorStreams
from hdrc3_dyknow.fakes import FakeHeader, FakeHelicopterState, FakeHookState, FakeTime
from hdrc3_dyknow.sample import Sample, Value

AGENT = "uav0"
PAYLOAD_STREAMS = """
object box1, box2 : Box;
stream payload/carrying1 contains Carrying(uav0, box1) with missing last_value;
stream payload/carrying2 contains Carrying(uav0, box2) with missing last_value;
"""
"""Streams without a source: the rig publishes their samples itself (power: the Data Interface
specification's ``uav0/power``, fed as the node feeds it from ``PowerStatus``)."""


@dataclass
class MonitorRig:
    """One agent's monitor over a specification, fed by explicit calls."""

    spec_text: str
    extra_streams: str = PAYLOAD_STREAMS
    loads: tuple[tuple[str, str], ...] = ()
    """(tag, sort) of loads with ``Carrying`` streams from the carrying sensor (:meth:`hook`)."""
    streams: MonitorStreams = field(init=False)
    monitor: ExecutionMonitor = field(init=False)
    events: list[MonitorEvent] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.streams = MonitorStreams.for_agent(AGENT, loads=self.loads)
        if self.extra_streams:
            self.streams.load(self.extra_streams, "<rig streams>")
        spec = MonitorSpecParser().parse(self.spec_text, "<rig spec>")
        self.monitor = ExecutionMonitor(spec, self.streams.host, self.streams.matcher)

    def start(self, now_ms: int = 0) -> StartResult:
        """Start monitoring."""
        return self.monitor.start(now_ms)

    def state(self, time_ms: int, *, delay_ms: int = 0, **fields: float | bool) -> None:
        """A Data Interface message valid at ``time_ms``, received ``delay_ms`` later."""
        msg = FakeHelicopterState(FakeHeader(FakeTime.from_ms(time_ms)))
        for name, value in fields.items():
            setattr(msg, name, value)
        self.streams.catalog.on_message(DATA_INTERFACE_TOPIC, msg, time_ms + delay_ms)

    def hook(self, time_ms: int, object_id: str, *, delay_ms: int = 0, winch: int = 0) -> None:
        """A carrying sensor reading (``HookState``).

        The magnet holds ``object_id`` (or ""), the winch is in state ``winch``
        (``HookState.WINCH_*``).
        """
        msg = FakeHookState.holding(time_ms, object_id)
        msg.winch = winch
        self.streams.catalog.on_message(HOOK_TOPIC, msg, time_ms + delay_ms)

    def sample(self, label: str, time_ms: int, value: Value) -> None:
        """A sample of a sourceless stream (payload, power)."""
        self.streams.host.publish(label, Sample(time_ms, time_ms, value))

    def power(self, time_ms: int, voltage: float, current: float) -> None:
        """A power unit report (``PowerStatus``) valid and received at ``time_ms``."""
        self.streams.publish_power(AGENT, time_ms, time_ms, voltage, current)

    def flag(self, time_ms: int, node_id: str, action: str, executing: bool, **args: str) -> None:
        """An execution flag of this rig's agent."""
        update = FlagUpdate(time_ms, AGENT, node_id, action, executing, tuple(args.items()))
        self.events.extend(self.monitor.on_flag(update))

    def advance(self, now_ms: int) -> list[MonitorEvent]:
        """Deliver samples and progress; returns (and keeps) the new events."""
        self.streams.host.advance(now_ms)
        new = self.monitor.advance(now_ms)
        self.events.extend(new)
        return new

    def of(self, kind: EventKind) -> list[MonitorEvent]:
        """Events of one kind so far."""
        return [event for event in self.events if event.kind is kind]
