"""`hdrc3 keys` and `hdrc3 delegate` on bad input (the flights are integration tests)."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main

EXAMPLES = Path(__file__).parents[3] / "examples" / "tst"


def test_keys_generate_writes_a_private_keystore_and_never_prints_a_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from hdrc3_delegation.keystore import load_keystore

    path = tmp_path / "keys.toml"
    assert main(["keys", "generate", str(path), "--agents", "gcs,uav0"]) == 0
    out = capsys.readouterr().out
    keys = load_keystore(path)
    assert keys.agents == ("gcs", "uav0")
    assert all(keys.key(a).hex() not in out for a in keys.agents)  # type: ignore[union-attr]
    assert main(["keys", "generate", str(path)]) == 2, "an existing keystore is kept"
    assert "exists" in capsys.readouterr().err
    assert main(["keys", "generate", str(tmp_path / "k2.toml"), "--agents", "UAV!"]) == 2


@pytest.mark.parametrize(
    ("args", "code", "message"),
    [
        (["delegate", "missing.tst", "--keystore", "{keys}"], 4, "unreadable"),
        (["delegate", "{bad}", "--keystore", "{keys}"], 4, "bad.tst:2:1: error E001"),
        (["delegate", "{ex}", "--keystore", "{none}"], 2, "cannot read the keystore"),
        (["delegate", "{ex}", "--keystore", "{keys}", "--to", "Uav!"], 2, "invalid agent"),
        (["delegate", "{ex}", "--keystore", "{keys}", "--max-agents", "0"], 2, "--max-agents"),
        (["delegate", "{ex}", "--keystore", "{keys}", "--as", "nobody"], 2, "no key for nobody"),
        (
            ["delegate", "{ex}", "--keystore", "{keys}", "--to", "uav0", "--responsible", "uav1"],
            2,
            "--responsible uav1 is not one of the agents uav0",
        ),
    ],
)
def test_delegate_refuses_bad_input_before_anything_starts(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    args: list[str],
    code: int,
    message: str,
) -> None:
    from hdrc3_delegation.keystore import write_keystore

    keys = tmp_path / "keys.toml"
    write_keystore(keys, ("gcs", "uav0"))
    bad = tmp_path / "bad.tst"
    bad.write_text("tau0(TS0, TE0) = fly-to(\n")
    values = {
        "keys": str(keys),
        "bad": str(bad),
        "ex": str(EXAMPLES / "delegate_two_pads.tst"),
        "none": str(tmp_path / "none.toml"),
    }
    assert main([a.format(**values) for a in args]) == code
    captured = capsys.readouterr()
    assert message in captured.out + captured.err
