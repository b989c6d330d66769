"""Agent names: each agent's nodes live under the ROS namespace ``/<agent>``."""

from __future__ import annotations

import re

from hdrc3_base.errors import ConfigError

AGENT_NAME = re.compile(r"^[a-z][a-z0-9_]{0,31}$")
"""Lower-case letters, digits and '_', starting with a letter: a valid ROS namespace."""


def parse_agents(text: str) -> tuple[str, ...]:
    """Parse ``uav0,uav1`` into agent names, rejecting malformed or duplicate names."""
    agents = tuple(a.strip() for a in text.split(",") if a.strip())
    if not agents:
        raise ConfigError("no agent given (expected e.g. --agents uav0,uav1)")
    for agent in agents:
        if not AGENT_NAME.match(agent):
            raise ConfigError(
                f"invalid agent name {agent!r}: use lower-case letters, digits and '_', "
                "starting with a letter (it becomes the ROS namespace /<agent>)"
            )
    if len(set(agents)) != len(agents):
        raise ConfigError(f"agent listed twice in {text!r}")
    return agents
