"""The commands a platform server has accepted and not yet ended, kept in a file across restarts.

A command whose final reply the PFC sent while the server was down (killed, restarting) would
otherwise never get its terminal event: the reply went to the dead process, and the PFC, done
with the command, reports command id 0. The journal lists every id answered ``FCL_OK`` /
``PPCL_OK`` (written before the answer leaves) until its terminal event is published; a
restarted server reads the ids of its previous run from it and ends each of them exactly once
(``FlightCommandLayer``, docs/realtime_events.md "Restarts"). Ids whose terminal event was
published before the crash are not in it, so they do not end twice. The one window left: a
crash between publishing a terminal event and rewriting the file ends that command again.

The file (JSON ``{"open": {"<id>": "<command>"}}``) is written to a temporary file beside it and
renamed over it, as world_sim's checkpoint is: a reader finds the previous or the new list, never
part of one. A missing, unreadable or foreign file is an empty journal (nothing to end).
"""

from __future__ import annotations

import json
import os
from pathlib import Path


def _load(path: Path | None) -> dict[int, str]:
    if path is None:
        return {}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        return {int(k): str(v) for k, v in dict(data["open"]).items() if int(k) > 0}
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return {}


class CommandJournal:
    """Open command ids of this and earlier runs of one server (``path`` None: kept in memory)."""

    def __init__(self, path: Path | None) -> None:
        """Read the ids the previous run left open."""
        self.path = path
        self.earlier: dict[int, str] | None = _load(path) if path is not None else None
        """Id -> command of commands earlier runs left open (None: no journal, not known)."""
        self._open: dict[int, str] = dict(self.earlier or {})
        self._ended: set[int] = set()

    def open_ids(self) -> dict[int, str]:
        """Ids without a terminal event yet (earlier runs' included)."""
        return dict(self._open)

    def accepted(self, command_id: int, command: str) -> None:
        """``command_id`` was answered OK (a command that already ended stays ended)."""
        if command_id > 0 and command_id not in self._ended and command_id not in self._open:
            self._open[command_id] = command
            self._write()

    def ended(self, command_id: int) -> None:
        """The terminal event of ``command_id`` was published."""
        self._ended.add(command_id)
        if self._open.pop(command_id, None) is not None:
            self._write()

    def _write(self) -> None:
        if self.path is None:
            return
        tmp = self.path.with_name(self.path.name + ".tmp")
        tmp.write_text(json.dumps({"open": {str(k): v for k, v in self._open.items()}}))
        os.replace(tmp, self.path)
