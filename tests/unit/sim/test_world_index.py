"""Line index of TOML text: tables, array-of-tables entries, keys, multi-line arrays."""

from __future__ import annotations

from sim.world_index import LineIndex

TEXT = """\
top = 1  # comment with [brackets]
[origin]
latitude = 1.0
[[building]]
name = "a"
footprint = [
  [0, 0],
  [1, 0],
]
height = 3
[[building]]  # second
name = "b # not a comment"
"""


def test_lines_of_tables_entries_and_keys() -> None:
    index = LineIndex.of(TEXT)
    assert index.line(None, 0, "top") == 1
    assert index.line("origin", 0, "latitude") == 3
    assert index.line("building", 0) == 4
    assert index.line("building", 0, "height") == 10  # lines inside the array are not keys
    assert index.line("building", 1, "name") == 12
    assert index.line("building", 1, "height") == 11  # missing key: the entry's header


def test_unknown_table_falls_back() -> None:
    index = LineIndex.of(TEXT)
    assert index.line("road", 0) == 1
    assert index.line("building", 5) == 1
