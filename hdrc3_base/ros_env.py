"""ROS 2 environment defaults shared by every hdrc3 entry point.

Two defaults, each kept when the user set the variable deliberately:

* ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``: DDS stays on loopback.
* ``FASTRTPS_DEFAULT_PROFILES_FILE`` names the packaged ``dds_discovery.xml``: Fast DDS
  participants announce themselves every 0.5 s instead of every 3 s, so that a restarted node
  and its peers find each other within about a second (issue 21's restart target) instead of
  waiting for the next 3 s announcement. Fast DDS reads the file when the first participant of
  the process is created, so this, too, must run before ``rclpy.init``.
"""

from __future__ import annotations

import os
from collections.abc import MutableMapping
from importlib import resources

DISCOVERY_RANGE_VAR = "ROS_AUTOMATIC_DISCOVERY_RANGE"
LOCALHOST = "LOCALHOST"
DISCOVERY_RANGES = ("LOCALHOST", "SUBNET", "OFF", "SYSTEM_DEFAULT")
"""The values ROS 2 accepts for ``ROS_AUTOMATIC_DISCOVERY_RANGE``."""
MAX_DOMAIN_ID = 101
"""Highest ROS domain id whose DDS ports are valid on Linux with the default port mapping."""
PROFILES_VARS = ("FASTRTPS_DEFAULT_PROFILES_FILE", "FASTDDS_DEFAULT_PROFILES_FILE")
"""Where Fast DDS 2.x (the first) and 3.x look for an XML profile file; either, if set, wins."""
DISCOVERY_PROFILE = "dds_discovery.xml"
"""The packaged profile file (in ``hdrc3_base``)."""


def discovery_profile() -> str:
    """Path of the packaged Fast DDS profile file."""
    return str(resources.files("hdrc3_base").joinpath(DISCOVERY_PROFILE))


def apply_dds_defaults(environ: MutableMapping[str, str] | None = None) -> str:
    """Keep DDS on loopback and discovery quick, unless the user chose otherwise.

    Must run before ``rclpy.init``: the RMW reads the variables when the context starts.

    Args:
        environ: Environment to update; the process environment by default.

    Returns:
        The discovery range now in force.
    """
    env = os.environ if environ is None else environ
    profile = discovery_profile()
    if not any(env.get(var) for var in PROFILES_VARS) and os.path.isfile(profile):
        env[PROFILES_VARS[0]] = profile  # (an install without the file: Fast DDS's own timing)
    return env.setdefault(DISCOVERY_RANGE_VAR, LOCALHOST)
