"""The TST model: nodes, their interface and references across agents (section 6.3.1).

A tree is a distributed data structure: a node is named by a :class:`NodeRef` (agent + node
id), and parents and children are references, so a subtree may live in another agent's TST
manager. Every node's interface holds the agent ``P``, the times ``TS``/``TE`` and its
type-specific parameters; each maps to a variable of the constraint network.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass, field

from hdrc3_deliberative.mission_syntax import SourcePos
from hdrc3_tst.errors import TstError
from hdrc3_tst.syntax import Condition

UNASSIGNED = ""
"""Agent of a reference whose node's ``P`` is still open."""


@dataclass(frozen=True)
class NodeRef:
    """Where a node lives: the agent whose TST manager holds it, and its id there."""

    agent: str
    node_id: str

    def __str__(self) -> str:
        return f"{self.agent or '?'}/{self.node_id}"


class NodeKind(enum.Enum):
    """Node types of Figure 16."""

    SEQUENCE = "sequence"
    CONCURRENT = "concurrent"
    IF = "if"
    WHILE = "while"
    FOREACH = "foreach"
    CALL = "call"
    GOAL = "goal"
    ACTION = "action"


EXPANDS_AS: dict[NodeKind, tuple[NodeKind, ...]] = {
    NodeKind.GOAL: (NodeKind.SEQUENCE, NodeKind.CONCURRENT),
    NodeKind.FOREACH: (NodeKind.CONCURRENT,),
}
"""The node kinds that get their children at run time, and what they may then act as."""


class NodeState(enum.Enum):
    """Lifecycle of a node (the executors' framework moves it; the model only stores it)."""

    CREATED = "created"
    RUNNING = "running"
    PAUSED = "paused"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    ABORTED = "aborted"

    @property
    def finished(self) -> bool:
        """Succeeded, failed or aborted."""
        return self in (NodeState.SUCCEEDED, NodeState.FAILED, NodeState.ABORTED)


class Outcome(enum.Enum):
    """How an executed node ended."""

    SUCCESS = "success"
    FAILURE = "failure"
    ABORTED = "aborted"


INTERFACE = ("P", "TS", "TE")
"""Parameters every node has: agent, start time, end time."""


@dataclass
class Node:
    """One node: its type, its parameters (name -> network variable) and its links."""

    node_id: str
    kind: NodeKind
    params: dict[str, str]
    """``P``, ``TS``, ``TE`` and the type-specific parameters -> constraint variables."""
    parent: NodeRef | None = None
    children: list[NodeRef] = field(default_factory=list)
    action: str = ""
    """Action type (ACTION), goal name (GOAL) or called TST (CALL)."""
    goal_args: tuple[str, ...] = ()
    condition: Condition | None = None
    """The query of IF/WHILE/FOREACH nodes."""
    loop_vars: tuple[str, ...] = ()
    """FOREACH: the variables each answer binds."""
    template: str = ""
    """FOREACH: the root of its body as written (never executed; each answer instantiates it)."""
    expanded_as: NodeKind | None = None
    """A GOAL node after planning, or a FOREACH node after its query, acts as this node kind."""
    state: NodeState = NodeState.CREATED
    pos: SourcePos = field(default_factory=SourcePos)

    @property
    def acts_as(self) -> NodeKind:
        """The control semantics it executes with (an expanded goal as its expansion)."""
        return self.expanded_as or self.kind


def timepoints(nodes: Iterable[Node]) -> dict[str, tuple[str, str]]:
    """Each start and end variable of ``nodes``: its node's id and ``TS`` or ``TE``."""
    return {n.params[p]: (n.node_id, p) for n in nodes for p in ("TS", "TE")}


@dataclass
class TaskTree:
    """The nodes of one mission, by id, and its root."""

    root: str
    nodes: dict[str, Node] = field(default_factory=dict)

    def node(self, node_id: str) -> Node:
        """The node called ``node_id`` (misuse: an unknown id raises :class:`TstError`)."""
        try:
            return self.nodes[node_id]
        except KeyError:
            raise TstError(f"no node {node_id!r} in this tree") from None

    def ref(self, node_id: str, agent: str) -> NodeRef:
        """A reference to one of this tree's nodes held by ``agent``."""
        return NodeRef(agent, self.node(node_id).node_id)

    def walk(self, node_id: str | None = None) -> list[tuple[int, Node]]:
        """(depth, node) depth-first from ``node_id`` (default: the root), children in order."""
        out: list[tuple[int, Node]] = []
        stack = [(0, self.node(node_id or self.root))]
        while stack:
            depth, node = stack.pop()
            out.append((depth, node))
            # Children held by another agent's manager are not in this tree.
            stack.extend(
                (depth + 1, self.nodes[c.node_id])
                for c in reversed(node.children)
                if c.node_id in self.nodes
            )
        return out

    def add(self, node: Node) -> None:
        """Add a node (misuse: a duplicate id raises)."""
        if node.node_id in self.nodes:
            raise TstError(f"node {node.node_id!r} already exists")
        self.nodes[node.node_id] = node

    def expand(self, node_id: str, mode: NodeKind, children: list[NodeRef]) -> None:
        """Give a node the children it makes at run time; it then acts as ``mode`` (§6.3).

        A goal node gets a plan's subtree (as a sequence or a concurrent node), a foreach node
        one instance per answer (as a concurrent node). The children must already be nodes of
        this tree or references to another agent's.
        """
        node = self.node(node_id)
        modes = EXPANDS_AS.get(node.kind)
        if modes is None:
            raise TstError(f"{node_id} is a {node.kind.value} node: only goal and foreach expand")
        if node.expanded_as is not None:
            raise TstError(f"{node.kind.value} {node_id} is already expanded")
        if mode not in modes:
            names = " or ".join(m.value for m in modes)
            raise TstError(f"a {node.kind.value} expands as {names}, not {mode.value}")
        node.expanded_as = mode
        node.children = list(children)

    def collapse(self, node_id: str) -> None:
        """Take a goal node's plan away so it is planned again (recovery, §9.3.1).

        The old plan's nodes stay in the tree (their records are the history); the goal acts
        as a goal again and expands with the next plan.
        """
        node = self.node(node_id)
        if node.kind is not NodeKind.GOAL:
            raise TstError(f"{node_id} is a {node.kind.value} node: only goals are replanned")
        node.expanded_as = None
        node.children = []
