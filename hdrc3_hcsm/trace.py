"""Debug trace: one record per micro step (event, fired transitions, actions, configuration).

Records are plain frozen dataclasses that serialise to JSON lines, so they can be recorded to a
file, published by the ROS adapter, and read back by ``render`` to highlight a configuration.
"""

from __future__ import annotations

import json
from collections import deque
from collections.abc import Iterable, Iterator
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Protocol

from hdrc3_hcsm.errors import ModelError


@dataclass(frozen=True)
class FiredTransition:
    """A transition taken in a micro step, in the instance ``machine`` (a path)."""

    tid: str
    machine: str
    source: str
    target: str
    actions: tuple[str, ...]


@dataclass(frozen=True)
class TraceRecord:
    """What happened in one micro step of one macro step."""

    computer: str
    macro_step: int
    micro_step: int
    time: float
    event: str
    origin: str
    transitions: tuple[FiredTransition, ...]
    faults: tuple[str, ...]
    configuration: tuple[str, ...]

    def to_json(self) -> str:
        """One JSON line."""
        return json.dumps(asdict(self), separators=(",", ":"))

    @staticmethod
    def from_json(line: str) -> TraceRecord:
        """Parse one JSON line written by :meth:`to_json`; raises ModelError on bad input."""
        try:
            raw: dict[str, Any] = json.loads(line)
            fired = tuple(
                FiredTransition(
                    str(t["tid"]),
                    str(t["machine"]),
                    str(t["source"]),
                    str(t["target"]),
                    tuple(str(a) for a in t["actions"]),
                )
                for t in raw["transitions"]
            )
            return TraceRecord(
                computer=str(raw["computer"]),
                macro_step=int(raw["macro_step"]),
                micro_step=int(raw["micro_step"]),
                time=float(raw["time"]),
                event=str(raw["event"]),
                origin=str(raw["origin"]),
                transitions=fired,
                faults=tuple(str(f) for f in raw["faults"]),
                configuration=tuple(str(c) for c in raw["configuration"]),
            )
        except (ValueError, KeyError, TypeError) as exc:
            raise ModelError(f"bad trace record: {exc}") from exc


class TraceSink(Protocol):
    """Anything that accepts trace records (recorder, file writer, ROS publisher)."""

    def record(self, record: TraceRecord) -> None:
        """Accept one record."""


class TraceRecorder:
    """Keeps the most recent ``capacity`` records in memory."""

    def __init__(self, capacity: int = 10_000) -> None:
        self._records: deque[TraceRecord] = deque(maxlen=capacity)

    def record(self, record: TraceRecord) -> None:
        """Keep ``record`` (the oldest is dropped when full)."""
        self._records.append(record)

    def records(self) -> tuple[TraceRecord, ...]:
        """All kept records, oldest first."""
        return tuple(self._records)

    def clear(self) -> None:
        """Forget all records."""
        self._records.clear()

    def __iter__(self) -> Iterator[TraceRecord]:
        return iter(tuple(self._records))


class TraceFileWriter:
    """Streams records to a JSON-lines file as they happen (long runs, no memory growth)."""

    def __init__(self, path: str | Path) -> None:
        # Kept open for the life of the writer; closed by close() or the with-block.
        self._out = Path(path).open("w", encoding="utf-8")  # noqa: SIM115

    def record(self, record: TraceRecord) -> None:
        """Append one record as a line."""
        self._out.write(record.to_json() + "\n")

    def close(self) -> None:
        """Flush and close the file."""
        self._out.close()

    def __enter__(self) -> TraceFileWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def fired_ids(records: Iterable[TraceRecord]) -> list[tuple[str, str]]:
    """``(event, transition id)`` pairs in firing order, the shape of the chapter's time-lines."""
    return [(r.event, t.tid) for r in records for t in r.transitions]


def write_jsonl(records: Iterable[TraceRecord], path: str | Path) -> None:
    """Write records as JSON lines."""
    with Path(path).open("w", encoding="utf-8") as out:
        for rec in records:
            out.write(rec.to_json() + "\n")


def read_jsonl(path: str | Path) -> list[TraceRecord]:
    """Read JSON-lines records; raises ModelError (a DataError) on unreadable or bad files."""
    try:
        lines = Path(path).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelError(f"cannot read trace {path}: {exc}") from exc
    return [TraceRecord.from_json(line) for line in lines if line.strip()]
