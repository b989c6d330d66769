"""Root of the hdrc3 exception hierarchy (misuse raises these; expected failures are results)."""


class Hdrc3Error(Exception):
    """Base class of every exception hdrc3 raises on misuse or bad input."""


class ConfigError(Hdrc3Error):
    """A command line, configuration file or argument is invalid."""


class DataError(Hdrc3Error):
    """A data file (recording, world, model) is missing, unreadable or corrupt."""


class SourceError(ConfigError):
    """A text in one of the stack's languages is malformed: ``source:line:column: reason``."""

    def __init__(self, reason: str, source: str, line: int, column: int) -> None:
        """Keep the parts; the message is ``source:line:column: reason``."""
        self.reason = reason
        self.source = source
        self.line = line
        self.column = column
        super().__init__(f"{source}:{line}:{column}: {reason}")
