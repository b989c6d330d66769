"""Diagnostics: located, coded messages from the parser and the validator."""

from __future__ import annotations

import enum
from dataclasses import dataclass

from hdrc3_hcsm.model import SourcePos


class Severity(enum.Enum):
    """How bad a finding is: errors stop a model from being run, warnings do not."""

    ERROR = "error"
    WARNING = "warning"


@dataclass(frozen=True)
class Diagnostic:
    """One finding with its source position, a stable code and a readable message."""

    severity: Severity
    code: str
    message: str
    pos: SourcePos

    def __str__(self) -> str:
        return f"{self.pos}: {self.severity.value} {self.code}: {self.message}"


def has_errors(diagnostics: tuple[Diagnostic, ...] | list[Diagnostic]) -> bool:
    """Tell whether any diagnostic is an error."""
    return any(d.severity is Severity.ERROR for d in diagnostics)
