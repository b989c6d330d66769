"""A client of the TST managers: create a mission on every agent it names, run, abort, set.

Used by ``hdrc3 tst`` and the integration tests (and, later, by the mission and delegation
layers). Creating a mission resolves it here first, so bad input is answered before anything is
sent; open agents are bound (``distribution.bind_open_agents``) and the same text with the same
fixes goes to each involved agent's ``tst_manager``. Statuses of every involved agent are
followed from before the first create on, so none is missed. Waits are bounded (wall clock).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from rclpy.node import Node

from hdrc3_base.answer_memory import RESEND_S, ensure_key
from hdrc3_base.ros_runtime import SERVICE_QOS, SERVICE_WAIT_S, RosProcess
from hdrc3_interfaces.msg import TstNodeStatus, TstReturn
from hdrc3_interfaces.srv import TstAbort, TstCreate, TstExecute, TstPause, TstSet
from hdrc3_tst.check import CheckResult, CheckStatus, load_text
from hdrc3_tst.distribution import bind_open_agents, involved_agents
from hdrc3_tst.model import NodeState
from hdrc3_tst.node import STATUS_QOS

CALL_TIMEOUT_S = 30.0
UNANSWERED = 255
"""Code of a reply that never came (not a ``TstReturn`` code)."""


@dataclass(frozen=True)
class Reply:
    """One manager's answer: its agent, ``TstReturn`` code, reason and conflicting constraints."""

    agent: str
    code: int
    reason: str = ""
    conflict: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """The manager said TST_OK."""
        return bool(self.code == TstReturn.TST_OK)


@dataclass(frozen=True)
class Created:
    """The outcome of creating a mission: the local check, and each involved agent's answer."""

    check: CheckResult
    root: str = ""
    root_agent: str = ""
    involved: tuple[str, ...] = ()
    replies: tuple[Reply, ...] = ()
    fixed: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """Valid, and every involved manager created it."""
        return self.check.status is CheckStatus.OK and all(r.ok for r in self.replies)


@dataclass
class TstClient:
    """Service calls to the TST managers and the statuses they publish."""

    process: RosProcess
    node: Node = field(init=False)
    statuses: list[Any] = field(default_factory=list)
    """Every ``TstNodeStatus`` received, in arrival order."""
    on_status: Callable[[Any], None] | None = None
    _followed: set[str] = field(default_factory=set)

    def __post_init__(self) -> None:
        """Create the client's node."""
        self.node = Node(f"hdrc3_tst_client_{os.getpid()}", context=self.process.context)
        self.process.add_node(self.node)

    def follow(self, agent: str) -> None:
        """Receive ``agent``'s node statuses."""
        if agent in self._followed:
            return
        self._followed.add(agent)
        self.node.create_subscription(
            TstNodeStatus, f"/{agent}/tst_status", self._on_status, STATUS_QOS
        )

    def _on_status(self, msg: Any) -> None:
        self.statuses.append(msg)
        if self.on_status is not None:
            self.on_status(msg)

    def _call(self, agent: str, srv_type: Any, name: str, request: Any) -> Reply:
        client = self.node.create_client(
            srv_type, f"/{agent}/tst_manager/{name}", qos_profile=SERVICE_QOS
        )
        try:
            if not self.process.spin_until(client.service_is_ready, SERVICE_WAIT_S):
                return Reply(
                    agent,
                    TstReturn.TST_UNKNOWN_AGENT,
                    f"no TST manager answers for agent {agent!r} (/{agent}/tst_manager/{name})",
                )
            ensure_key(request)  # a command: sent again with its key until answered, run once
            answer = self.process.first_answer(client, request, CALL_TIMEOUT_S, RESEND_S)
            if answer is None:
                return Reply(agent, UNANSWERED, f"{agent}: no answer in {CALL_TIMEOUT_S:g} s")
            result = answer.result
            return Reply(agent, int(result.code), str(result.reason), tuple(result.conflict))
        finally:
            self.node.destroy_client(client)

    # --- the services -------------------------------------------------------------------
    def create(
        self, mission: str, text: str, file: str = "<mission>", agents: tuple[str, ...] = ()
    ) -> Created:
        """Check the mission, bind open agents, and create it on every involved manager."""
        check = load_text(text, file, agents)
        if check.status is not CheckStatus.OK or check.tst is None:
            return Created(check)
        tst = check.tst
        preferred = agents[0] if agents else (tst.agents[0] if tst.agents else "")
        fixes, reason = bind_open_agents(tst, preferred)
        if reason:
            return Created(check, replies=(Reply("", TstReturn.TST_INVALID, reason),))
        involved = involved_agents(tst)
        for agent in involved:
            self.follow(agent)
        fixed = tuple(str(f) for f in fixes)
        request = TstCreate.Request(
            mission=mission, text=text, file=file, agents=list(agents), fixed=list(fixed)
        )
        replies = tuple(self._call(a, TstCreate, "create", request) for a in involved)
        root = tst.tree.root
        return Created(check, root, tst.agent_of(root), involved, replies, fixed)

    def execute(self, mission: str, agent: str, node_id: str) -> Reply:
        """Start ``node_id`` on ``agent`` (the mission's epoch is now)."""
        request = TstExecute.Request(mission=mission, node_id=node_id, epoch=float("nan"))
        return self._call(agent, TstExecute, "execute", request)

    def abort(self, mission: str, agents: tuple[str, ...], reason: str) -> list[Reply]:
        """Abort the mission on every agent."""
        request = TstAbort.Request(mission=mission, node_id="", reason=reason)
        return [self._call(a, TstAbort, "abort", request) for a in agents]

    def pause(self, mission: str, agents: tuple[str, ...], resume: bool) -> list[Reply]:
        """Pause (or resume) the mission's running actions on every agent."""
        request = TstPause.Request(mission=mission, node_id="", resume=resume)
        return [self._call(a, TstPause, "pause", request) for a in agents]

    def set(
        self, mission: str, agents: tuple[str, ...], node_id: str, param: str, value: str
    ) -> list[Reply]:
        """Fix a parameter on every agent's replica."""
        request = TstSet.Request(mission=mission, node_id=node_id, param=param, value=value)
        return [self._call(a, TstSet, "set", request) for a in agents]

    # --- following ----------------------------------------------------------------------
    def latest(self, mission: str) -> dict[str, Any]:
        """The newest status of every node of ``mission`` seen so far."""
        out: dict[str, Any] = {}
        for msg in self.statuses:
            if msg.mission == mission:
                out[msg.node_id] = msg
        return out

    def finished(self, mission: str, node_id: str) -> Any | None:
        """The terminal status of a node, once it has one."""
        msg = self.latest(mission).get(node_id)
        return msg if msg is not None and NodeState(msg.state).finished else None
