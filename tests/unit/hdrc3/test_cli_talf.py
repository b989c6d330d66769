"""`hdrc3 talf`: check, to-tst, from-tst and semantics, in-process and through the command."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from hdrc3.cli.main import main
from hdrc3_tst.check import CheckStatus, load_file
from hdrc3_tst.parser import parse_file, parse_text

ROOT = Path(__file__).resolve().parents[3]
TALF = ROOT / "examples" / "talf"
TST = ROOT / "examples" / "tst"


def test_check_accepts_the_examples(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["talf", "check", str(TALF / "fukushima_monitor.talf")]) == 0
    out = capsys.readouterr().out
    assert out.endswith("ok (2 missions, 6 composite action types with the library)\n")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("mission m: [t, t2]", "bad.talf:1:19: error T001: unexpected end of file"),
        ("mission m: [t, t2] fly(1)", "bad.talf:1:20: error T102: unknown action 'fly'"),
        ("mission m: [t, t2] hover()", "bad.talf:1:20: error T103: hover takes (duration)"),
        ("mission m: [t, t2] hover(x)", "bad.talf:1:26: error T101: unbound variable 'x'"),
    ],
)
def test_invalid_input_exits_2_with_file_line_column(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    text: str,
    expected: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.talf").write_text(text)
    assert main(["talf", "check", "bad.talf"]) == 2
    assert capsys.readouterr().out.startswith(expected)


def test_a_mission_no_agent_can_fly_is_rejected_before_anything_flies(
    capsys: pytest.CaptureFixture[str],
) -> None:
    file = str(TALF / "emergency_services.talf")
    caps = ["--capabilities", "uav0=flight+hook", "--capabilities", "uav1=flight"]
    assert main(["talf", "to-tst", file, *caps]) == 2
    out = capsys.readouterr().out
    assert "error T110: unsatisfiable constraints: emergency/leg1/" in out
    assert (
        "scan-area needs camera+flight+ptu; no agent has it (uav0: flight+hook; uav1: flight)"
        in out
    )
    assert main(["talf", "check", file, "--capabilities", "uav0=flight+wings"]) == 2
    assert "--capabilities 'uav0=flight+wings'" in capsys.readouterr().err


def test_to_tst_writes_a_tst_that_tst_check_accepts(tmp_path: Path) -> None:
    out = tmp_path / "diamond.tst"
    file = str(TALF / "fukushima_monitor.talf")
    assert main(["talf", "to-tst", file, "--mission", "diamond", "-o", str(out)]) == 0
    checked = load_file(out)
    assert checked.status is CheckStatus.OK
    assert main(["talf", "to-tst", file, "--mission", "nope"]) == 2


def test_from_tst_and_back(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    talf = tmp_path / "ex.talf"
    assert main(["talf", "from-tst", str(TST / "example_6_1.tst"), "-o", str(talf)]) == 0
    assert "mission tau0:" in talf.read_text()
    capsys.readouterr()
    assert main(["talf", "to-tst", str(talf)]) == 0
    assert parse_text(capsys.readouterr().out).tree == parse_file(TST / "example_6_1.tst").tree
    assert main(["talf", "from-tst", str(TST / "patrol.tst")]) == 2
    assert "call node go: TALF composite actions are expanded" in capsys.readouterr().out


def test_semantics_prints_the_narrative(capsys: pytest.CaptureFixture[str]) -> None:
    file = str(TALF / "fukushima_monitor.talf")
    assert main(["talf", "semantics", file, "--mission", "single"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("definition monitor-single:\n  forall t, t2, av, target, duration")
    assert "mission single:\n  exists t1, t2, t3, t4 (TS <= TE" in out


def test_the_hdrc3_command_runs_talf(tmp_path: Path) -> None:
    command = Path(sys.executable).with_name("hdrc3")
    assert command.exists()
    file = str(TALF / "emergency_services.talf")
    done = subprocess.run(
        [str(command), "talf", "to-tst", file, "-o", str(tmp_path / "e.tst")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    checked = subprocess.run(
        [str(command), "tst", "check", str(tmp_path / "e.tst")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert checked.stdout.splitlines()[-1].startswith(f"{tmp_path / 'e.tst'}: ok (12 nodes, ")
