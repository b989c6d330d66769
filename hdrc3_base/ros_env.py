"""ROS 2 environment defaults shared by every hdrc3 entry point."""

from __future__ import annotations

import os
from collections.abc import MutableMapping

DISCOVERY_RANGE_VAR = "ROS_AUTOMATIC_DISCOVERY_RANGE"
LOCALHOST = "LOCALHOST"
DISCOVERY_RANGES = ("LOCALHOST", "SUBNET", "OFF", "SYSTEM_DEFAULT")
"""The values ROS 2 accepts for ``ROS_AUTOMATIC_DISCOVERY_RANGE``."""
MAX_DOMAIN_ID = 101
"""Highest ROS domain id whose DDS ports are valid on Linux with the default port mapping."""


def apply_localhost_default(environ: MutableMapping[str, str] | None = None) -> str:
    """Keep DDS discovery on loopback unless the user chose a range deliberately.

    Must run before ``rclpy.init``: the RMW reads the variable when the context starts.

    Args:
        environ: Environment to update; the process environment by default.

    Returns:
        The discovery range now in force.

    """
    env = os.environ if environ is None else environ
    return env.setdefault(DISCOVERY_RANGE_VAR, LOCALHOST)
