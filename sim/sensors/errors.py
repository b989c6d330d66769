"""Exceptions of the sensor models (misuse, never expected failures)."""

from hdrc3_base.errors import ConfigError


class SensorError(ConfigError):
    """A sensor was configured or driven with invalid parameters."""
