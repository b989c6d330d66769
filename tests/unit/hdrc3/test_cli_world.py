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


def test_generate_writes_a_world_that_checks(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "gen.toml"
    assert main(["world", "generate", "--seed", "3", "--out", str(out), "--animals", "2"]) == 0
    assert "revinge-s3 ok" in capsys.readouterr().out
    assert main(["world", "check", str(out)]) == 0
    assert "2 animal" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--seed", "-2"], "seed must be an integer >= 0"),
        (["--seed", "1", "--persons", "999"], "object counts must be 0..200"),
        (["--seed", "1", "--base", "atlantis"], "cannot read world file"),
    ],
)
def test_generate_refuses_bad_requests(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    out = tmp_path / "gen.toml"
    assert main(["world", "generate", "--out", str(out), *args]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()
