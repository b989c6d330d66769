"""`hdrc3 tst check` in-process."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main

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
