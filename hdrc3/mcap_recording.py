"""MCAP files in the rosbag2 layout: a writer for recordings and a tolerant reader for replay.

Messages are stored as CDR bytes exactly as they came off the wire, on channels whose schema is the
full ``ros2msg`` definition text, so Foxglove, ``ros2 bag`` and mcap-ros2-support decode them
without access to this installation. The writer closes a chunk at least every ``flush_period_ns``
of log time (and whenever :meth:`RecordingWriter.flush` is called), so a recorder killed mid-write
leaves a file that is readable up to its last complete chunk.
"""

from __future__ import annotations

import io
import struct
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from mcap.exceptions import EndOfFile
from mcap.reader import make_reader
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from hdrc3 import __version__
from hdrc3.message_types import DefinitionResolver, MessageTypeName
from hdrc3_base.errors import DataError, Hdrc3Error

ROS2_PROFILE = "ros2"
SCHEMA_ENCODING = "ros2msg"
MESSAGE_ENCODING = "cdr"


@dataclass(frozen=True, slots=True)
class TopicInfo:
    """A recorded topic: its name, message type and the QoS its publishers offered (YAML)."""

    topic: str
    type_name: str
    offered_qos_profiles: str = ""


@dataclass(frozen=True, slots=True)
class RecordedMessage:
    """One message read back from a recording, still CDR-serialised."""

    topic: str
    type_name: str
    data: bytes
    log_time_ns: int
    publish_time_ns: int


class RecordingWriter:
    """Writes CDR messages to an MCAP file in the rosbag2 layout."""

    def __init__(
        self,
        path: str | Path,
        resolver: DefinitionResolver | None = None,
        chunk_size: int = 256 * 1024,
        flush_period_ns: int = 1_000_000_000,
    ) -> None:
        """Create (truncate) ``path`` and write the MCAP header.

        Args:
            path: Output file.
            resolver: Source of message definitions; one over the installed share dirs by default.
            chunk_size: Uncompressed bytes after which a chunk is closed.
            flush_period_ns: Log-time span after which the open chunk is closed and flushed.

        """
        self.path = Path(path)
        try:
            self._stream: IO[bytes] = self.path.open("wb")
        except OSError as exc:
            raise DataError(f"cannot create {self.path}: {exc.strerror}") from exc
        self._resolver = resolver or DefinitionResolver()
        self._writer = Writer(self._stream, chunk_size=chunk_size, compression=CompressionType.ZSTD)
        self._writer.start(profile=ROS2_PROFILE, library=f"hdrc3 {__version__}")
        self._flush_period_ns = flush_period_ns
        self._last_flush_ns: int | None = None
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self.message_count = 0
        self._closed = False

    @property
    def topics(self) -> list[str]:
        """Topics that have a channel in the file."""
        return list(self._channels)

    def add_topic(self, info: TopicInfo) -> None:
        """Register the channel (and its schema, once per type) for a topic."""
        if info.topic in self._channels:
            return
        type_name = str(MessageTypeName.parse(info.type_name))
        schema_id = self._schemas.get(type_name)
        if schema_id is None:
            definition = self._resolver.full_definition(type_name)
            schema_id = self._writer.register_schema(
                name=type_name, encoding=SCHEMA_ENCODING, data=definition.encode()
            )
            self._schemas[type_name] = schema_id
        metadata = {"offered_qos_profiles": info.offered_qos_profiles}
        self._channels[info.topic] = self._writer.register_channel(
            topic=info.topic,
            message_encoding=MESSAGE_ENCODING,
            schema_id=schema_id,
            metadata=metadata,
        )

    def add_channel(
        self, topic: str, schema: tuple[str, str, bytes], message_encoding: str
    ) -> None:
        """Register a channel that is not a ROS topic (the live view's Foxglove channels).

        Args:
            topic: Channel name.
            schema: (name, encoding, data) of its schema, e.g. a protobuf descriptor set.
            message_encoding: Encoding of its messages, e.g. ``protobuf`` or ``json``.
        """
        if topic in self._channels:
            return
        name, encoding, data = schema
        schema_id = self._writer.register_schema(name=name, encoding=encoding, data=data)
        self._channels[topic] = self._writer.register_channel(
            topic=topic, message_encoding=message_encoding, schema_id=schema_id
        )

    def write(self, topic: str, data: bytes, log_time_ns: int, publish_time_ns: int = 0) -> None:
        """Append one serialised message on a topic registered with :meth:`add_topic`."""
        channel_id = self._channels.get(topic)
        if channel_id is None:
            raise Hdrc3Error(f"topic {topic} has no channel; call add_topic first")
        self._writer.add_message(
            channel_id=channel_id,
            log_time=log_time_ns,
            data=data,
            publish_time=publish_time_ns or log_time_ns,
            sequence=self.message_count,
        )
        self.message_count += 1
        if self._last_flush_ns is None:
            self._last_flush_ns = log_time_ns
        elif log_time_ns - self._last_flush_ns >= self._flush_period_ns:
            self.flush()
            self._last_flush_ns = log_time_ns

    def flush(self) -> None:
        """Close the open chunk and push everything written so far to the file."""
        if not self._closed:
            self._writer.flush()  # type: ignore[no-untyped-call]

    def close(self) -> None:
        """Write the summary section and footer, and close the file."""
        if self._closed:
            return
        self._closed = True
        try:
            self._writer.finish()  # type: ignore[no-untyped-call]
        finally:
            self._stream.close()


