"""CSV traces: header atoms, cell values, objects and malformed files."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_base.errors import DataError
from hdrc3_dyknow.interpretation import StateOrderError
from hdrc3_dyknow.trace_csv import parse_value, read_trace_csv


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "trace.csv"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("cell", "value"),
    [
        ("true", True),
        ("FALSE", False),
        (" 12 ", 12.0),
        ("-3.5e2", -350.0),
        ("box1", "box1"),
        ("", None),
        ("nan", "nan"),
    ],
)
def test_cell_values(cell: str, value: object) -> None:
    assert parse_value(cell) == value


def test_reads_states_fluents_and_objects(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        'p,time_ms,speed( uav0 ),"carrying(uav0, box1)",at(box1,depot)\n'
        "true,0,3.5,false,true\n"
        "false,100.5,,true,false\n"
        "\n",
    )
    trace = read_trace_csv(path)
    assert trace.fluents == ("p", "speed(uav0)", "carrying(uav0,box1)", "at(box1,depot)")
    assert trace.objects == ("uav0", "box1", "depot")
    assert [state.time_ms for state in trace.states] == [0.0, 100.5]
    assert trace.states[0].values == {
        "p": True,
        "speed(uav0)": 3.5,
        "carrying(uav0,box1)": False,
        "at(box1,depot)": True,
    }
    assert "speed(uav0)" not in trace.states[1].values  # empty cell: undefined


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty"),
        ("p,q\n1,2\n", "no 'time_ms' column"),
        ("time_ms,p(\n0,1\n", "column 2"),
        ("time_ms,p,p\n0,1,1\n", "two columns"),
        ("time_ms,p\nzero,1\n", "trace.csv:2: time_ms is not a number"),
        ("time_ms,p\n0,1,2\n", "trace.csv:2: 3 cells"),
        ("time_ms,p\ninf,1\n", "not finite"),
    ],
)
def test_malformed_files(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(DataError, match=message):
        read_trace_csv(write(tmp_path, text))


def test_times_must_increase(tmp_path: Path) -> None:
    with pytest.raises(StateOrderError, match="100 ms does not follow 100 ms"):
        read_trace_csv(write(tmp_path, "time_ms,p\n100,1\n100,0\n"))


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="cannot read trace"):
        read_trace_csv(tmp_path / "absent.csv")
