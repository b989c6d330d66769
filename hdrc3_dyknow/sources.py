"""Stream catalogue: turns stream specifications into sources, function units and annotations.

Sources make external information available as streams (section 8.1): here the fields of the
Data Interface message ``HelicopterState`` (section 6.2.4) and of the payload hook's ``carrying``
sensor ``HookState`` (sections 9.3, 11.1.2), read duck-typed so this module never imports ROS.
:data:`MESSAGE_SOURCES` is the one table of what a topic source may read: each message type with
its fields; the catalogue derives every topic's type from it (:meth:`StreamCatalog.topic_types`),
so the ROS adapters subscribe with the right type and keep no table of their own. Function
units compute streams from synchronised input streams, e.g. ``xy_dist``
of two positions (the ``XYDist`` feature of section 8.5). Loading a specification validates
every declaration against the ontology first and applies nothing if any is wrong.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import pymap3d

from hdrc3_dyknow.knowledge_process import FunctionUnit, KnowledgeProcessHost
from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.sample import Sample, StreamError, Value, check_value, ms_from_ns
from hdrc3_dyknow.semantic_matching import StreamSemantics
from hdrc3_dyknow.semantic_spec import (
    FunctionSource,
    SpecError,
    StreamDecl,
    StreamSpec,
    TopicSource,
)
from hdrc3_dyknow.state_sync import StateSynchronizer

Extractor = Callable[[Any], Value]


def _position(msg: Any) -> Value:
    return (float(msg.latitude), float(msg.longitude), float(msg.altitude))


HELICOPTER_STATE_FIELDS: Mapping[str, Extractor] = {
    "latitude": lambda m: float(m.latitude),
    "longitude": lambda m: float(m.longitude),
    "altitude": lambda m: float(m.altitude),
    "velocity_north": lambda m: float(m.velocity_north),
    "velocity_east": lambda m: float(m.velocity_east),
    "velocity_up": lambda m: float(m.velocity_up),
    "pitch": lambda m: float(m.pitch),
    "roll": lambda m: float(m.roll),
    "heading": lambda m: float(m.heading),
    "rpm": lambda m: float(m.rpm),
    "on_ground_flag": lambda m: bool(m.on_ground_flag),
    "auto_flag": lambda m: bool(m.auto_flag),
    "power_status": lambda m: int(m.power_status),
    "position": _position,
    "ground_speed": lambda m: math.hypot(float(m.velocity_north), float(m.velocity_east)),
    "speed": lambda m: math.sqrt(
        float(m.velocity_north) ** 2 + float(m.velocity_east) ** 2 + float(m.velocity_up) ** 2
    ),
}
"""Fields of ``hdrc3_interfaces/msg/HelicopterState`` a topic source may read (plus derived)."""

HOOK_STATE_FIELDS: Mapping[str, Extractor] = {
    "carrying": lambda m: bool(m.carrying),
    "object_id": lambda m: str(m.object_id),
    "magnet": lambda m: bool(m.magnet),
    "winch": lambda m: int(m.winch),
    "cable_length": lambda m: float(m.cable_length),
    "tension": lambda m: float(m.tension),
}
"""Fields of ``hdrc3_interfaces/msg/HookState`` (the ``carrying`` sensor) a source may read."""


@dataclass(frozen=True, slots=True)
class MessageSource:
    """A message type topic sources read: its full ROS type name and readable fields."""

    type_name: str
    """``package/msg/Type``."""
    fields: Mapping[str, Extractor]


MESSAGE_SOURCES: Mapping[str, MessageSource] = {
    "HelicopterState": MessageSource(
        "hdrc3_interfaces/msg/HelicopterState", HELICOPTER_STATE_FIELDS
    ),
    "HookState": MessageSource("hdrc3_interfaces/msg/HookState", HOOK_STATE_FIELDS),
}
"""Message types a specification may name after ``type`` (default ``HelicopterState``)."""


def _equals(extract: Extractor, text: str) -> Extractor:
    """Whether the field's value equals ``text`` (a boolean stream of one tag)."""
    return lambda m: str(extract(m)) == text


