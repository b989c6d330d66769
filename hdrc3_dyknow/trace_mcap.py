"""State traces from recorded flights (MCAP files with CDR messages and ``ros2msg`` schemas).

Each fluent is mapped to a field of a topic, written ``FLUENT=TOPIC.FIELD`` where the field is
the dotted path after the topic's last ``/`` segment, e.g.
``altitude(uav0)=/uav0/helicopter_state.altitude`` or ``z=/uav0/pose.pose.position.z``; a path
element that is a number indexes an array. A fluent's value in a state is that field of the
latest message on its topic at the state's time.

States start once every mapped topic has delivered a message. They are emitted at each message
time (messages with equal log times form one state) or, with ``period_ms``, on a regular grid
starting at that first complete time. State times are in ms since the first message read.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from hdrc3_base.errors import ConfigError, DataError
from hdrc3_dyknow.interpretation import FluentValue, State, atom_key, parse_atom_key

NS_PER_MS = 1_000_000


@dataclass(frozen=True, slots=True)
class FluentSource:
    """Where a fluent's values come from.

    Attributes:
        fluent: Ground atom key of the fluent.
        topic: Topic name, e.g. ``/uav0/helicopter_state``.
        field: Path of the field inside the message, e.g. ``("pose", "position", "z")``.

    """

    fluent: str
    topic: str
    field: tuple[str, ...]


def parse_fluent_source(text: str) -> FluentSource:
    """Parse ``FLUENT=TOPIC.FIELD``.

    Raises:
        ConfigError: The mapping is malformed.

    """
    fluent, sep, location = text.partition("=")
    slash = location.rfind("/")
    dot = location.find(".", slash + 1)
    if not sep or not location.startswith("/") or dot < 0:
        raise ConfigError(f"--map {text!r}: expected FLUENT=/TOPIC.FIELD, e.g. alt=/uav0/state.z")
    field = tuple(location[dot + 1 :].split("."))
    if any(not part for part in field):
        raise ConfigError(f"--map {text!r}: empty field name")
    try:
        name, args = parse_atom_key(fluent)
    except DataError as exc:
        raise ConfigError(f"--map {text!r}: {exc}") from None
    return FluentSource(atom_key(name, args), location[:dot], field)


def read_trace_mcap(
    path: Path, sources: Sequence[FluentSource], period_ms: float | None = None
) -> Iterator[State]:
    """Yield the states of a recording (see the module docstring).

    Raises:
        ConfigError: No mapping, a bad period, or a mapped topic missing from the file.
        DataError: The file is unreadable or a field is missing or not a scalar.

    """
    if not sources:
        raise ConfigError("give at least one --map FLUENT=/TOPIC.FIELD")
    if period_ms is not None and not (math.isfinite(period_ms) and period_ms > 0):
        raise ConfigError(f"--period-ms must be a positive number, not {period_ms}")
    try:
        stream = path.open("rb")
    except OSError as exc:
        raise DataError(f"cannot read recording {path}: {exc.strerror}") from None
    with stream:
        try:
            reader = make_reader(stream, decoder_factories=[DecoderFactory()])
            summary = reader.get_summary()
            recorded = {channel.topic for channel in summary.channels.values()} if summary else None
            missing = sorted({s.topic for s in sources} - recorded) if recorded is not None else []
            if missing:
                raise ConfigError(f"{path} has no topic {', '.join(missing)}")
            messages = reader.iter_decoded_messages(topics=sorted({s.topic for s in sources}))
            yield from _States(sources, period_ms).run(
                (message.log_time, channel.topic, decoded)
                for _schema, channel, message, decoded in messages
            )
        except McapError as exc:
            raise DataError(f"recording {path} is unreadable: {exc}") from None


class _States:
    """Turns (log time, topic, message) triples in log-time order into states."""

    def __init__(self, sources: Sequence[FluentSource], period_ms: float | None) -> None:
        self._sources = sources
        self._period = period_ms
        self._latest: dict[str, object] = {}
        self._origin_ns: int | None = None
        self._grid: float | None = None  # next grid time in period mode

    def run(self, messages: Iterator[tuple[int, str, object]]) -> Iterator[State]:
        pending_ns: int | None = None
        for log_ns, topic, message in messages:
            if self._origin_ns is None:
                self._origin_ns = log_ns
            if pending_ns is not None and log_ns != pending_ns:
                # Every message of instant pending_ns is in: its values hold until log_ns.
                yield from self._emit(pending_ns, log_ns)
            self._latest[topic] = message
            pending_ns = log_ns
        if pending_ns is not None:
            yield from self._emit(pending_ns, None)

    def _emit(self, time_ns: int, next_ns: int | None) -> Iterator[State]:
        if not all(source.topic in self._latest for source in self._sources):
            return
        time_ms = self._ms(time_ns)
        if self._period is None:
            yield self._state(time_ms)
            return
        if self._grid is None:
            self._grid = time_ms
        if next_ns is None:
            while self._grid <= time_ms:  # last instant: grid points up to it
                yield self._state(self._grid)
                self._grid += self._period
            return
        end = self._ms(next_ns)
        while self._grid < end:
            yield self._state(self._grid)
            self._grid += self._period

    def _ms(self, time_ns: int) -> float:
        assert self._origin_ns is not None
        return (time_ns - self._origin_ns) / NS_PER_MS

    def _state(self, time_ms: float) -> State:
        values = {
            source.fluent: _field(self._latest[source.topic], source) for source in self._sources
        }
        return State(time_ms, values)


def _field(message: object, source: FluentSource) -> FluentValue:
    value = message
    for part in source.field:
        try:
            value = value[int(part)] if part.isdigit() else getattr(value, part)  # type: ignore[index]
        except (AttributeError, IndexError, TypeError, KeyError):
            raise DataError(
                f"{source.topic} messages have no field {'.'.join(source.field)!r} "
                f"(needed for fluent {source.fluent!r})"
            ) from None
    if isinstance(value, bool | int | float | str):
        return value
    raise DataError(
        f"field {'.'.join(source.field)!r} of {source.topic} is a {type(value).__name__}, "
        f"not a number, boolean or string (fluent {source.fluent!r})"
    )
