"""`hdrc3 world list|check` in-process."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main


def test_list_shows_revinge(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["world", "list"]) == 0
    assert "revinge" in capsys.readouterr().out.split()


def test_check_shipped_world(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["world", "check", "revinge"]) == 0
    out = capsys.readouterr().out
    assert "revinge: ok" in out and "28 buildings" in out and "pads H1, H2" in out


def test_check_bad_world_prints_file_line_reason(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text('[world]\nname = "x"\n[[object]]\nid = "a"\ntype = "tank"\n')
    assert main(["world", "check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:1: missing required section [origin]" in err
    assert f"{bad}:5: unknown object type 'tank'" in err
