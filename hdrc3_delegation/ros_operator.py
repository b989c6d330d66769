"""The delegating side over ROS (rclpy): an operator or agent runs a :class:`Delegation`.

:class:`RosDelegator` owns a node in the delegator's namespace that reads its
``/<agent>/acl_inbox``, authenticates every act (refusals are counted and reported with their
verdict), feeds the delegation and publishes its signed acts through the same
:class:`~hdrc3_delegation.node.Outbox` as the gateways. ``hdrc3 delegate``, the integration
tests and ``bench/delegation.py`` use it.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import Any

from rclpy.node import Node

from hdrc3_base.ros_runtime import RosProcess
from hdrc3_delegation.authentication import Authenticator
from hdrc3_delegation.contract_net import Delegation
from hdrc3_delegation.messages import from_msg
from hdrc3_delegation.node import ACL_QOS, TICK_S, Outbox, inbox
from hdrc3_interfaces.msg import AclMessage as AclMessageMsg


class RosDelegator:
    """Runs delegations for one agent (``auth.agent``) in a :class:`RosProcess`."""

    def __init__(self, process: RosProcess, auth: Authenticator) -> None:
        self.process = process
        self.auth = auth
        self.node = Node(
            f"delegator_{os.getpid()}", namespace=f"/{auth.agent}", context=process.context
        )
        process.add_node(self.node)
        self.outbox = Outbox(self.node, auth)
        self.received: list[Any] = []
        """Acts received and not yet handled by :meth:`run`."""
        self.received_count = 0
        self.refusals: list[str] = []
        self.node.create_subscription(AclMessageMsg, inbox(auth.agent), self._on_acl, ACL_QOS)

    def _on_acl(self, msg: Any) -> None:
        self.received.append(msg)
        self.received_count += 1

    def wait_for_gateways(self, agents: tuple[str, ...], timeout: float) -> tuple[str, ...]:
        """Wait until every agent's gateway listens on its inbox; the agents still missing."""

        def missing() -> tuple[str, ...]:
            return tuple(a for a in agents if not self.node.count_subscribers(inbox(a)))

        self.process.spin_until(lambda: not missing(), timeout)
        self.outbox.connect([a for a in agents if a not in missing()])
        return missing()

    def run(
        self,
        delegation: Delegation,
        timeout: float,
        on_event: Callable[[str], None] = lambda line: None,
        until: Callable[[Delegation], bool] = lambda d: d.phase.finished,
    ) -> Delegation:
        """Drive ``delegation`` until ``until`` (default: done or failed) or ``timeout`` wall s."""
        shown = 0

        def step() -> bool:
            nonlocal shown
            now = time.time()
            while self.received:
                self._receive(delegation, self.received.pop(0), now)
            self.outbox.send(delegation.tick(now))
            for line in delegation.events[shown:]:
                on_event(line)
            shown = len(delegation.events)
            return until(delegation)

        self.outbox.send(delegation.start(time.time()))
        self.process.spin_until(step, timeout, step_s=TICK_S)
        return delegation

    def _receive(self, delegation: Delegation, ros: Any, now: float) -> None:
        decoded = from_msg(ros)
        if decoded.message is None:
            self.refusals.append(f"malformed from {str(ros.sender)[:40]!r}: {decoded.reason}")
            return
        check = self.auth.verify(decoded.message, now)
        if not check.accepted:
            self.refusals.append(
                f"{check.verdict.value} from {decoded.message.sender}: {check.reason}"
            )
            return
        self.outbox.send(delegation.handle(decoded.message, now))
