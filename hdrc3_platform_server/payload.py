"""Event payloads on the real-time channel (docs/realtime_events.md).

A payload is the command id (little-endian uint64), then little-endian float64 numbers, then an
optional UTF-8 reason. The receiver knows how many numbers an event carries.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass

from hdrc3_base.errors import DataError

_ID = struct.Struct("<Q")
_F64 = 8


class PayloadError(DataError):
    """A payload too short for the numbers its event must carry."""


@dataclass(frozen=True, slots=True)
class Payload:
    """Decoded event data."""

    command_id: int
    numbers: tuple[float, ...]
    reason: str


def encode(command_id: int, numbers: Sequence[float] = (), reason: str = "") -> bytes:
    """Pack an id, numbers and a reason."""
    body = struct.pack(f"<{len(numbers)}d", *numbers) if numbers else b""
    return _ID.pack(command_id & 0xFFFFFFFFFFFFFFFF) + body + reason.encode("utf-8")


def decode(data: bytes, count: int = 0) -> Payload:
    """Unpack an id, ``count`` numbers and the rest as reason (invalid UTF-8 replaced)."""
    need = _ID.size + count * _F64
    if len(data) < need:
        raise PayloadError(f"payload of {len(data)} bytes, need at least {need}")
    (command_id,) = _ID.unpack_from(data, 0)
    numbers = struct.unpack_from(f"<{count}d", data, _ID.size) if count else ()
    reason = data[need:].decode("utf-8", errors="replace")
    return Payload(int(command_id), tuple(float(n) for n in numbers), reason)


def command_id_of(data: bytes) -> int | None:
    """The id at the start of ``data``, or None if the payload is too short."""
    if len(data) < _ID.size:
        return None
    return int(_ID.unpack_from(data, 0)[0])
