"""The live view: the running system as Foxglove channels over a local WebSocket (issue 19)."""

DEFAULT_HOST = "127.0.0.1"
"""Loopback only, unless the user binds elsewhere deliberately."""
DEFAULT_PORT = 8765
"""Foxglove's default WebSocket port."""
