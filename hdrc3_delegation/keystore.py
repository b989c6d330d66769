"""Per-agent HMAC keys from a keystore file (TOML), for authenticated speech acts (section 10).

The file holds one table, ``[keys]``, mapping each agent name to its key in hex (at least
:data:`MIN_KEY_BYTES` bytes)::

    [keys]
    gcs = "6b1f..."
    uav0 = "90ac..."

A gateway needs the key of every agent it accepts messages from, and its own to sign. Keys never
appear in ``repr``, logs or recordings: :class:`Keystore` only hands them to the authenticator.
:func:`write_keystore` creates a file readable by its owner only (mode 0600).
"""

from __future__ import annotations

import os
import secrets
import tomllib
from collections.abc import Iterable
from pathlib import Path

from hdrc3_base.agents import AGENT_NAME
from hdrc3_base.errors import ConfigError

MIN_KEY_BYTES = 32
"""Shortest key accepted (HMAC-SHA256's block is 64 bytes; 32 random bytes are 256 bits)."""


class KeystoreError(ConfigError):
    """The keystore file is unreadable or malformed (the message never contains a key)."""


class Keystore:
    """Agent name -> key; knows which agents it holds, never prints a key."""

    def __init__(self, keys: dict[str, bytes]) -> None:
        """Keep the keys (validated by the loader)."""
        self._keys = dict(keys)

    @property
    def agents(self) -> tuple[str, ...]:
        """The agents with a key, sorted."""
        return tuple(sorted(self._keys))

    def key(self, agent: str) -> bytes | None:
        """The agent's key, or None when unknown."""
        return self._keys.get(agent)

    def __repr__(self) -> str:
        return f"Keystore(agents={list(self.agents)})"


def parse_keystore(text: str, source: str = "<keystore>") -> Keystore:
    """Keys from TOML text (raises :class:`KeystoreError` with the source and reason)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise KeystoreError(f"{source}: {exc}") from None
    table = data.get("keys")
    if not isinstance(table, dict) or not table:
        raise KeystoreError(f"{source}: no [keys] table with at least one agent")
    keys: dict[str, bytes] = {}
    for agent, value in table.items():
        if not AGENT_NAME.match(agent):
            raise KeystoreError(f"{source}: {agent!r} is not an agent name")
        if not isinstance(value, str):
            raise KeystoreError(f"{source}: the key of {agent} is not a hex string")
        try:
            key = bytes.fromhex(value)
        except ValueError:
            raise KeystoreError(f"{source}: the key of {agent} is not valid hex") from None
        if len(key) < MIN_KEY_BYTES:
            raise KeystoreError(
                f"{source}: the key of {agent} has {len(key)} bytes, fewer than {MIN_KEY_BYTES}"
            )
        keys[agent] = key
    return Keystore(keys)


def load_keystore(path: str | Path) -> Keystore:
    """Keys from a keystore file (raises :class:`KeystoreError` when unreadable or malformed)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise KeystoreError(f"{path}: cannot read the keystore: {exc.__class__.__name__}") from None
    return parse_keystore(text, str(path))


def write_keystore(path: str | Path, agents: Iterable[str]) -> Keystore:
    """A new keystore with a fresh random key per agent, written with mode 0600."""
    agents = tuple(agents)
    for agent in agents:
        if not AGENT_NAME.match(agent):
            raise KeystoreError(f"{agent!r} is not an agent name")
    keys = {agent: secrets.token_bytes(MIN_KEY_BYTES) for agent in agents}
    lines = ["# hdrc3 agent keys (HMAC-SHA256); keep this file private", "[keys]"]
    lines += [f'{agent} = "{key.hex()}"' for agent, key in keys.items()]
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as out:
        out.write("\n".join(lines) + "\n")
    return Keystore(keys)
