"""`hdrc3 tst check` in-process."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main
from hdrc3.launch_plan import RAW_IMAGES
from hdrc3.launched_system import LaunchedSystem
from hdrc3_base.errors import ConfigError

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "tst"


def test_check_prints_the_tree_with_time_windows(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tst", "check", str(EXAMPLES / "example_6_1.tst")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "tau0: sequence  P=uav0  TS [0, 1200)  TE (0, 1200]"
    assert lines[3].startswith("    tau3: scan-area  P=uav1  TS [0, 1200)  TE (0, 1200)")
    assert "area=AreaB  altitude=30" in lines[3]
    assert lines[-1].startswith(f"{EXAMPLES / 'example_6_1.tst'}: ok (5 nodes, 10 time variables")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("t(TS, TE) = sequence", "bad.tst:1:21: error E001: unexpected end of file"),
        (
            "t(TS, TE) = hover(TS, TE, 5) where P = uav0",
            "bad.tst:1:36: error E101: unknown name 'P'",
        ),
        ("t(TS, TE) = hover(TS, TE, 5) where TE <= 3", "bad.tst:1:1: error E200: inconsistent"),
    ],
)
def test_invalid_input_exits_4_with_file_line_column(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    text: str,
    expected: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.tst").write_text(text)
    assert main(["tst", "check", "bad.tst"]) == 4
    assert capsys.readouterr().out.startswith(expected)


def test_agents_option_adds_agents(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    file = tmp_path / "a.tst"
    file.write_text("t(P, TS, TE) = land(TS, TE) where P = uav3")
    assert main(["tst", "check", str(file)]) == 4
    assert main(["tst", "check", str(file), "--agents", "uav3"]) == 0
    assert main(["tst", "check", str(file), "--agents", "UAV"]) == 2  # malformed agent name
    assert "invalid agent name" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("options", "excluded"),
    [
        (["--out", "OUT"], RAW_IMAGES),
        (["--out", "OUT", "--record-exclude", ""], None),
        (["--out", "OUT", "--record-exclude", "saliency$"], "saliency$"),
        ([], None),  # nothing recorded without --out
    ],
)
def test_run_launch_records_without_raw_images_by_default(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, options: list[str], excluded: str | None
) -> None:
    commands: list[list[str]] = []

    def refuse(system: LaunchedSystem) -> LaunchedSystem:
        commands.append(system.command)
        raise ConfigError("not launched in a unit test")

    monkeypatch.setattr(LaunchedSystem, "__enter__", refuse)
    argv = [str(tmp_path) if word == "OUT" else word for word in options]
    assert main(["tst", "run", str(EXAMPLES / "example_6_1.tst"), "--launch", *argv]) == 2
    (command,) = commands
    if excluded is None:
        assert "--record-exclude" not in command
    else:
        assert command[command.index("--record-exclude") + 1] == excluded


def test_run_rejects_a_malformed_exclude_pattern_before_creating_anything(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    args = ["--launch", "--out", str(out), "--record-exclude", "image_raw["]
    assert main(["tst", "run", str(EXAMPLES / "example_6_1.tst"), *args]) == 2
    assert "--record-exclude 'image_raw[' is not a regular expression" in capsys.readouterr().err
    assert not out.exists()
