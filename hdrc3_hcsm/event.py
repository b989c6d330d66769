"""Events on the wire between computers: globally unique ids, sequence numbers and CRC-32."""

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

    def checksum(self) -> int:
        """CRC-32 over id, name, data, source/target computers and sequence."""
        name = self.name.encode("utf-8")
        header = struct.pack("<QI", self.event_id & 0xFFFFFFFFFFFFFFFF, len(name))
        tail = (
            self.source.encode("utf-8")
            + b"\0"
            + self.target.encode("utf-8")
            + struct.pack("<I", self.sequence & 0xFFFFFFFF)
        )
        crc = zlib.crc32(header)
        crc = zlib.crc32(name, crc)
        crc = zlib.crc32(struct.pack("<I", len(self.data)), crc)
        crc = zlib.crc32(self.data, crc)
        return zlib.crc32(tail, crc)

    def sealed(self, sequence: int) -> WireEvent:
        """Return a copy numbered ``sequence`` with its checksum filled in."""
        numbered = replace(self, sequence=sequence & 0xFFFFFFFF)
        return replace(numbered, crc32=numbered.checksum())

    def intact(self) -> bool:
        """Tell whether the stored checksum matches the content."""
        return self.crc32 == self.checksum()
