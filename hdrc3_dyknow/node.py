"""The ``dyknow`` ROS 2 node: DyKnow stream processing, semantic matching and monitoring.

Sources read topics (the Data Interface's ``HelicopterState``, the hook's ``HookState``: the
message types of ``sources.MESSAGE_SOURCES``, each subscribed with the type the catalogue
derives) named in stream specifications loaded at run time (parameters ``spec_file``/``spec``,
service ``~/load_streams``).
``~/monitor`` (``MonitorFormula``) starts or stops monitoring a formula over streams found by
semantic matching; verdicts go out as ``MonitorVerdict`` on the requested topic. ``~/list_streams``
(``ListStreams``) introspects streams, policies and rates. Time is the node's ROS clock (``/clock``
when ``use_sim_time`` is set), converted to stream milliseconds. This is the only module of
:mod:`hdrc3_dyknow` that imports rclpy.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Sequence
from functools import partial
from pathlib import Path
from typing import Any

from builtin_interfaces.msg import Time
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.subscription import Subscription

from hdrc3_base.errors import ConfigError, Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults
from hdrc3_base.ros_runtime import run_node
from hdrc3_dyknow.coordinator import (
    MonitorResult,
    MonitorStatus,
    StreamReasoningCoordinator,
    VerdictEvent,
)
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.progression import Verdict
from hdrc3_dyknow.sample import ms_from_ns
from hdrc3_dyknow.semantic_matching import SemanticMatcher, StreamSemantics
from hdrc3_dyknow.semantic_spec import SpecError, SpecSyntaxError, TopicSource, parse_spec
from hdrc3_dyknow.sources import StreamCatalog
from hdrc3_interfaces.msg import MonitorVerdict, StreamInfo
from hdrc3_interfaces.srv import ListStreams, LoadStreamSpec, MonitorFormula

DEFAULT_VERDICT_TOPIC = "~/verdicts"
_VERDICTS = {
    Verdict.UNDECIDED: MonitorVerdict.VERDICT_UNKNOWN,
    Verdict.TRUE: MonitorVerdict.VERDICT_TRUE,
    Verdict.FALSE: MonitorVerdict.VERDICT_FALSE,
}
_CODES = {
    MonitorStatus.STARTED: MonitorFormula.Response.OK,
    MonitorStatus.STOPPED: MonitorFormula.Response.OK,
    MonitorStatus.BAD_REQUEST: MonitorFormula.Response.BAD_REQUEST,
    MonitorStatus.PARSE_ERROR: MonitorFormula.Response.PARSE_ERROR,
    MonitorStatus.UNKNOWN_SYMBOL: MonitorFormula.Response.UNKNOWN_SYMBOL,
    MonitorStatus.NOT_FOUND: MonitorFormula.Response.NOT_FOUND,
}
# Verdicts are latched so a client subscribing right after its start request sees them all.
_VERDICT_QOS = QoSProfile(
    depth=100, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)


def message_class(type_name: str) -> Any:
    """The generated class of ``package/msg/Type`` (a type of ``sources.MESSAGE_SOURCES``)."""
    package, _, name = type_name.split("/")
    return getattr(importlib.import_module(f"{package}.msg"), name)


def subscribe_sources(
    node: Node, catalog: StreamCatalog, known: dict[str, Subscription], callback: Any
) -> None:
    """Subscribe ``node`` to every topic of ``catalog`` not in ``known``, with its type.

    ``callback(topic, msg)`` receives each message; ``known`` gains the new subscriptions.
    """
    for topic, type_name in catalog.topic_types().items():
        if topic not in known:
            known[topic] = node.create_subscription(
                message_class(type_name), topic, partial(callback, topic), 50
            )


class DyKnowNode(Node):
    """ROS adapter around the DyKnow core (host, catalog, ontology, coordinator)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("dyknow", **kwargs)
        spec_file = self.declare_parameter("spec_file", "").value
        spec_text = self.declare_parameter("spec", "").value
        ontology_file = self.declare_parameter("ontology_file", "").value
        self._period_ms = int(self.declare_parameter("state_period_ms", 100).value)
        self._max_delay_ms = int(self.declare_parameter("max_delay_ms", 200).value)
        tick_s = float(self.declare_parameter("tick_period_s", 0.05).value)
        if not tick_s > 0 or self._period_ms <= 0 or self._max_delay_ms < 0:
            raise ConfigError(
                f"need tick_period_s > 0, state_period_ms > 0, max_delay_ms >= 0; got {tick_s},"
                f" {self._period_ms}, {self._max_delay_ms}"
            )

        self._host = KnowledgeProcessHost()
        self._semantics = StreamSemantics()
        self._ontology = Ontology.load(Path(ontology_file) if ontology_file else None)
        self._catalog = StreamCatalog(
            self._host, self._ontology, self._semantics, self._period_ms, self._max_delay_ms
        )
        self._coordinator = StreamReasoningCoordinator(
            self._host, SemanticMatcher(self._ontology, self._semantics)
        )
        self._topic_subscriptions: dict[str, Subscription] = {}
        self._verdict_topics: dict[str, str] = {}
        self._verdict_publishers: dict[str, Publisher] = {}
        self.bad_messages = 0

        for text, source in ((self._read(spec_file), spec_file), (spec_text, "<spec parameter>")):
            if text:
                error, reason, _ = self._load(text, source)
                if error is not None:
                    self.get_logger().error(reason)

        self.create_service(MonitorFormula, "~/monitor", self._on_monitor)
        self.create_service(ListStreams, "~/list_streams", self._on_list_streams)
        self.create_service(LoadStreamSpec, "~/load_streams", self._on_load_streams)
        self.create_timer(tick_s, self._tick)
        self.get_logger().info(
            f"dyknow ready: {len(self._host.labels())} streams, topics {self._catalog.topics()}"
        )

    def _read(self, path: str) -> str:
        if not path:
            return ""
        try:
            return Path(path).read_text(encoding="utf-8")
        except OSError as exc:
            self.get_logger().error(f"cannot read spec_file {path}: {exc}")
            return ""

    def _now_ms(self) -> int:
        return ms_from_ns(self.get_clock().now().nanoseconds)

    def _load(self, text: str, source: str) -> tuple[Hdrc3Error | None, str, list[str]]:
        try:
            spec = parse_spec(text, source)
            for decl in spec.streams:
                if isinstance(decl.source, TopicSource):
                    self._check_topic(decl.source.topic, source, decl.line, decl.column)
            labels = self._catalog.load(spec)
        except Hdrc3Error as exc:
            return exc, str(exc), []
        subscribe_sources(self, self._catalog, self._topic_subscriptions, self._on_state)
        return None, f"loaded {len(labels)} streams", labels

    def _check_topic(self, topic: str, source: str, line: int, column: int) -> None:
        try:
            self.resolve_topic_name(topic)
        except Exception as exc:  # rclpy raises several types for invalid names
            raise SpecError(f"invalid topic name {topic!r}: {exc}", source, line, column) from None

    def _on_state(self, topic: str, msg: Any) -> None:
        try:
            self._catalog.on_message(topic, msg, self._now_ms())
        except Hdrc3Error as exc:  # one bad message must not stop the node
            self.bad_messages += 1
            self.get_logger().warning(f"dropped message on {topic}: {exc}", throttle_duration_sec=5)

    def _tick(self) -> None:
        self._host.advance(self._now_ms())
        for event in self._coordinator.drain():
            self._publish(event)

    def _publish(self, event: VerdictEvent) -> None:
        topic = self._verdict_topics.get(event.monitor_id)
        if topic is None:
            return
        msg = MonitorVerdict()
        msg.stamp = Time(sec=event.time // 1000, nanosec=(event.time % 1000) * 1_000_000)
        msg.monitor_id = event.monitor_id
        msg.formula = event.formula
        msg.verdict = _VERDICTS[event.verdict]
        msg.residual = event.residual
        msg.states = event.states
        self._verdict_publishers[topic].publish(msg)

    def _on_monitor(
        self, request: MonitorFormula.Request, response: MonitorFormula.Response
    ) -> MonitorFormula.Response:
        if request.action == MonitorFormula.Request.STOP:
            result = self._coordinator.stop(request.monitor_id)
            self._verdict_topics.pop(request.monitor_id, None)
        elif request.action == MonitorFormula.Request.START:
            topic = request.verdict_topic or DEFAULT_VERDICT_TOPIC
            if topic not in self._verdict_publishers:
                try:
                    self._verdict_publishers[topic] = self.create_publisher(
                        MonitorVerdict, topic, _VERDICT_QOS
                    )
                except Exception as exc:  # rclpy raises several types for bad topic names
                    response.code = MonitorFormula.Response.BAD_REQUEST
                    response.reason = f"invalid verdict topic {topic!r}: {exc}"
                    return response
            period = request.state_period_ms or self._period_ms
            delay = self._max_delay_ms if request.max_delay_ms < 0 else request.max_delay_ms
            try:
                result = self._coordinator.start(request.monitor_id, request.formula, period, delay)
            except Hdrc3Error as exc:  # unexpected misuse still gets an answer, not a crash
                result = MonitorResult(MonitorStatus.BAD_REQUEST, str(exc))
            if result.status is MonitorStatus.STARTED:
                self._verdict_topics[request.monitor_id] = topic
                response.verdict_topic = self._verdict_publishers[topic].topic_name
        else:
            response.code = MonitorFormula.Response.BAD_REQUEST
            response.reason = f"unknown action {request.action}; use START=0 or STOP=1"
            return response
        response.code = _CODES[result.status]
        response.reason = result.reason
        response.streams = list(result.streams)
        return response

    def _on_list_streams(
        self, request: ListStreams.Request, response: ListStreams.Response
    ) -> ListStreams.Response:
        for status in self._host.status():
            if not status.label.startswith(request.label_prefix):
                continue
            term = self._semantics.annotation(status.label)
            policy, stats = status.policy, status.stats
            response.streams.append(
                StreamInfo(
                    label=status.label,
                    annotation=status.annotation,
                    feature=term.feature if term else "",
                    objects=list(term.args) if term else [],
                    ordered=policy.ordered,
                    change_only=policy.change_only,
                    sample_period_ms=policy.sample_period_ms,
                    max_delay_ms=policy.max_delay_ms,
                    late_handling=policy.late.value,
                    missing_handling=policy.missing.value,
                    samples_in=stats.samples_in,
                    samples_out=stats.samples_out,
                    out_of_order=stats.out_of_order,
                    duplicates=stats.duplicates,
                    late=stats.late,
                    rate_hz=status.rate_hz,
                    last_valid_time_ms=-1
                    if status.last_valid_time is None
                    else status.last_valid_time,
                )
            )
        return response

    def _on_load_streams(
        self, request: LoadStreamSpec.Request, response: LoadStreamSpec.Response
    ) -> LoadStreamSpec.Response:
        error, reason, labels = self._load(request.spec, "<load_streams request>")
        if error is None:
            response.code = LoadStreamSpec.Response.OK
        elif isinstance(error, SpecSyntaxError):
            response.code = LoadStreamSpec.Response.PARSE_ERROR
        else:
            response.code = LoadStreamSpec.Response.BAD_SPEC
        response.reason = reason
        response.labels = labels
        return response


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``hdrc3-dyknow``; accepts standard ``--ros-args`` (e.g. ``-r __ns:=/uav0``)."""
    apply_dds_defaults()
    try:
        return run_node(
            lambda context: DyKnowNode(context=context), sys.argv if argv is None else argv
        )
    except Hdrc3Error as exc:
        print(f"hdrc3-dyknow: error: {exc}", file=sys.stderr)
        return 2
