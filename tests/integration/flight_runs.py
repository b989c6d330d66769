"""Shared by the flight tests: the seed of their simulations and reading their recordings."""

from __future__ import annotations

from pathlib import Path
from typing import Any

SEED = "2"
"""A simulation whose GPS has no outage over 2.5 s on either aircraft in its first 900 s
(``tests/unit/sim/test_gps_outages.py`` keeps this true): with the default seed 0, uav1's GPS
is out from 151 to 155 s, and a scan still flying then ends FAILED by the failsafe hold."""


def recorded(path: Path, *suffixes: str) -> dict[str, list[Any]]:
    """The recorded messages of every topic ending in one of ``suffixes``, by suffix."""
    from rclpy.serialization import deserialize_message

    from hdrc3.mcap_recording import RecordingReader
    from hdrc3.message_types import message_class

    recording = RecordingReader.open(path)
    topics = {t: s for t, s in recording.topics().items() if t.endswith(suffixes)}
    out: dict[str, list[Any]] = {suffix: [] for suffix in suffixes}
    for m in recording.messages(list(topics)):
        suffix = next(x for x in suffixes if m.topic.endswith(x))
        out[suffix].append(deserialize_message(m.data, message_class(topics[m.topic])))
    return out
