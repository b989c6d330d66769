"""Fakes for tests and benchmarks: straight-line motion, a TST manager port, an in-memory bus.

:class:`LocalBus` carries signed speech acts between a delegator and contractors in one process
on a caller-driven clock, through the real :class:`Authenticator` of each agent, so protocol
tests exercise signing, verification and replay refusal without ROS. A partitioned agent's
messages (both ways) are held, not lost, and delivered late when the partition heals, as a
reliable DDS writer would once the peer is reachable again.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from hdrc3_delegation.acl import AclMessage, Performative
from hdrc3_delegation.authentication import Authenticator, Check
from hdrc3_delegation.contract_net import Contractor, Delegation, NodeReport
from hdrc3_delegation.task_cost import MotionInfo, Vec3, straight_line
from hdrc3_navigation.cost import FlightModel


@dataclass
class StraightLineMotion:
    """:class:`~hdrc3_delegation.task_cost.MotionCost` without obstacles."""

    model: FlightModel = field(default_factory=FlightModel)
    queries: int = 0

    def motion(self, start: Vec3, goal: Vec3, speed: float) -> MotionInfo:
        """The straight flight's figures."""
        self.queries += 1
        return straight_line(self.model, start, goal, speed)


@dataclass
class FakeManager:
    """A contractor's TST manager: records what it was asked; a test sets node states."""

    refuse_create: str = ""
    created: list[tuple[str, tuple[str, ...]]] = field(default_factory=list)
    executed: list[tuple[str, str]] = field(default_factory=list)
    aborted: list[tuple[str, str]] = field(default_factory=list)
    states: dict[str, dict[str, str]] = field(default_factory=dict)

    def create(self, mission: str, text: str, fixes: Sequence[str]) -> str:
        """Accept (or refuse with ``refuse_create``)."""
        if self.refuse_create:
            return self.refuse_create
        self.created.append((mission, tuple(fixes)))
        return ""

    def execute(self, mission: str, node_id: str) -> str:
        """Record the start."""
        self.executed.append((mission, node_id))
        return ""

    def abort(self, mission: str, reason: str) -> None:
        """Record the abort."""
        self.aborted.append((mission, reason))

    def node_states(self, mission: str) -> dict[str, NodeReport]:
        """What the test set (a failed node's reason: "set by the test")."""
        return {
            node: NodeReport(state, "set by the test" if state == "failed" else "")
            for node, state in self.states.get(mission, {}).items()
        }


@dataclass
class LocalBus:
    """Signed delivery between one delegator and contractors, on the caller's clock."""

    delegator_auth: Authenticator
    contractors: dict[str, tuple[Contractor, Authenticator]]
    now: float = 0.0
    partitioned: set[str] = field(default_factory=set)
    held: list[tuple[AclMessage, str]] = field(default_factory=list)
    log: list[tuple[AclMessage, str, Check]] = field(default_factory=list)
    """Every delivery: message, receiver, the receiver's verdict."""
    delegation: Delegation | None = None
    cut: tuple[Performative, str, int] | None = None
    """(performative, agent, n): partition the agent just before the (n+1)-th such message."""

    def send(self, sender: Authenticator, messages: Sequence[AclMessage]) -> None:
        """Sign and deliver every message (held across a partition), then their answers."""
        self.route([sender.sign(m, self.now) for m in messages])

    def route(self, signed: Sequence[AclMessage]) -> None:
        """Deliver signed messages to each receiver, and the answers, until all is quiet."""
        queue = [(m, r) for m in signed for r in m.receivers]
        while queue:
            msg, receiver = queue.pop(0)
            if self.cut and msg.performative is self.cut[0] and self.cut[1] == receiver:
                performative, agent, passing = self.cut
                self.cut = (performative, agent, passing - 1) if passing else None
                if not passing:
                    self.partitioned.add(receiver)
            if {msg.sender, receiver} & self.partitioned:
                self.held.append((msg, receiver))
                continue
            queue += [(a, r) for a in self._deliver(msg, receiver) for r in a.receivers]

    def heal(self) -> None:
        """End every partition and deliver what was held (late)."""
        self.partitioned.clear()
        held, self.held = self.held, []
        for msg, receiver in held:
            self.route([a for a in self._deliver(msg, receiver)])

    def tick(self, now: float) -> None:
        """Advance the clock and let every party act on its deadlines."""
        self.now = now
        if self.delegation is not None:
            self.send(self.delegator_auth, self.delegation.tick(now))
        for contractor, auth in self.contractors.values():
            self.send(auth, contractor.tick(now))

    def _deliver(self, msg: AclMessage, receiver: str) -> list[AclMessage]:
        if receiver == self.delegator_auth.agent and self.delegation is not None:
            auth = self.delegator_auth
            check = auth.verify(msg, self.now)
            answers = self.delegation.handle(msg, self.now) if check.accepted else []
        elif receiver in self.contractors:
            contractor, auth = self.contractors[receiver]
            check = auth.verify(msg, self.now)
            answers = contractor.handle(msg, self.now) if check.accepted else []
        else:
            return []
        self.log.append((msg, receiver, check))
        return [auth.sign(a, self.now) for a in answers]
