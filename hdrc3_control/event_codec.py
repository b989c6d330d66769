"""Payloads of the real-time events between DRC, PFC and PPC (docs/realtime_events.md).

Every command event starts with the DRC's command id as a little-endian ``uint64``; numbers
follow as little-endian ``float64``; a reason is UTF-8 text after the numbers. This is the one
codec of these payloads: the PFC and PPC kernels, the Platform Server and its fakes all use it.
Decoding never raises on bad bytes: it returns a :class:`Decoded` with a status and a readable
problem. The receiver knows how many numbers an event carries (the Platform Server's command
registry, ``hdrc3_platform_server.commands``, for the command events).
"""

from __future__ import annotations

import enum
import math
import struct
from collections.abc import Sequence
from dataclasses import dataclass

_ID = struct.Struct("<Q")
_F64 = 8


class DecodeStatus(enum.Enum):
    """Outcome of decoding one payload."""

    OK = "ok"
    TOO_SHORT = "too_short"
    WRONG_LENGTH = "wrong_length"
    NOT_FINITE = "not_finite"
    BAD_TEXT = "bad_text"


@dataclass(frozen=True, slots=True)
class Decoded:
    """A decoded payload: the command id, the numbers and the reason text.

    ``reason`` is also set for BAD_TEXT, with the invalid bytes replaced by U+FFFD.
    """

    status: DecodeStatus
    command_id: int = 0
    values: tuple[float, ...] = ()
    reason: str = ""
    problem: str = ""

    @property
    def ok(self) -> bool:
        """True when the payload was well formed."""
        return self.status is DecodeStatus.OK


def encode(command_id: int, values: Sequence[float] = (), reason: str = "") -> bytes:
    """Id, numbers and reason in the contract's layout."""
    if not 0 <= command_id < 2**64:
        raise ValueError(f"command id {command_id} outside uint64")
    numbers = struct.pack(f"<{len(values)}d", *values) if values else b""
    return _ID.pack(command_id) + numbers + reason.encode("utf-8")


def encode_values(values: tuple[float, ...]) -> bytes:
    """Numbers only, without an id (e.g. Mode-Changed-EV)."""
    return struct.pack(f"<{len(values)}d", *values)


def command_id_of(data: bytes) -> int:
    """The leading id of a payload (0 when the payload is shorter than an id)."""
    return int(_ID.unpack_from(data)[0]) if len(data) >= _ID.size else 0


def decode(data: bytes, count: int, *, with_reason: bool = False) -> Decoded:
    """Decode id + ``count`` floats (+ reason text when ``with_reason``)."""
    need = _ID.size + count * _F64
    if len(data) < need:
        return Decoded(DecodeStatus.TOO_SHORT, problem=f"{len(data)} bytes, need at least {need}")
    if not with_reason and len(data) != need:
        return Decoded(DecodeStatus.WRONG_LENGTH, problem=f"{len(data)} bytes, expected {need}")
    cid = int(_ID.unpack_from(data)[0])
    values = struct.unpack_from(f"<{count}d", data, _ID.size) if count else ()
    if not all(math.isfinite(v) for v in values):
        return Decoded(DecodeStatus.NOT_FINITE, cid, problem=f"non-finite numbers {values}")
    reason = ""
    if with_reason:
        try:
            reason = data[need:].decode("utf-8")
        except UnicodeDecodeError as exc:
            # the text stays readable (invalid bytes replaced) for callers that only show it
            text = data[need:].decode("utf-8", errors="replace")
            return Decoded(DecodeStatus.BAD_TEXT, cid, tuple(values), text, str(exc))
    return Decoded(DecodeStatus.OK, cid, tuple(values), reason)
