"""The keystore file: loading, validation, keys never printed."""

from __future__ import annotations

import re
import stat
from pathlib import Path

import pytest

from hdrc3_delegation.keystore import (
    KeystoreError,
    load_keystore,
    parse_keystore,
    write_keystore,
)

KEY = "11" * 32


def test_written_keystores_are_private_and_load_back(tmp_path: Path) -> None:
    path = tmp_path / "keys.toml"
    written = write_keystore(path, ["gcs", "uav0"])
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    loaded = load_keystore(path)
    assert loaded.agents == ("gcs", "uav0")
    assert loaded.key("uav0") == written.key("uav0")
    assert loaded.key("uav9") is None


def test_repr_never_shows_a_key() -> None:
    keystore = parse_keystore(f'[keys]\nuav0 = "{KEY}"\n')
    assert KEY not in repr(keystore) and "uav0" in repr(keystore)


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("[keys\n", "line 1"),
        ("", "no [keys] table"),
        ("[keys]\n", "no [keys] table"),
        (f'[keys]\nUAV = "{KEY}"\n', "not an agent name"),
        ("[keys]\nuav0 = 5\n", "not a hex string"),
        ('[keys]\nuav0 = "zz"\n', "not valid hex"),
        ('[keys]\nuav0 = "abcd"\n', "2 bytes"),
    ],
)
def test_malformed_keystores_are_refused(text: str, reason: str) -> None:
    with pytest.raises(KeystoreError, match=re.escape(reason)) as info:
        parse_keystore(text, "k.toml")
    assert str(info.value).startswith("k.toml")
    assert KEY not in str(info.value)


def test_an_unreadable_file_is_a_keystore_error(tmp_path: Path) -> None:
    with pytest.raises(KeystoreError, match="cannot read"):
        load_keystore(tmp_path / "missing.toml")
