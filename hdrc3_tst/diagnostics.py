"""Diagnostics: located, coded messages from the parser, the resolver and the network."""

from __future__ import annotations

from dataclasses import dataclass

from hdrc3_deliberative.mission_syntax import SourcePos


@dataclass(frozen=True)
class Diagnostic:
    """One error with its source position, a stable code and a readable message.

    Codes: E000 unreadable file, E001 syntax, E002 bad number, E1xx names and types
    (resolver), E2xx constraint inconsistency (network).
    """

    code: str
    message: str
    pos: SourcePos

    def __str__(self) -> str:
        return f"{self.pos}: error {self.code}: {self.message}"
