"""Exceptions of the HCSM package (misuse); expected failures are results with a status."""

from __future__ import annotations

from hdrc3_base.errors import ConfigError, DataError


class ModelError(DataError):
    """A model cannot be loaded or run (parse or validation errors, missing root)."""


class BindingError(ConfigError):
    """The interpreter was bound to conditions, computers or functions that do not fit the model."""
