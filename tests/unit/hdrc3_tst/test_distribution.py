"""Binding open agents and naming the agents a mission involves."""

from __future__ import annotations

import pytest

from hdrc3_tst.check import load_text
from hdrc3_tst.distribution import Fix, bind_open_agents, involved_agents, parse_fix

HEAD = "world revinge\nagents uav0, uav1\npoint Sq = town_square at 30\n"


@pytest.mark.parametrize(
    ("where", "preferred", "fixes", "involved"),
    [
        ("true", "uav1", ["m.P=uav1"], ("uav1",)),
        ("P != uav1", "uav1", ["m.P=uav0"], ("uav0",)),
        ("P = uav0", "uav1", [], ("uav0",)),
    ],
)
def test_open_agents_prefer_the_given_one(
    where: str, preferred: str, fixes: list[str], involved: tuple[str, ...]
) -> None:
    result = load_text(HEAD + f"m(P, TS, TE) = fly-to(TS, TE, 5, Sq) where {where}\n")
    assert result.tst is not None
    made, reason = bind_open_agents(result.tst, preferred)
    assert reason == ""
    assert [str(f) for f in made] == fixes
    assert involved_agents(result.tst) == involved


@pytest.mark.parametrize(
    ("text", "fix"),
    [
        ("tau2.speed=4", Fix("tau2", "speed", 4.0)),
        ("call/hop.P=uav1", Fix("call/hop", "P", "uav1")),
        ("tau2.speed", None),
        ("speed=4", None),
        ("tau2.=4", None),
    ],
)
def test_parse_fix(text: str, fix: Fix | None) -> None:
    assert parse_fix(text) == fix