def _enu(values: Sequence[Value]) -> tuple[float, float, float]:
    first, second = values
    if not (isinstance(first, tuple) and isinstance(second, tuple)):
        raise StreamError(f"expected two (lat, lon, alt) positions, got {values!r}")
    lat, lon, alt = (float(v) for v in first)  # type: ignore[arg-type]
    lat0, lon0, alt0 = (float(v) for v in second)  # type: ignore[arg-type]
    east, north, up = pymap3d.geodetic2enu(lat, lon, alt, lat0, lon0, alt0)
    return float(east), float(north), float(up)


def xy_dist(values: Sequence[Value]) -> Value:
    """Horizontal distance (m) between two WGS84 positions (lat deg, lon deg, alt m)."""
    east, north, _ = _enu(values)
    return math.hypot(east, north)


def distance(values: Sequence[Value]) -> Value:
    """3-D distance (m) between two WGS84 positions."""
    return math.hypot(*_enu(values))


def difference(values: Sequence[Value]) -> Value:
    """First number minus the second."""
    first, second = values
    if isinstance(first, bool | str | tuple) or isinstance(second, bool | str | tuple):
        raise StreamError(f"difference needs two numbers, got {values!r}")
    return float(first) - float(second)


FUNCTIONS: Mapping[str, tuple[int, Callable[[Sequence[Value]], Value]]] = {
    "xy_dist": (2, xy_dist),
    "distance": (2, distance),
    "difference": (2, difference),
}
"""Functions a function source may apply: name -> (number of inputs, function)."""


@dataclass(frozen=True, slots=True)
class TopicBinding:
    """One field of one topic feeding one stream."""

    label: str
    field: str
    extract: Extractor
    message: str
    """Key of the message type in :data:`MESSAGE_SOURCES`."""


