"""Line index of a TOML world file: where each table, array-of-tables entry and key starts.

tomllib reports no positions for values, yet semantic errors must name file:line. This pass scans
the raw text for table headers (``[name]``, ``[[name]]``) and ``key =`` lines, so a validator can
ask "on which line is key ``height`` of the 3rd ``[[building]]``?".
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

_HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z_][A-Za-z0-9_-]*)\s*(\]\]?)\s*(#.*)?$")
_KEY = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_-]*)\s*=")


@dataclass(slots=True)
class _Span:
    header_line: int
    keys: dict[str, int] = field(default_factory=dict)


@dataclass(slots=True)
class LineIndex:
    """Lines (1-based) of tables, array-of-tables entries and their keys in one TOML text."""

    root: _Span = field(default_factory=lambda: _Span(1))
    tables: dict[str, list[_Span]] = field(default_factory=dict)

    @staticmethod
    def of(text: str) -> LineIndex:
        """Index ``text``."""
        index = LineIndex()
        current = index.root
        depth = 0  # open brackets of a multi-line array: its lines are values, not keys
        for number, line in enumerate(text.splitlines(), start=1):
            code = _strip_comment(line)
            if depth == 0:
                header = _HEADER.match(line)
                if header is not None and len(header.group(1)) == len(header.group(3)):
                    current = _Span(number)
                    index.tables.setdefault(header.group(2), []).append(current)
                    continue
                key = _KEY.match(code)
                if key is not None:
                    current.keys.setdefault(key.group(1), number)
            depth = max(0, depth + code.count("[") - code.count("]"))
        return index

    def line(self, table: str | None, entry: int = 0, key: str | None = None) -> int:
        """Line of ``key`` inside the ``entry``-th occurrence of ``table`` (None: the root).

        Falls back to the table's header line, then to the root key naming the table, then to 1.
        """
        if table is None:
            span = self.root
        else:
            spans = self.tables.get(table, [])
            if entry >= len(spans):
                return self.root.keys.get(table, 1)
            span = spans[entry]
        if key is not None and key in span.keys:
            return span.keys[key]
        return span.header_line


def _strip_comment(line: str) -> str:
    """Drop a trailing comment (a ``#`` outside double/single quoted strings)."""
    quote = ""
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch == "#":
            return line[:i]
    return line