@dataclass
class RecordingReader:
    """Reads a recording front to back, tolerating a truncated tail (a killed recorder)."""

    path: Path
    truncated: bool = field(default=False, init=False)
    """True once reading stopped at an incomplete record instead of the footer."""

    @classmethod
    def open(cls, path: str | Path) -> RecordingReader:
        """Check that ``path`` exists and starts like an MCAP file."""
        file = Path(path)
        if not file.is_file():
            raise DataError(f"{file}: no such recording")
        with file.open("rb") as stream:
            magic = stream.read(8)
        if magic != b"\x89MCAP0\r\n":
            raise DataError(f"{file}: not an MCAP file (bad magic bytes)")
        return cls(file)

    def topics(self) -> dict[str, str]:
        """Map every recorded ROS topic (CDR) to its message type (reads the whole file).

        Channels in other encodings (the live view's Foxglove channels) are not ROS topics.
        """
        found: dict[str, str] = {}
        for schema, channel in self._channels_seen():
            if channel.message_encoding == MESSAGE_ENCODING:
                found[channel.topic] = schema.name if schema else ""
        return found

    def message_count(self, topics: Iterable[str] | None = None) -> int | None:
        """Messages (of ``topics``, or all) by the file's summary; None without one (truncated)."""
        try:
            with self.path.open("rb") as stream:
                summary = make_reader(stream).get_summary()
        except Exception:  # a file without a footer or summary: the caller counts as it reads
            return None
        if summary is None or summary.statistics is None:
            return None
        if topics is None:
            return int(summary.statistics.message_count)
        wanted = set(topics)
        counts = summary.statistics.channel_message_counts
        return sum(
            int(counts.get(channel_id, 0))
            for channel_id, channel in summary.channels.items()
            if channel.topic in wanted
        )

    def messages(self, topics: Iterable[str] | None = None) -> Iterator[RecordedMessage]:
        """Yield the recorded messages in file order, optionally only those of ``topics``."""
        wanted = None if topics is None else set(topics)
        schemas: dict[int, Schema] = {}
        channels: dict[int, Channel] = {}
        for record in self._records():
            if isinstance(record, Schema):
                schemas[record.id] = record
            elif isinstance(record, Channel):
                channels[record.id] = record
            elif isinstance(record, Message):
                channel = channels.get(record.channel_id)
                if channel is None:
                    raise DataError(f"{self.path}: message on unknown channel {record.channel_id}")
                if wanted is not None and channel.topic not in wanted:
                    continue
                schema = schemas.get(channel.schema_id)
                yield RecordedMessage(
                    topic=channel.topic,
                    type_name=schema.name if schema else "",
                    data=bytes(record.data),
                    log_time_ns=record.log_time,
                    publish_time_ns=record.publish_time,
                )

    def _channels_seen(self) -> Iterator[tuple[Schema | None, Channel]]:
        schemas: dict[int, Schema] = {}
        for record in self._records():
            if isinstance(record, Schema):
                schemas[record.id] = record
            elif isinstance(record, Channel):
                yield schemas.get(record.schema_id), record

    def _records(self) -> Iterator[object]:
        self.truncated = False
        with self.path.open("rb") as raw:
            stream = io.BufferedReader(raw)
            reader = StreamReader(stream, validate_crcs=True)
            try:
                yield from reader.records
            except (EndOfFile, EOFError, struct.error):
                # A record cut off by the end of the file: a recorder killed mid-write.
                self.truncated = True
            except Exception as exc:  # mcap, zstd and lz4 raise unrelated types for bad bytes
                raise DataError(f"{self.path}: corrupt MCAP data ({exc})") from exc