class StreamCatalog:
    """Applies specifications to a host, the ontology and the stream semantics manager."""

    def __init__(
        self,
        host: KnowledgeProcessHost,
        ontology: Ontology,
        semantics: StreamSemantics,
        default_period_ms: int = 100,
        default_max_delay_ms: int = 200,
    ) -> None:
        self.host = host
        self.ontology = ontology
        self.semantics = semantics
        self.default_period_ms = default_period_ms
        self.default_max_delay_ms = default_max_delay_ms
        self.rejected: dict[str, int] = {}
        self._topics: dict[str, dict[str, TopicBinding]] = {}

    def topics(self) -> list[str]:
        """Topics that sources read, sorted."""
        return sorted(topic for topic, bindings in self._topics.items() if bindings)

    def topic_types(self) -> dict[str, str]:
        """Each topic sources read -> its full message type name (``package/msg/Type``)."""
        return {
            topic: MESSAGE_SOURCES[next(iter(bindings.values())).message].type_name
            for topic, bindings in sorted(self._topics.items())
            if bindings
        }

    def load(self, spec: StreamSpec) -> list[str]:
        """Validate and apply a specification; return the declared labels.

        Raises:
            SpecError: A declaration names an unknown sort, feature, object, field, function or
                input stream (nothing is applied then).

        """
        source = spec.source
        objects = {obj for decl in spec.objects for obj in decl.names}
        for decl in spec.objects:
            if self.ontology.sort(decl.sort) is None:
                raise SpecError(
                    f"unknown sort {decl.sort!r}; known sorts: {', '.join(self.ontology.sorts())}",
                    source,
                    decl.line,
                    decl.column,
                )
        labels = set(self.host.labels())
        # a topic has one message type: the one its other streams (here or loaded) read
        replaced = {stream.label for stream in spec.streams}
        types = {
            topic: b.message
            for topic, bindings in self._topics.items()
            for b in bindings.values()
            if b.label not in replaced
        }
        for stream in spec.streams:
            self._check(stream, objects, labels, source, types)
            labels.add(stream.label)
        for decl in spec.objects:
            for name in decl.names:
                self.ontology.add_object(name, decl.sort)
        for stream in spec.streams:
            self._apply(stream)
        return [stream.label for stream in spec.streams]

    def _check_topic(
        self, source: TopicSource, fail: Callable[[str], SpecError], types: dict[str, str]
    ) -> None:
        message = MESSAGE_SOURCES.get(source.message)
        if message is None:
            raise fail(f"unknown message type {source.message!r}; known: {sorted(MESSAGE_SOURCES)}")
        if source.field not in message.fields:
            known = ", ".join(sorted(message.fields))
            raise fail(f"unknown field {source.field!r}; {source.message} fields: {known}")
        seen = types.setdefault(source.topic, source.message)
        if seen != source.message:
            raise fail(f"topic {source.topic!r} carries {seen}, not {source.message}")

    def _check(
        self,
        decl: StreamDecl,
        objects: set[str],
        labels: set[str],
        source: str,
        types: dict[str, str],
    ) -> None:
        def fail(message: str) -> SpecError:
            return SpecError(f"stream {decl.label!r}: {message}", source, decl.line, decl.column)

        feature = self.ontology.feature(decl.term.feature)
        if feature is None:
            raise fail(f"unknown feature {decl.term.feature!r} (not in the ontology)")
        arity = self.ontology.arity(feature)
        if arity is not None and arity != len(decl.term.args):
            raise fail(f"feature {feature} takes {arity} objects, got {len(decl.term.args)}")
        for arg in decl.term.args:
            if arg not in objects and not self.ontology.is_object(arg):
                raise fail(f"unknown object {arg!r}; declare it with 'object {arg} : <Sort>;'")
        if isinstance(decl.source, TopicSource):
            self._check_topic(decl.source, fail, types)
        if isinstance(decl.source, FunctionSource):
            if decl.source.function not in FUNCTIONS:
                raise fail(f"unknown function {decl.source.function!r}; known: {sorted(FUNCTIONS)}")
            count = FUNCTIONS[decl.source.function][0]
            if count != len(decl.source.inputs):
                raise fail(f"{decl.source.function} takes {count} input streams")
            for label in decl.source.inputs:
                if label not in labels:
                    raise fail(f"unknown input stream {label!r}")

    def _apply(self, decl: StreamDecl) -> None:
        label = decl.label
        self._unbind(label)
        policy = decl.policy
        if isinstance(decl.source, FunctionSource):
            # The unit's synchroniser already applies period and delay; its output is periodic.
            policy = replace(policy, sample_period_ms=0, max_delay_ms=0)
        self.host.declare(label, policy, decl.annotation)
        self.semantics.annotate(label, decl.term)
        if isinstance(decl.source, TopicSource):
            topic = decl.source
            extract = MESSAGE_SOURCES[topic.message].fields[topic.field]
            if topic.equals is not None:
                extract = _equals(extract, topic.equals)
            binding = TopicBinding(label, topic.field, extract, topic.message)
            self._topics.setdefault(decl.source.topic, {})[label] = binding
        elif isinstance(decl.source, FunctionSource):
            function = FUNCTIONS[decl.source.function][1]
            inputs = decl.source.inputs
            sync = StateSynchronizer(
                inputs,
                decl.policy.sample_period_ms or self.default_period_ms,
                decl.policy.max_delay_ms or self.default_max_delay_ms,
            )
            unit = FunctionUnit(inputs, label, function, sync)
            self.host.add_process(
                "function:" + label, unit, dict.fromkeys(inputs, Policy()), [label]
            )

    def _unbind(self, label: str) -> None:
        for bindings in self._topics.values():
            bindings.pop(label, None)
        self.host.remove_process("function:" + label)

    def on_message(self, topic: str, message: Any, available_ms: int) -> int:
        """Publish the bound fields of one message of ``topic``; return samples published.

        The valid time is the message's header stamp (its available time if the stamp is
        zero); values that are not finite are counted in :attr:`rejected`, never published.
        """
        stamp = message.header.stamp
        valid_ms = ms_from_ns(int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec))
        valid_ms = valid_ms or available_ms
        published = 0
        for binding in self._topics.get(topic, {}).values():
            try:
                value = check_value(binding.extract(message))
            except StreamError:
                self.rejected[binding.label] = self.rejected.get(binding.label, 0) + 1
                continue
            self.host.publish(binding.label, Sample(valid_ms, available_ms, value))
            published += 1
        return published
