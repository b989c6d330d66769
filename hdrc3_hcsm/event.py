"""Events on the wire between computers: globally unique ids, incarnations, sequence numbers, CRC.

The ``incarnation`` names one run of the sending computer's transport (a random 64-bit number
drawn at start): sequence numbers count within an incarnation, so a restarted sender that counts
from 1 again is recognised as new instead of being taken for a replay of old events.
"""

from __future__ import annotations

import enum
import struct
import zlib
from dataclasses import dataclass, replace


class EventOrigin(enum.Enum):
    """Where an event processed in a micro step came from."""

    PULSE = "pulse"
    EXTERNAL = "external"
    INTERNAL = "internal"
    EXIT = "exit"


class PostStatus(enum.Enum):
    """Outcome of offering an external event to an interpreter."""

    ACCEPTED = "accepted"
    UNKNOWN_EVENT = "unknown_event"
    ID_MISMATCH = "id_mismatch"
    WRONG_TARGET = "wrong_target"
    QUEUE_FULL = "queue_full"
    TOO_LARGE = "too_large"


@dataclass(frozen=True)
class WireEvent:
    """An external event as transmitted between computers (mirrors hdrc3_interfaces/Event)."""

    event_id: int
    name: str
    data: bytes
    source: str
    target: str
    sequence: int = 0
    crc32: int = 0
    incarnation: int = 0

    def checksum(self) -> int:
        """CRC-32 over id, name, data, source/target computers, incarnation and sequence."""
        name = self.name.encode("utf-8")
        header = struct.pack("<QI", self.event_id & 0xFFFFFFFFFFFFFFFF, len(name))
        tail = (
            self.source.encode("utf-8")
            + b"\0"
            + self.target.encode("utf-8")
            + struct.pack("<QI", self.incarnation & 0xFFFFFFFFFFFFFFFF, self.sequence & 0xFFFFFFFF)
        )
        crc = zlib.crc32(header)
        crc = zlib.crc32(name, crc)
        crc = zlib.crc32(struct.pack("<I", len(self.data)), crc)
        crc = zlib.crc32(self.data, crc)
        return zlib.crc32(tail, crc)

    def sealed(self, sequence: int, incarnation: int = 0) -> WireEvent:
        """Return a copy numbered ``sequence`` of ``incarnation`` with its checksum filled in."""
        numbered = replace(
            self,
            sequence=sequence & 0xFFFFFFFF,
            incarnation=incarnation & 0xFFFFFFFFFFFFFFFF,
        )
        return replace(numbered, crc32=numbered.checksum())

    def intact(self) -> bool:
        """Tell whether the stored checksum matches the content."""
        return self.crc32 == self.checksum()
