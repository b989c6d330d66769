"""Diagnostics of TALF files: located, coded, readable; and the status of a load.

Codes: T000 unreadable file, T001 syntax, T002 bad number, T101 unbound variable, T102 unknown
action, T103 wrong arity, T104 argument of the wrong kind, T105 defined twice, T106 recursive
composite action, T107 unknown constraint set, T108 unknown mission, T110 no agent has the
capabilities a node needs.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from hdrc3_deliberative.mission_syntax import SourcePos


class TalfStatus(enum.Enum):
    """Outcome of reading or checking a TALF file."""

    OK = "ok"
    UNREADABLE = "unreadable"
    SYNTAX_ERROR = "syntax_error"
    INVALID = "invalid"
    UNSATISFIABLE = "unsatisfiable"


@dataclass(frozen=True)
class TalfDiagnostic:
    """One error: where, a stable code and a reason."""

    code: str
    message: str
    pos: SourcePos

    def __str__(self) -> str:
        return f"{self.pos}: error {self.code}: {self.message}"
