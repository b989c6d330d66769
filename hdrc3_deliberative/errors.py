"""Exceptions of the deliberative layer (bad planning input)."""

from __future__ import annotations

from hdrc3_base.errors import ConfigError, Hdrc3Error


class PlanningInputError(ConfigError):
    """A domain, problem or control file is malformed or inconsistent.

    The message starts with ``file:line:column`` when a position is known.
    """

    def __init__(self, message: str, source: str = "", line: int = 0, column: int = 0) -> None:
        self.source = source
        self.line = line
        self.column = column
        self.reason = message
        where = source
        if line:
            where = f"{source}:{line}:{column}"
        super().__init__(f"{where}: {message}" if where else message)


class GroundingTimeout(Hdrc3Error):
    """Grounding did not finish before the planning deadline (the planner reports TIMEOUT)."""
