"""Conditions of ``if``, ``while`` and ``foreach`` nodes: queries an agent answers (Figure 16).

The chapter's condition is a FIPA query to an agent, answered when the node executes. An RMAX's
TST manager answers the queries it can decide from its own Data Interface (one registry below);
any other query has no answering agent yet (knowledge from DyKnow and perception comes with later
issues), and the node fails with that reason instead of guessing.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

from hdrc3_tst.platform_port import PlatformState
from hdrc3_tst.syntax import Condition, Name

LOW_BATTERY = 0.3
"""State of charge below which ``low-battery(P)`` holds."""


class Answer(enum.Enum):
    """The answer to a yes/no query."""

    TRUE = "true"
    FALSE = "false"
    UNKNOWN = "unknown"


@dataclass(frozen=True)
class QueryResult:
    """An answer, with the reason when it is UNKNOWN."""

    answer: Answer
    reason: str = ""


_PREDICATES: Mapping[str, Callable[[PlatformState], bool]] = MappingProxyType(
    {
        "airborne": lambda s: not s.on_ground,
        "on-ground": lambda s: s.on_ground,
        "autonomous": lambda s: s.autonomous,
        "low-battery": lambda s: s.battery < LOW_BATTERY,
        "failsafe": lambda s: bool(s.failsafe),
    }
)
"""Predicates over one agent's own state, each taking that agent as its only argument."""


def ask(
    condition: Condition,
    agent: str,
    values: Mapping[str, float | str],
    state: PlatformState | None,
) -> QueryResult:
    """Answer ``condition`` as ``agent`` would, from its latest Data Interface sample.

    Args:
        condition: The node's query.
        agent: The agent answering (the node's own).
        values: Variable values of the node's scope (an argument naming a variable is looked up).
        state: The agent's latest Data Interface sample.
    """
    predicate = _PREDICATES.get(condition.name)
    if predicate is None:
        known = ", ".join(sorted(_PREDICATES))
        return QueryResult(
            Answer.UNKNOWN,
            f"no agent answers the query {condition.name}(...) (an RMAX answers: {known})",
        )
    subjects = [values.get(a.id, a.id) if isinstance(a, Name) else a.value for a in condition.args]
    if subjects != [agent]:
        return QueryResult(
            Answer.UNKNOWN, f"{condition.name} is answered by {agent} about itself only"
        )
    if state is None:
        return QueryResult(Answer.UNKNOWN, f"{agent} has no Data Interface sample yet")
    holds = predicate(state) != condition.negated
    return QueryResult(Answer.TRUE if holds else Answer.FALSE)
