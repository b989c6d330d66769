"""State traces stored as CSV: a ``time_ms`` column plus one column per ground fluent.

Example::

    time_ms,p,speed(uav0),carrying(uav0,box1)
    0,true,3.5,false
    100,false,12,true

Header cells other than ``time_ms`` are ground atoms (spaces inside the parentheses are
ignored; an atom with several arguments may be quoted or not); the object names in their
arguments are the trace's objects. Cells hold ``true`` / ``false`` (any case), numbers, or object
names; an empty cell leaves the fluent undefined in that state. Times must strictly increase.
"""

from __future__ import annotations

import csv
import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from hdrc3_base.errors import DataError
from hdrc3_dyknow.interpretation import (
    FluentValue,
    State,
    StateOrderError,
    atom_key,
    parse_atom_key,
)

TIME_COLUMN = "time_ms"


@dataclass(frozen=True, slots=True)
class Trace:
    """A finite sequence of states read from a file.

    Attributes:
        states: The states, in strictly increasing time.
        fluents: Ground atom keys of the fluent columns, in column order.
        objects: Object names appearing as fluent arguments, in first-seen order.

    """

    states: tuple[State, ...]
    fluents: tuple[str, ...]
    objects: tuple[str, ...]


def parse_value(text: str) -> FluentValue | None:
    """A CSV cell as a fluent value; None for an empty cell."""
    cell = text.strip()
    if not cell:
        return None
    lowered = cell.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        number = float(cell)
    except ValueError:
        return cell
    return cell if math.isnan(number) else number


def read_trace_csv(path: Path) -> Trace:
    """Read a CSV trace.

    Raises:
        DataError: The file is missing or malformed (the message names the row or column).

    """
    try:
        with path.open(newline="", encoding="utf-8") as stream:
            rows = list(csv.reader(stream))
    except OSError as exc:
        raise DataError(f"cannot read trace {path}: {exc.strerror}") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise DataError(f"trace {path} is not a readable CSV file: {exc}") from None
    if not rows:
        raise DataError(f"trace {path} is empty")
    header = _join_atoms(rows[0])
    if TIME_COLUMN not in header:
        raise DataError(f"trace {path} has no {TIME_COLUMN!r} column")
    time_index = header.index(TIME_COLUMN)
    columns: dict[int, str] = {}
    objects: dict[str, None] = {}
    for index, cell in enumerate(header):
        if index == time_index:
            continue
        try:
            name, args = parse_atom_key(cell)
        except DataError as exc:
            raise DataError(f"{path}: column {index + 1}: {exc}") from None
        key = atom_key(name, args)
        if key in columns.values():
            raise DataError(f"{path}: fluent {key!r} has two columns")
        columns[index] = key
        objects.update(dict.fromkeys(args))
    states = [
        _state(row, line, time_index, columns, path)
        for line, row in enumerate(rows[1:], start=2)
        if any(cell.strip() for cell in row)
    ]
    for before, after in itertools.pairwise(states):
        if after.time_ms <= before.time_ms:
            raise StateOrderError(
                f"{path}: state at {after.time_ms:g} ms does not follow {before.time_ms:g} ms"
            )
    return Trace(tuple(states), tuple(columns.values()), tuple(objects))


def _join_atoms(cells: list[str]) -> list[str]:
    """Header cells, re-joining atoms like ``carrying(uav0,box1)`` that were left unquoted."""
    joined: list[str] = []
    for cell in cells:
        if joined and joined[-1].count("(") > joined[-1].count(")"):
            joined[-1] += "," + cell
        else:
            joined.append(cell)
    return [cell.strip() for cell in joined]


def _state(
    row: list[str], line: int, time_index: int, columns: Mapping[int, str], path: Path
) -> State:
    if len(row) > len(columns) + 1:
        raise DataError(f"{path}:{line}: {len(row)} cells but {len(columns) + 1} columns")
    try:
        time_ms = float(row[time_index])
    except (IndexError, ValueError):
        raise DataError(f"{path}:{line}: {TIME_COLUMN} is not a number") from None
    if not math.isfinite(time_ms):
        raise DataError(f"{path}:{line}: {TIME_COLUMN} is not finite")
    values: dict[str, FluentValue] = {}
    for index, key in columns.items():
        value = parse_value(row[index]) if index < len(row) else None
        if value is not None:
            values[key] = value
    return State(time_ms, values)
