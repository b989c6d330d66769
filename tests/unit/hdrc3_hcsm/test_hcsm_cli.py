from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main
from hdrc3_hcsm.models import model_path
from hdrc3_hcsm.trace import TraceRecord, write_jsonl

MODEL = str(model_path("pfc_modes.hcsm"))


def test_check_shipped_model(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["hcsm", "check", MODEL]) == 0
    assert "ok (3 automata, 16 events, 27 transitions, 0 warnings)" in capsys.readouterr().out


def test_check_reports_errors_with_location(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.hcsm"
    bad.write_text("model M on PFC;\ncomputers PFC;\nautomaton A X { state S-ST; }\nroot X;\n")
    assert main(["hcsm", "check", str(bad), MODEL]) == 1
    out = capsys.readouterr().out
    assert f"{bad}:3:11: error E040: automaton 'X' has no init state" in out
    assert f"{bad}: invalid (1 errors, 0 warnings)" in out
    assert "pfc_modes.hcsm: ok" in out


def test_check_syntax_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "syntax.hcsm"
    bad.write_text("model M on PFC\n")
    assert main(["hcsm", "check", str(bad)]) == 1
    # the end of the file is after its last character (as in the TST and TALF languages)
    assert (
        f"{bad}:2:1: error E001: unexpected end of file; expected one of: ';'"
        in capsys.readouterr().out
    )


def test_check_rejects_an_empty_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    empty = tmp_path / "empty.hcsm"
    empty.write_text("")
    assert main(["hcsm", "check", str(empty)]) == 1
    out = capsys.readouterr().out
    assert f"{empty}:1:1: error E017: empty model: the file declares nothing" in out
    assert f"{empty}: invalid (1 errors, 1 warnings)" in out


def test_render_dot_with_trace(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    trace = tmp_path / "t.jsonl"
    config = ("Mode-Switch:Hovering-ST", "Control-Mode:Ctrl-Run-ST")
    write_jsonl([TraceRecord("PFC", 1, 1, 0.0, "pulse", "pulse", (), (), config)], trace)
    out = tmp_path / "m.dot"
    assert main(["hcsm", "render", MODEL, "-o", str(out), "--trace", str(trace)]) == 0
    assert out.read_text().count("fillcolor=gold") == 2
    assert f"wrote {out}" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["-o", "OUT.svg"], "graphviz 'dot'"),
        (["-o", "OUT.dot", "--trace", "MISSING"], "cannot read trace"),
        (["-o", "OUT.dot", "--trace", "EMPTY"], "holds no records"),
        (["-o", "OUT.dot", "--trace", "ONE", "--record", "5"], "outside the trace"),
    ],
)
def test_render_errors_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    (tmp_path / "EMPTY").write_text("")
    write_jsonl([TraceRecord("PFC", 1, 1, 0.0, "pulse", "pulse", (), (), ())], tmp_path / "ONE")
    args = [str(tmp_path / a) if a.isupper() else a for a in extra]
    if "OUT.svg" in extra and __import__("shutil").which("dot"):
        pytest.skip("graphviz installed")
    assert main(["hcsm", "render", MODEL, *args]) == 2
    assert message in capsys.readouterr().err


def test_render_invalid_model_exit_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.hcsm"
    bad.write_text("automaton A X { }")
    assert main(["hcsm", "render", str(bad), "-o", str(tmp_path / "x.dot")]) == 1
    assert not (tmp_path / "x.dot").exists()
    assert "invalid, not drawn" in capsys.readouterr().out


def test_check_several_computers_runs_the_system_check(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    drc = tmp_path / "drc.hcsm"
    drc.write_text(
        "model D on DRC; computers PFC, DRC;\n"
        "event Traj3D-EV = 999 to PFC;\n"
        "automaton A D { init S-ST; A.1: S-ST -> S-ST on pulse / SEND Traj3D-EV to PFC; }\n"
        "root D;\n"
    )
    assert main(["hcsm", "check", MODEL, str(drc)]) == 1
    out = capsys.readouterr().out
    assert f"{drc}:2:7: error E060: event 'Traj3D-EV' has id 999 here but 1022" in out
    assert "system of 2 models: invalid" in out


def test_run_prints_transitions_and_writes_a_renderable_trace(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    trace = tmp_path / "run.jsonl"
    args = ["hcsm", "run", MODEL, "--steps", "4", "--cond", "2:Braking-Done-CO=true"]
    assert main([*args, "--cond", "3:Ctrl-Ready-CO=true", "--trace", str(trace)]) == 0
    out = capsys.readouterr().out
    assert "step 0: pulse -> A.1 Mode-Switch: Start-ST -> Stop-Ctrl-ST / SEND Ctrl-Stop-EV" in out
    assert "step 0: SEND Braking-Started-EV to DRC" in out
    assert "step 3: Ctrl-Ok-EV -> A.4 Mode-Switch: Wait-Hover-ST -> Stabilizing-ST" in out
    assert "configuration: Mode-Switch:Stabilizing-ST Control-Mode:Ctrl-Run-ST" in out
    dot = tmp_path / "m.dot"
    assert main(["hcsm", "render", MODEL, "-o", str(dot), "--trace", str(trace)]) == 0
    assert dot.read_text().count("fillcolor=gold") == 2


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--post", "x:Traj3D-EV"], "expected STEP:NAME"),
        (["--cond", "0:Nope-CO=true"], "unknown condition"),
        (["--cond", "0:Hover-Stable-CO=yes"], "unknown condition or value"),
    ],
)
def test_run_rejects_bad_scripts(
    capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    assert main(["hcsm", "run", MODEL, "--steps", "1", *extra]) == 2
    assert message in capsys.readouterr().err


def test_run_reports_unknown_events(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["hcsm", "run", MODEL, "--steps", "1", "--post", "0:Nope-EV"]) == 0
    assert "step 0: event 'Nope-EV' rejected" in capsys.readouterr().out
