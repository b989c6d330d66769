"""Root of the hdrc3 exception hierarchy (misuse raises these; expected failures are results)."""


class Hdrc3Error(Exception):
    """Base class of every exception hdrc3 raises on misuse or bad input."""


class ConfigError(Hdrc3Error):
    """A command line, configuration file or argument is invalid."""


class DataError(Hdrc3Error):
    """A data file (recording, world, model) is missing, unreadable or corrupt."""
