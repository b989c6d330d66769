"""Plain-Python stand-ins for Data Interface messages, for tests and benchmarks without ROS.

They have the attribute shape of ``hdrc3_interfaces/msg/HelicopterState`` that
:class:`hdrc3_dyknow.sources.StreamCatalog` reads.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(slots=True)
class FakeTime:
    """``builtin_interfaces/Time``."""

    sec: int = 0
    nanosec: int = 0

    @classmethod
    def from_ms(cls, ms: int) -> FakeTime:
        """A stamp ``ms`` milliseconds after the epoch."""
        return cls(ms // 1000, (ms % 1000) * 1_000_000)


@dataclass(slots=True)
class FakeHeader:
    """``std_msgs/Header``."""

    stamp: FakeTime = field(default_factory=FakeTime)
    frame_id: str = ""


@dataclass(slots=True)
class FakeHelicopterState:
    """``hdrc3_interfaces/msg/HelicopterState`` with the fields sources read."""

    header: FakeHeader = field(default_factory=FakeHeader)
    latitude: float = 0.0
    longitude: float = 0.0
    altitude: float = 0.0
    velocity_north: float = 0.0
    velocity_east: float = 0.0
    velocity_up: float = 0.0
    pitch: float = 0.0
    roll: float = 0.0
    heading: float = 0.0
    rpm: float = 0.0
    on_ground_flag: bool = False
    auto_flag: bool = False
    power_status: int = 0

    @classmethod
    def at(cls, ms: int, latitude: float, longitude: float, altitude: float) -> FakeHelicopterState:
        """A state stamped ``ms`` at the given WGS84 position."""
        return cls(FakeHeader(FakeTime.from_ms(ms)), latitude, longitude, altitude)


@dataclass(slots=True)
class FakeHookState:
    """``hdrc3_interfaces/msg/HookState`` (the carrying sensor) with the fields sources read."""

    header: FakeHeader = field(default_factory=FakeHeader)
    carrying: bool = False
    object_id: str = ""
    magnet: bool = False
    winch: int = 0
    cable_length: float = 0.0
    tension: float = 0.0

    @classmethod
    def holding(cls, ms: int, object_id: str) -> FakeHookState:
        """A reading stamped ``ms``: the magnet holds ``object_id`` ("" : nothing)."""
        held = bool(object_id)
        return cls(FakeHeader(FakeTime.from_ms(ms)), held, object_id, held)
