"""Conditions of ``if``, ``while`` and ``foreach`` nodes: queries an agent answers (Figure 16).

The chapter's condition is a FIPA query to an agent, answered when the node executes. An RMAX's
TST manager answers the queries it can decide from its own Data Interface (one registry below);
any other query has no answering agent yet (knowledge from DyKnow and perception comes with later
issues), and the node fails with that reason instead of guessing.

A ``foreach`` query has free variables (its loop variables) and answers with every binding
that makes it true. The manager answers those it knows from the mission itself: its agents and
their capabilities (section 9.4's ``foreach av where [t] can-scan(av) do conc ...``) and its
declared places.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

from hdrc3_deliberative.mission_syntax import Name
from hdrc3_tst.actions import ParamType
from hdrc3_tst.platform_port import PlatformState
from hdrc3_tst.syntax import Condition

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


@dataclass(frozen=True)
class QueryDomain:
    """What a manager knows about its mission: the agents, their actions, the declared places."""

    agents: tuple[str, ...]
    actions: frozenset[str]
    """The action types an agent of the mission executes (every agent is an RMAX today)."""
    places: Mapping[str, ParamType]


@dataclass(frozen=True)
class Answers:
    """Every binding of a foreach's variables that makes its query true (UNKNOWN: a reason)."""

    answer: Answer
    bindings: tuple[tuple[str, ...], ...] = ()
    reason: str = ""


_ENUMERATED: Mapping[str, Callable[[QueryDomain], tuple[str, ...]]] = MappingProxyType(
    {
        "agent": lambda d: d.agents,
        "can-scan": lambda d: d.agents if "scan-area" in d.actions else (),
        "can-fly": lambda d: d.agents if "fly-to" in d.actions else (),
        "point": lambda d: tuple(n for n, k in d.places.items() if k is ParamType.POINT),
        "area": lambda d: tuple(n for n, k in d.places.items() if k is ParamType.AREA),
    }
)
"""Unary predicates with a free variable, answered over the mission's domain."""


def ask_all(
    condition: Condition,
    loop_vars: tuple[str, ...],
    domain: QueryDomain,
    agent: str,
    values: Mapping[str, float | str],
    state: PlatformState | None,
) -> Answers:
    """Answer a foreach query: the loop variables' bindings, in the domain's order.

    A query that names none of the loop variables is a yes/no query: false has no answers,
    true binds nothing (an error: the instances would be identical).
    """
    free = [a.id for a in condition.args if isinstance(a, Name) and a.id in loop_vars]
    if not free:
        single = ask(condition, agent, values, state)
        if single.answer is Answer.FALSE:
            return Answers(Answer.FALSE)
        reason = single.reason or (
            f"the query {condition.name}(...) binds none of {', '.join(loop_vars)}"
        )
        return Answers(Answer.UNKNOWN, reason=reason)
    enumerate_ = _ENUMERATED.get(condition.name)
    if enumerate_ is None or len(condition.args) != 1 or tuple(free) != loop_vars:
        known = ", ".join(f"{n}(X)" for n in _ENUMERATED)
        return Answers(
            Answer.UNKNOWN,
            reason=f"no agent answers {condition.name}(...) over {', '.join(loop_vars)} "
            f"(answered here: {known}, binding the only loop variable)",
        )
    if condition.negated:
        return Answers(
            Answer.UNKNOWN, reason=f"not {condition.name}(X) has no finite set of answers here"
        )
    found = enumerate_(domain)
    return Answers(Answer.TRUE if found else Answer.FALSE, tuple((v,) for v in found))
