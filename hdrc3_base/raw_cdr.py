"""Read chosen fields of a serialized (CDR) ROS message without building the message.

Why hand-written: for every message a subscription delivers, rclpy builds the whole Python
message (``sensor_msgs/Imu``: the message, a Header, a Time, three vectors and quaternions and
three numpy covariance arrays), 15-56 us per message (measured: Imu 56 us, Attitude 14 us,
YacsStatus 16 us). The control kernel takes about ten of them per 20 ms tick and reads a few
numbers of each. A :class:`CdrReader` takes those numbers straight from the bytes with one
``struct`` call per stretch between strings (1-3 us). No library does this cheaper:
``rclpy.serialization.deserialize_message`` builds the full message, and ``mcap_ros2``'s decoder
parses the ``.msg`` text into dynamic objects.

The layout is not written here: it is compiled from the message class's own type description
(rosidl's ``SLOT_TYPES`` and ``get_fields_and_field_types()``), the one source of the message
layout. Plain CDR (XCDR1) as ROS 2's rmw writes it: a 4-byte encapsulation header (``00 01``:
little endian, ``00 00``: big endian), then the fields in declaration order, each primitive
aligned to its own size counted from the end of that header; a string is a uint32 length
(with the terminating NUL) and its bytes. Since a string's length moves what follows it, each
stretch between strings is compiled for the eight alignments it may start at. Sequences are
not supported (refused when the reader is made). Bad bytes raise :class:`RawMessageError`.
"""

from __future__ import annotations

import importlib
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from rosidl_parser.definition import (
    AbstractString,
    Array,
    BasicType,
    NamespacedType,
)

from hdrc3_base.errors import ConfigError, DataError

_ENCAPSULATION = 4
"""Bytes of the encapsulation header; alignment counts from its end."""
_ENDIAN = {b"\x00\x01": "<", b"\x00\x00": ">"}
_FORMATS = {
    "boolean": "?",
    "octet": "B",
    "char": "B",
    "uint8": "B",
    "int8": "b",
    "uint16": "H",
    "int16": "h",
    "uint32": "I",
    "int32": "i",
    "uint64": "Q",
    "int64": "q",
    "float": "f",
    "double": "d",
}
"""rosidl basic types -> struct format characters (their size is their CDR alignment)."""


class RawMessageError(DataError):
    """Serialized bytes that are not the message a reader expects."""


@dataclass(frozen=True, slots=True)
class _Primitive:
    path: str
    fmt: str
    count: int
    """1, or the length of a fixed-size array (read as padding only: arrays are not picked)."""


@dataclass(frozen=True, slots=True)
class _String:
    path: str


def _flatten(msg_type: Any, prefix: str) -> list[_Primitive | _String]:
    """The message's fields, nested messages expanded, in declaration (= wire) order."""
    names = list(msg_type.get_fields_and_field_types())
    out: list[_Primitive | _String] = []
    for name, slot in zip(names, msg_type.SLOT_TYPES, strict=True):
        path = f"{prefix}{name}"
        if isinstance(slot, BasicType):
            out.append(_Primitive(path, _FORMATS[slot.typename], 1))
        elif isinstance(slot, AbstractString):
            out.append(_String(path))
        elif isinstance(slot, NamespacedType):
            module = importlib.import_module(".".join(slot.namespaces))
            out.extend(_flatten(getattr(module, slot.name), f"{path}."))
        elif isinstance(slot, Array) and isinstance(slot.value_type, BasicType):
            out.append(_Primitive(path, _FORMATS[slot.value_type.typename], slot.size))
        else:
            raise ConfigError(f"{path}: {type(slot).__name__} fields are not supported")
    return out


@dataclass(frozen=True, slots=True)
class _Stretch:
    """Fields between strings: one struct per starting alignment (offset mod 8)."""

    structs: dict[str, tuple[struct.Struct, ...]]
    """Per byte order, indexed by the alignment the stretch starts at."""


def _compile(fields: Sequence[_Primitive], wanted: set[str], start: int, endian: str) -> str:
    """The struct format of ``fields`` starting ``start`` bytes past an 8-byte boundary."""
    fmt, pos = [endian], start
    for f in fields:
        size = struct.calcsize(f.fmt)
        pad = -pos % size
        width = size * f.count
        if f.path in wanted:
            fmt.append(f"{pad}x{f.fmt}" if pad else f.fmt)
        else:
            fmt.append(f"{pad + width}x")
        pos += pad + width
    return "".join(fmt)


class CdrReader:
    """Reads ``fields`` (dotted paths of primitive fields, in declaration order) of one type.

    ``CdrReader(Imu, ("header.stamp.sec", "header.stamp.nanosec", "angular_velocity.x"))``;
    :meth:`read` returns their values as a tuple in that order.
    """

    def __init__(self, msg_type: Any, fields: Sequence[str]) -> None:
        """Compile the reader.

        Raises:
            ConfigError: an unknown or non-primitive field, fields out of declaration order, or
                a message with sequences.
        """
        flat = _flatten(msg_type, "")
        order = [f.path for f in flat if isinstance(f, _Primitive) and f.count == 1]
        for path in fields:
            if path not in order:
                raise ConfigError(f"{msg_type.__name__} has no primitive field {path!r}")
        if sorted(fields, key=order.index) != list(fields):
            raise ConfigError(f"{msg_type.__name__}: fields {list(fields)} not in wire order")
        wanted = set(fields)
        self.name = msg_type.__name__
        self._parts: list[_Stretch | None] = []
        """The stretches between strings; None for a string."""
        stretch: list[_Primitive] = []
        for field in [*flat, None]:
            if isinstance(field, _Primitive):
                stretch.append(field)
                continue
            if stretch:
                self._parts.append(
                    _Stretch(
                        {
                            e: tuple(
                                struct.Struct(_compile(stretch, wanted, a, e)) for a in range(8)
                            )
                            for e in _ENDIAN.values()
                        }
                    )
                )
                stretch = []
            if field is not None:
                self._parts.append(None)

    def read(self, data: bytes) -> tuple[Any, ...]:
        """The chosen fields' values.

        Raises:
            RawMessageError: not a CDR message, or cut short.
        """
        endian = _ENDIAN.get(bytes(data[:2]))
        if endian is None or len(data) < _ENCAPSULATION:
            raise RawMessageError(
                f"{self.name}: not a CDR message (header {bytes(data[:4]).hex() or 'empty'})"
            )
        pos, out = _ENCAPSULATION, ()
        try:
            for part in self._parts:
                if part is None:
                    pos += -(pos - _ENCAPSULATION) % 4
                    (length,) = struct.unpack_from(endian + "I", data, pos)
                    pos += 4 + length
                    continue
                unpacker = part.structs[endian][(pos - _ENCAPSULATION) % 8]
                out += unpacker.unpack_from(data, pos)
                pos += unpacker.size
        except struct.error as exc:
            raise RawMessageError(f"{self.name}: message cut short: {exc}") from exc
        if pos > len(data):
            raise RawMessageError(f"{self.name}: a string runs past the {len(data)} bytes")
        return out
