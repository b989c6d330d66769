"""ROS 2 adapter: the ``execution_monitor`` node of one agent (chapter 9.3).

Reads the agent's Data Interface (``helicopter_state``, ``HelicopterState``), its payload hook's
carrying sensor (``sensors/carrying``, ``HookState``: ``carrying(agent, load)`` for each box and
carrier of the ``world`` parameter's world file) and its power unit
(``sensors/power``, ``PowerStatus``: voltage times current is the ``power`` fluent of Example
9.1) into DyKnow streams (:mod:`monitor_streams`, plus any ``stream_spec`` file), its execution
flags (``execution_flags``, ``ExecutionFlag``), and progresses the formulas of the
``monitor_spec`` file (:mod:`monitor_spec`; formulas flagged with ``generate`` are generated
from the planning domain of the ``domain_file`` parameter, :mod:`monitor_generation`) with an
:class:`~hdrc3_deliberative.execution_monitor.ExecutionMonitor`.

Publishes, in the agent's namespace:

* ``monitor_verdicts`` (``MonitorVerdict``): each formula's activation (UNKNOWN, with the formula
  as activated), its final verdict (TRUE/FALSE) or its retirement (UNKNOWN, residual);
* ``monitor_violations`` (``MonitorViolation``): violations, stale-data alarms and refused
  activations, with the recovery operator and brake request of the violated formula.

A specification that does not parse, or a formula over an unknown fluent, stops the node with
exit code 2 and the reason (``file:line:column``): it never runs without its formulas. Time is
the ROS clock (``/clock`` from ``world_sim`` unless ``sim_time`` is false), in milliseconds.
States are synthesised and progressed after every sample (a state complete with it is decided at
once) and on a timer (``tick_period_s``: states whose samples are late or missing).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from builtin_interfaces.msg import Time
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from hdrc3_base.errors import ConfigError, Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults
from hdrc3_base.ros_runtime import run_node
from hdrc3_deliberative.execution_monitor import (
    EventKind,
    ExecutionMonitor,
    FlagUpdate,
    MonitorEvent,
    StartStatus,
)
from hdrc3_deliberative.monitor_generation import expand, read_domain_file
from hdrc3_deliberative.monitor_spec import DEFAULT_SPEC, MonitorSpecParser
from hdrc3_deliberative.monitor_streams import MonitorStreams
from hdrc3_dyknow.node import subscribe_sources
from hdrc3_dyknow.sample import ms_from_ns
from hdrc3_interfaces.msg import (
    ExecutionFlag,
    MonitorVerdict,
    MonitorViolation,
    PowerStatus,
)
from sim.world import ObjectKind
from sim.world_loader import load_world

NODE_NAME = "execution_monitor"
_EVENT_QOS = QoSProfile(
    depth=200, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
_VERDICTS = {
    EventKind.ACTIVATED: MonitorVerdict.VERDICT_UNKNOWN,
    EventKind.RETIRED: MonitorVerdict.VERDICT_UNKNOWN,
    EventKind.SATISFIED: MonitorVerdict.VERDICT_TRUE,
    EventKind.VIOLATED: MonitorVerdict.VERDICT_FALSE,
}
_VIOLATIONS = {
    EventKind.VIOLATED: MonitorViolation.KIND_VIOLATION,
    EventKind.STALE_DATA: MonitorViolation.KIND_STALE_DATA,
    EventKind.REFUSED: MonitorViolation.KIND_REFUSED,
}


def world_loads(world: str) -> tuple[tuple[str, str], ...]:
    """(tag, ontology sort) of the boxes and carriers of ``world`` ("": none)."""
    if not world:
        return ()
    try:
        objects = load_world(world).objects
    except Hdrc3Error as exc:
        raise ConfigError(f"world {world!r}: {exc}") from None
    sorts = {ObjectKind.BOX: "Box", ObjectKind.CARRIER: "Carrier"}
    return tuple((o.id, sorts[o.kind]) for o in objects if o.kind in sorts)


def _stamp(ms: int) -> Time:
    return Time(sec=ms // 1000, nanosec=(ms % 1000) * 1_000_000)


class ExecutionMonitorNode(Node):
    """Execution monitor of one agent: DyKnow streams in, verdicts and violations out."""

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(NODE_NAME, context=context)
        self.declare_parameter("sim_time", True)
        if self.get_parameter("sim_time").value:
            self.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        spec_file = str(self.declare_parameter("monitor_spec", str(DEFAULT_SPEC)).value)
        stream_file = str(self.declare_parameter("stream_spec", "").value)
        ontology_file = str(self.declare_parameter("ontology_file", "").value)
        self.agent = str(self.declare_parameter("agent", "").value) or (
            self.get_namespace().strip("/") or "uav0"
        )
        tick_s = float(self.declare_parameter("tick_period_s", 0.05).value)
        if not tick_s > 0:
            raise ConfigError(f"tick_period_s must be > 0, got {tick_s}")

        domain_file = str(self.declare_parameter("domain_file", "").value)
        spec = MonitorSpecParser().parse_file(Path(spec_file))
        if domain_file:  # formulas generated for the flagged conditions (§9.3)
            spec = expand(spec, read_domain_file(Path(domain_file)))
        world = str(self.declare_parameter("world", "").value)
        self.streams = MonitorStreams.for_agent(
            self.agent, Path(ontology_file) if ontology_file else None, world_loads(world)
        )
        if stream_file:
            try:
                text = Path(stream_file).read_text(encoding="utf-8")
            except OSError as exc:
                raise ConfigError(f"cannot read stream_spec {stream_file}: {exc}") from None
            self.streams.load(text, stream_file)
        self.monitor = ExecutionMonitor(spec, self.streams.host, self.streams.matcher)
        self.bad_messages = 0
        self._started = False
        self._verdicts = self.create_publisher(MonitorVerdict, "monitor_verdicts", _EVENT_QOS)
        self._violations = self.create_publisher(MonitorViolation, "monitor_violations", _EVENT_QOS)
        subscribe_sources(self, self.streams.catalog, {}, self._on_state)
        self.create_subscription(ExecutionFlag, "execution_flags", self._on_flag, 50)
        self.create_subscription(PowerStatus, "sensors/power", self._on_power, 10)
        # Checked now so a bad formula stops the node at once; activated at the first tick.
        check = self.monitor.check()
        if check.status is not StartStatus.STARTED:
            raise ConfigError(check.reason)
        self.create_timer(tick_s, self._tick)
        self.get_logger().info(
            f"execution monitor of {self.agent}: {len(spec.monitors)} formulas from {spec_file}"
        )

    def _now_ms(self) -> int:
        return ms_from_ns(self.get_clock().now().nanoseconds)

    def _on_state(self, topic: str, msg: Any) -> None:
        now = self._now_ms()
        try:
            self.streams.catalog.on_message(topic, msg, now)
        except Hdrc3Error as exc:  # one bad message must not stop the node
            self.bad_messages += 1
            self.get_logger().warning(f"dropped message on {topic}: {exc}", throttle_duration_sec=5)
            return
        if self._started:  # a state complete with this sample is progressed now, not at the tick
            self._advance(now)

    def _on_power(self, msg: PowerStatus) -> None:
        stamp = ms_from_ns(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
        if not self.streams.publish_power(
            self.agent, stamp, self._now_ms(), msg.voltage, msg.current
        ):
            self.bad_messages += 1

    def _on_flag(self, msg: ExecutionFlag) -> None:
        names, values = list(msg.argument_names), list(msg.argument_values)
        if len(names) != len(values):
            self.bad_messages += 1
            self.get_logger().warning(
                f"execution flag of {msg.node_id}: {len(names)} argument names but"
                f" {len(values)} values; its arguments are ignored"
            )
            names = values = []
        stamp = ms_from_ns(msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec)
        flag = FlagUpdate(
            stamp or self._now_ms(),
            msg.agent or self.agent,
            msg.node_id,
            msg.action,
            bool(msg.executing),
            tuple(zip(names, values, strict=True)),
        )
        self._publish(self.monitor.on_flag(flag))

    def _tick(self) -> None:
        now = self._now_ms()
        if now <= 0:
            return  # no /clock yet
        if not self._started:
            result = self.monitor.start(now)
            self._started = True
            self.get_logger().info(f"monitoring started at {now} ms: {result.reason}")
        self._advance(now)

    def _advance(self, now: int) -> None:
        self.streams.host.advance(now)
        self._publish(self.monitor.advance(now))

    def _publish(self, events: Sequence[MonitorEvent]) -> None:
        for event in events:
            if event.kind in _VERDICTS:
                self._verdicts.publish(
                    MonitorVerdict(
                        stamp=_stamp(event.time_ms),
                        monitor_id=event.monitor_id,
                        formula=event.formula,
                        verdict=_VERDICTS[event.kind],
                        residual=event.formula if event.kind is EventKind.RETIRED else "",
                        states=event.states,
                    )
                )
            if event.kind in _VIOLATIONS:
                self._violations.publish(self._violation(event))
                self.get_logger().warning(
                    f"{event.kind.value}: {event.monitor_id} at {event.time_ms} ms:"
                    f" {event.formula} ({event.reason})"
                )
            elif event.kind is EventKind.DATA_RESUMED:
                self.get_logger().info(event.reason)

    def _violation(self, event: MonitorEvent) -> Any:
        msg = MonitorViolation(
            agent=self.agent,
            monitor_id=event.monitor_id,
            formula=event.formula,
            kind=_VIOLATIONS[event.kind],
            node_id=event.node_id,
            argument_names=[name for name, _ in event.arguments],
            argument_values=[value for _, value in event.arguments],
            reason=event.reason,
            activated=_stamp(event.activated_ms),
            states=event.states,
        )
        msg.header.stamp = _stamp(event.time_ms)
        if event.decl is not None:
            msg.action = event.decl.operator
            msg.recovery = event.decl.recovery
            msg.emergency_brake = event.decl.brake
        return msg


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``hdrc3-execution-monitor`` (``--ros-args -r __ns:=/uav0 -p monitor_spec:=FILE``)."""
    apply_dds_defaults()
    try:
        return run_node(
            lambda context: ExecutionMonitorNode(context), sys.argv if argv is None else argv
        )
    except Hdrc3Error as exc:
        print(f"hdrc3-execution-monitor: error: {exc}", file=sys.stderr)
        return 2
