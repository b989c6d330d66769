import pytest

from hdrc3_base.agents import parse_agents
from hdrc3_base.errors import ConfigError


@pytest.mark.parametrize(
    ("text", "agents"),
    [("uav0", ("uav0",)), ("uav0, uav1", ("uav0", "uav1")), ("a_1,", ("a_1",))],
)
def test_parse_agents(text: str, agents: tuple[str, ...]) -> None:
    assert parse_agents(text) == agents


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "no agent given"),
        ("UAV0", "invalid agent name 'UAV0'"),
        ("uav-0", "invalid agent name"),
        ("0uav", "invalid agent name"),
        ("uav0,uav0", "agent listed twice"),
    ],
)
def test_bad_agents(text: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        parse_agents(text)
