"""A mission across agents (section 6.3): who holds which node, and the fixes every replica shares.

Each agent's TST manager resolves the same mission text, so each holds a replica of the
constraint network, and keeps the nodes whose agent ``P`` is its own. Before the text is sent,
the client binds every open ``P`` (preferring the agent that runs the root) and sends those
bindings, with any other fixes, as ``node.param=value`` strings, so that every replica assigns
the same nodes to the same agents.
"""

from __future__ import annotations

from dataclasses import dataclass

from hdrc3_tst.finite import SolveStatus
from hdrc3_tst.model import NodeKind
from hdrc3_tst.network import FixStatus
from hdrc3_tst.resolver import ResolvedTst


@dataclass(frozen=True)
class Fix:
    """One fixed parameter of one node."""

    node_id: str
    param: str
    value: float | str

    def __str__(self) -> str:
        value = f"{self.value:g}" if isinstance(self.value, float) else self.value
        return f"{self.node_id}.{self.param}={value}"


def parse_fix(text: str) -> Fix | None:
    """``node.param=value`` (value a number or a name); None when malformed."""
    target, sep, value = text.partition("=")
    node_id, dot, param = target.rpartition(".")
    if not (sep and dot and node_id and param and value):
        return None
    try:
        return Fix(node_id, param, float(value))
    except ValueError:
        return Fix(node_id, param, value)


def parse_value(text: str) -> float | str:
    """A parameter value given as text: a number when it parses as one, else a name."""
    try:
        return float(text)
    except ValueError:
        return text


def bind_open_agents(tst: ResolvedTst, preferred: str) -> tuple[list[Fix], str]:
    """Fix every open ``P`` (``preferred`` first, else a solution of the network).

    Returns:
        The fixes made, in tree order, and "" or the reason no agent fits a node.
    """
    fixes: list[Fix] = []
    for _, node in tst.tree.walk():
        var = node.params["P"]
        if var in tst.network.values:
            continue
        candidates: list[float | str] = [preferred]
        solution = tst.network.finite.solve()
        if solution.status is SolveStatus.CONSISTENT and var in solution.witness:
            candidates.append(solution.witness[var])
        for value in candidates:
            if tst.set(node.node_id, "P", value).status is FixStatus.OK:
                fixes.append(Fix(node.node_id, "P", value))
                break
        else:
            return fixes, f"no agent can run {node.node_id}"
    return fixes, ""


def involved_agents(tst: ResolvedTst) -> tuple[str, ...]:
    """The agents holding nodes, the root's first (every ``P`` must be bound).

    A foreach's instances may run on any agent of the mission, so a mission with a foreach
    involves them all.
    """
    seen: dict[str, None] = {}
    for _, node in tst.tree.walk():
        seen.setdefault(tst.agent_of(node.node_id), None)
        if node.kind is NodeKind.FOREACH:
            seen.update(dict.fromkeys(tst.agents))
    return tuple(seen)
