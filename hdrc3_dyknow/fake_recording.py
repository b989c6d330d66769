"""Small synthetic flight recordings (MCAP, CDR, ``ros2msg`` schemas) for tests and examples.

The recording has one topic per aircraft, ``/<uav>/helicopter_state``, of the self-describing
type ``hdrc3_fake/msg/HelicopterState`` (altitude, speed, a carrying flag and a nested position),
so no installed interface package is needed to read it back.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from mcap_ros2.writer import Writer

STATE_TYPE = "hdrc3_fake/msg/HelicopterState"
STATE_DEFINITION = """float64 altitude
float64 speed
bool carrying
Point position
================================================================================
MSG: hdrc3_fake/Point
float64 x
float64 y
float64 z
"""


@dataclass(frozen=True, slots=True)
class FakeSample:
    """One helicopter state message.

    Attributes:
        uav: Aircraft name; the topic is ``/<uav>/helicopter_state``.
        time_ms: Log time in ms.
        altitude: Altitude in m.
        speed: Ground speed in m/s.
        carrying: Whether a box is attached.

    """

    uav: str
    time_ms: int
    altitude: float
    speed: float = 0.0
    carrying: bool = False


def write_fake_recording(path: Path, samples: Iterable[FakeSample]) -> None:
    """Write ``samples`` (in any order) as an MCAP recording at ``path``."""
    with path.open("wb") as stream:
        writer = Writer(stream)
        schema = writer.register_msgdef(STATE_TYPE, STATE_DEFINITION)
        for sample in sorted(samples, key=lambda s: s.time_ms):
            message = {
                "altitude": sample.altitude,
                "speed": sample.speed,
                "carrying": sample.carrying,
                "position": {"x": 0.0, "y": 0.0, "z": sample.altitude},
            }
            time_ns = sample.time_ms * 1_000_000
            writer.write_message(
                f"/{sample.uav}/helicopter_state",
                schema,
                message,
                log_time=time_ns,
                publish_time=time_ns,
            )
        writer.finish()  # type: ignore[no-untyped-call]
