"""Conversion of a timed concurrent plan into a Task Specification Tree (§9.2, §6.3).

The plan becomes a concurrent node with one sequence node per agent; each elementary action
node keeps its planned start and end times, which the TST executor uses as temporal
constraints (so dependencies between agents are kept by time, as in the plan).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Any

from hdrc3_deliberative.result import Occurrence

UNASSIGNED = "unassigned"


class TstNodeKind(Enum):
    """Node types used for plan sub-trees."""

    SEQUENCE = "sequence"
    CONCURRENT = "concurrent"
    ELEMENTARY = "elementary"


@dataclass(frozen=True)
class TstPlanNode:
    """A node of a plan sub-tree: control nodes have children, elementary nodes an action."""

    kind: TstNodeKind
    children: tuple[TstPlanNode, ...] = ()
    action: Occurrence | None = None
    agent: str = UNASSIGNED

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly nested dict."""
        out: dict[str, Any] = {"type": self.kind.value, "agent": self.agent}
        if self.action is not None:
            out.update(
                action=self.action.name,
                args=list(self.action.args),
                start=self.action.start,
                end=self.action.end,
            )
        if self.children:
            out["children"] = [child.to_dict() for child in self.children]
        return out

    def elementary(self) -> list[Occurrence]:
        """All actions below this node, depth first."""
        if self.action is not None:
            return [self.action]
        return [occ for child in self.children for occ in child.elementary()]


def plan_to_tst(plan: tuple[Occurrence, ...]) -> TstPlanNode:
    """Concurrent node over per-agent sequences of elementary action nodes."""
    by_agent: dict[str, list[Occurrence]] = {}
    for occ in plan:
        by_agent.setdefault(occ.agent or UNASSIGNED, []).append(occ)
    sequences = tuple(
        TstPlanNode(
            TstNodeKind.SEQUENCE,
            tuple(
                TstPlanNode(TstNodeKind.ELEMENTARY, action=o, agent=agent)
                for o in sorted(occs, key=lambda o: o.start)
            ),
            agent=agent,
        )
        for agent, occs in sorted(by_agent.items())
    )
    if len(sequences) == 1:
        return sequences[0]
    return TstPlanNode(TstNodeKind.CONCURRENT, sequences)
