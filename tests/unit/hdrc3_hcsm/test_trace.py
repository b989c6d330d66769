from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_hcsm.errors import ModelError
from hdrc3_hcsm.trace import (
    FiredTransition,
    TraceFileWriter,
    TraceRecord,
    TraceRecorder,
    fired_ids,
    read_jsonl,
    write_jsonl,
)

REC = TraceRecord(
    computer="PFC",
    macro_step=3,
    micro_step=2,
    time=0.06,
    event="Ctrl-Ok-EV",
    origin="internal",
    transitions=(FiredTransition("A.4", "Mode-Switch", "Wait-Hover-ST", "Stabilizing-ST", ()),),
    faults=(),
    configuration=("Mode-Switch:Stabilizing-ST", "Control-Mode:Ctrl-Run-ST"),
)


def test_json_round_trip_and_file(tmp_path: Path) -> None:
    assert TraceRecord.from_json(REC.to_json()) == REC
    write_jsonl([REC, REC], tmp_path / "t.jsonl")
    assert read_jsonl(tmp_path / "t.jsonl") == [REC, REC]


@pytest.mark.parametrize("line", ["{", "[]", '{"computer": "PFC"}', "null"])
def test_bad_records_raise_model_error(line: str) -> None:
    with pytest.raises(ModelError):
        TraceRecord.from_json(line)


def test_recorder_is_bounded() -> None:
    rec = TraceRecorder(capacity=2)
    for i in range(3):
        rec.record(TraceRecord("PFC", i, 1, 0.0, "pulse", "pulse", (), (), ()))
    assert [r.macro_step for r in rec] == [1, 2]
    rec.record(REC)
    assert fired_ids(rec) == [("Ctrl-Ok-EV", "A.4")]


def test_file_writer_streams_records_from_an_interpreter(tmp_path: Path) -> None:
    from hdrc3_hcsm.interpreter import Interpreter
    from hdrc3_hcsm.loader import load_file
    from hdrc3_hcsm.models import model_path
    from hdrc3_hcsm.tables import compile_model

    model = compile_model(load_file(model_path("pfc_modes.hcsm")))
    path = tmp_path / "run.jsonl"
    with TraceFileWriter(path) as sink:
        interp = Interpreter(model, dict.fromkeys(model.conditions, lambda: False), trace=sink)
        interp.execute(0.0)
    records = read_jsonl(path)
    assert fired_ids(records) == [
        ("pulse", "A.1"),
        ("Ctrl-Stop-EV", "B.1"),
        ("Ctrl-Stopped-EV", "A.2"),
    ]
    assert [r.origin for r in records] == ["pulse", "internal", "internal"]
    assert records[-1].configuration == ("Mode-Switch:Braking-ST", "Control-Mode:Ctrl-Off-ST")
    assert records[0].transitions[0].actions == ("SEND Ctrl-Stop-EV",)
