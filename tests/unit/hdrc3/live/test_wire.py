from __future__ import annotations

import json

from foxglove.messages import Log, LogLevel

from hdrc3.live.wire import JSON, PROTOBUF, WireSchema, decode, encode_json


def test_well_known_schema_round_trips_a_message():
    schema = WireSchema.well_known(Log)
    assert (schema.name, schema.encoding, schema.message_encoding) == (
        "foxglove.Log",
        "protobuf",
        PROTOBUF,
    )
    msg = decode(schema, Log(level=LogLevel.Error, message="boom", name="uav0").encode())
    assert (msg.message, msg.name, msg.level) == ("boom", "uav0", LogLevel.Error.value)


def test_json_schema_and_messages():
    schema = WireSchema.json_schema("hdrc3.X", {"a": {"type": "number"}})
    assert schema.message_encoding == JSON and schema.encoding == "jsonschema"
    assert json.loads(schema.data)["properties"] == {"a": {"type": "number"}}
    assert decode(schema, encode_json({"a": 1.5})) == {"a": 1.5}
