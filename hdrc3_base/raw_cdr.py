"""Readers of serialized (CDR) messages for subscriptions that take their messages raw.

Why hand-written: for every message a subscription delivers, rclpy builds the whole Python
message (``sensor_msgs/Imu``: the message, a Header, a Time, three vectors and quaternions and
three numpy covariance arrays), 15-56 us per message (measured: Imu 56 us, Attitude 14 us,
YacsStatus 16 us). The control kernel takes about ten of them per 20 ms tick and reads a few
floats of each. These readers take those fields straight from the bytes with :mod:`struct`
(about 1-2 us). No library does this cheaper: ``rclpy.serialization.deserialize_message``
builds the full message, and ``mcap_ros2``'s decoder parses the ``.msg`` text into dynamic
objects.

The layouts follow plain CDR (XCDR1) as ROS 2's rmw writes it: a 4-byte encapsulation header
(``00 01``: little endian, ``00 00``: big endian), then the fields in declaration order, each
primitive aligned to its own size counted from the end of that header; a string is a uint32
length (with the terminating NUL) and its bytes. The tests compare every reader with
``rclpy.serialization.serialize_message`` for random values and frame ids of every length.
Short or malformed data raises :class:`RawMessageError`.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any

from hdrc3_base.errors import DataError
from hdrc3_base.stamps import NS_PER_S

_ENCAPSULATION = 4
"""Bytes of the encapsulation header; alignment counts from its end."""
_ENDIAN = {b"\x00\x01": "<", b"\x00\x00": ">"}


class RawMessageError(DataError):
    """Serialized bytes that are not the message a reader expects."""


@dataclass(frozen=True, slots=True)
class RawImu:
    """The fields of ``sensor_msgs/Imu`` the control kernel uses."""

    stamp_ns: int
    angular_velocity: tuple[float, float, float]
    """rad/s."""
    linear_acceleration: tuple[float, float, float]
    """m/s^2."""


@dataclass(frozen=True, slots=True)
class RawAttitude:
    """``hdrc3_interfaces/Attitude``."""

    stamp_ns: int
    roll: float
    pitch: float
    heading: float


@dataclass(frozen=True, slots=True)
class RawGroundContact:
    """``hdrc3_interfaces/GroundContact``."""

    stamp_ns: int
    on_ground: bool


@dataclass(frozen=True, slots=True)
class RawYacsStatus:
    """``hdrc3_interfaces/YacsStatus`` (the fields after the header, in declaration order)."""

    stamp_ns: int
    mode: int
    rc_link_ok: bool
    engine_switch: bool
    engine_running: bool
    rotor_rpm: float
    source: int
    rejected_commands: int


def _start(data: bytes) -> str:
    """The struct byte-order prefix of ``data`` (RawMessageError if it has no known header)."""
    endian = _ENDIAN.get(bytes(data[:2]))
    if endian is None or len(data) < _ENCAPSULATION:
        raise RawMessageError(f"not a CDR message (header {bytes(data[:4]).hex() or 'empty'})")
    return endian


def _header(data: bytes, endian: str) -> tuple[int, int]:
    """Stamp (ns) of a leading ``std_msgs/Header`` and the offset after it (from the start)."""
    try:
        sec, nanosec, length = struct.unpack_from(endian + "iII", data, _ENCAPSULATION)
    except struct.error as exc:
        raise RawMessageError(f"header cut short: {exc}") from exc
    end = _ENCAPSULATION + 12 + length
    if length == 0 or end > len(data):
        raise RawMessageError(f"frame_id of {length} bytes does not fit in {len(data)} bytes")
    return sec * NS_PER_S + nanosec, end


def _aligned(offset: int, size: int) -> int:
    """``offset`` (from the start of the data) moved up to a multiple of ``size`` of the body."""
    body = offset - _ENCAPSULATION
    return _ENCAPSULATION + (body + size - 1) // size * size


def _unpack(fmt: str, data: bytes, offset: int) -> tuple[Any, ...]:
    try:
        return struct.unpack_from(fmt, data, offset)
    except struct.error as exc:
        raise RawMessageError(f"message cut short: {exc}") from exc


def read_stamp(data: bytes) -> int:
    """Nanoseconds of ``builtin_interfaces/Time`` or ``rosgraph_msgs/Clock`` (same layout)."""
    sec, nanosec = _unpack(_start(data) + "iI", data, _ENCAPSULATION)
    return int(sec * NS_PER_S + nanosec)


def read_imu(data: bytes) -> RawImu:
    """``sensor_msgs/Imu``: stamp, angular velocity and linear acceleration."""
    endian = _start(data)
    stamp, offset = _header(data, endian)
    # orientation (4 doubles) and its covariance (9) precede the angular velocity (3), whose
    # covariance (9) precedes the linear acceleration (3)
    wx, wy, wz, ax, ay, az = _unpack(endian + "104x3d72x3d", data, _aligned(offset, 8))
    return RawImu(stamp, (wx, wy, wz), (ax, ay, az))


def read_attitude(data: bytes) -> RawAttitude:
    """``hdrc3_interfaces/Attitude``."""
    endian = _start(data)
    stamp, offset = _header(data, endian)
    roll, pitch, heading = _unpack(endian + "3d", data, _aligned(offset, 8))
    return RawAttitude(stamp, roll, pitch, heading)


def read_ground_contact(data: bytes) -> RawGroundContact:
    """``hdrc3_interfaces/GroundContact``."""
    endian = _start(data)
    stamp, offset = _header(data, endian)
    (on_ground,) = _unpack(endian + "?", data, offset)
    return RawGroundContact(stamp, bool(on_ground))


def read_yacs_status(data: bytes) -> RawYacsStatus:
    """``hdrc3_interfaces/YacsStatus``."""
    endian = _start(data)
    stamp, offset = _header(data, endian)
    mode, link, switch, running = _unpack(endian + "B???", data, offset)
    rpm_at = _aligned(offset + 4, 8)
    rpm, source = _unpack(endian + "dB", data, rpm_at)
    (rejected,) = _unpack(endian + "I", data, _aligned(rpm_at + 9, 4))
    return RawYacsStatus(stamp, mode, link, switch, running, rpm, source, rejected)
