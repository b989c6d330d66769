"""What goes on the wire of one live channel: its schema and encoded messages.

Foxglove's well-known schemas come from the SDK (``foxglove.messages.X.get_schema()``, protobuf);
channels of our own use JSON with a JSON Schema. :func:`decode` turns protobuf bytes back into a
message with the SDK's own descriptor set (protobuf's dynamic message factory), so tests and tools
read exactly what a client receives.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Protocol

from google.protobuf import descriptor_pb2, descriptor_pool, message_factory
from google.protobuf.message import Message

PROTOBUF = "protobuf"
JSON = "json"


class WellKnown(Protocol):
    """A Foxglove SDK message class (``foxglove.messages.SceneUpdate``, ...)."""

    @staticmethod
    def get_schema() -> Any:
        """The SDK schema (name, encoding, data)."""


@dataclass(frozen=True, slots=True)
class WireSchema:
    """Schema of one channel: name, schema encoding, schema bytes, message encoding."""

    name: str
    encoding: str
    data: bytes
    message_encoding: str

    @staticmethod
    def well_known(message_class: WellKnown) -> WireSchema:
        """The protobuf schema of a Foxglove well-known message class."""
        schema = message_class.get_schema()
        return WireSchema(str(schema.name), str(schema.encoding), bytes(schema.data), PROTOBUF)

    @staticmethod
    def json_schema(name: str, properties: dict[str, Any]) -> WireSchema:
        """A JSON channel whose messages are objects with ``properties``."""
        schema = {"title": name, "type": "object", "properties": properties}
        return WireSchema(name, "jsonschema", json.dumps(schema).encode(), JSON)


def encode_json(payload: dict[str, Any]) -> bytes:
    """Bytes of one JSON message."""
    return json.dumps(payload, separators=(",", ":")).encode()


def decode(schema: WireSchema, data: bytes) -> Message | dict[str, Any]:
    """Decode one message of a channel (a protobuf message, or a dict for JSON channels)."""
    if schema.message_encoding == JSON:
        decoded: dict[str, Any] = json.loads(data)
        return decoded
    files = descriptor_pb2.FileDescriptorSet.FromString(schema.data)
    pool = descriptor_pool.DescriptorPool()
    for file in files.file:
        pool.Add(file)
    cls = message_factory.GetMessageClass(pool.FindMessageTypeByName(schema.name))
    return cls.FromString(data)
