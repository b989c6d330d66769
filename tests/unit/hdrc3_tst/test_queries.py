"""Queries of conditional nodes, answered from the agent's own Data Interface."""

from __future__ import annotations

import pytest

from hdrc3_deliberative.mission_syntax import Name
from hdrc3_tst.platform_port import PlatformState
from hdrc3_tst.queries import Answer, ask
from hdrc3_tst.syntax import Condition

FLYING = PlatformState(0.0, 0.0, 30.0, on_ground=False, autonomous=True, battery=0.2)
VALUES = {"P": "uav0", "Q": "uav1"}


@pytest.mark.parametrize(
    ("name", "args", "negated", "state", "answer", "reason"),
    [
        ("airborne", ("P",), False, FLYING, Answer.TRUE, ""),
        ("on-ground", ("P",), False, FLYING, Answer.FALSE, ""),
        ("on-ground", ("P",), True, FLYING, Answer.TRUE, ""),
        ("low-battery", ("uav0",), False, FLYING, Answer.TRUE, ""),
        ("airborne", ("Q",), False, FLYING, Answer.UNKNOWN, "airborne is answered by uav0"),
        ("airborne", ("P",), False, None, Answer.UNKNOWN, "uav0 has no Data Interface sample"),
        ("seen", ("P",), False, FLYING, Answer.UNKNOWN, "no agent answers the query seen(...)"),
    ],
)
def test_ask(
    name: str,
    args: tuple[str, ...],
    negated: bool,
    state: PlatformState | None,
    answer: Answer,
    reason: str,
) -> None:
    condition = Condition(name, tuple(Name(a) for a in args), negated)
    result = ask(condition, "uav0", VALUES, state)
    assert result.answer is answer
    assert result.reason.startswith(reason)
