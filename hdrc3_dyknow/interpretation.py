"""States that monitor formulas are progressed through: a timepoint plus an interpretation.

Chapter 9.3.3 identifies a state by its time and an interpretation of the fluents. A
:class:`State` carries its time in milliseconds and a mapping from *ground atom keys* to values.
The key of a fluent term is its name followed by its comma-separated object arguments without
spaces, e.g. ``"p"``, ``"speed(uav0)"``, ``"carrying(uav0,box1)"``, ``"executing-climb(uav0)"``
(see :func:`atom_key`). States may arrive with irregular spacing but their times must strictly
increase.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TypeAlias

from hdrc3_base.errors import DataError

FluentValue: TypeAlias = bool | int | float | str
"""Value of a fluent in a state: booleans for boolean fluents, numbers, or object names."""

_KEY = re.compile(
    r"^\s*(?P<name>[A-Za-z_][A-Za-z0-9_]*(?:-[A-Za-z_][A-Za-z0-9_]*)*)\s*"
    r"(?:\(\s*(?P<args>[^()]*?)\s*\))?\s*$"
)


class UnknownFluentError(DataError):
    """A formula needs a fluent that the state does not define.

    Attributes:
        symbol: Ground atom key of the missing fluent, e.g. ``"speed(uav0)"``.
        time_ms: Time of the state that lacks it.

    """

    def __init__(self, symbol: str, time_ms: float) -> None:
        self.symbol = symbol
        self.time_ms = time_ms
        super().__init__(f"unknown fluent {symbol!r} in the state at {time_ms:g} ms")


class FluentTypeError(DataError):
    """A fluent has a value of the wrong type for its use (e.g. a string compared with ``<``)."""


class StateOrderError(DataError):
    """A state's time does not lie strictly after the previous state's time."""


@dataclass(frozen=True, slots=True)
class State:
    """One state: a timepoint and the interpretation of the fluents at it.

    Attributes:
        time_ms: Time of the state in milliseconds (any origin; only differences matter).
        values: Value of each fluent, keyed by ground atom key (:func:`atom_key`).

    """

    time_ms: float
    values: Mapping[str, FluentValue]


def atom_key(name: str, args: tuple[str, ...] = ()) -> str:
    """Ground atom key of fluent ``name`` applied to object names ``args``."""
    return f"{name}({','.join(args)})" if args else name


def parse_atom_key(text: str) -> tuple[str, tuple[str, ...]]:
    """Split a ground atom such as ``"carrying(uav0, box1)"`` into name and arguments.

    Raises:
        DataError: ``text`` is not a fluent name with optional object arguments.

    """
    match = _KEY.match(text)
    if match is None:
        raise DataError(f"{text!r} is not a ground fluent such as 'speed(uav0)'")
    raw_args = match.group("args")
    args = tuple(arg.strip() for arg in raw_args.split(",")) if raw_args else ()
    if any(not arg for arg in args):
        raise DataError(f"{text!r} has an empty argument")
    return match.group("name"), args
