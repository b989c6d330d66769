"""``/<agent>/gateway`` (rclpy): the agent layer's only door for speech acts (section 10, Fig. 30).

Inbound, every ``AclMessage`` on ``/<agent>/acl_inbox`` is decoded and authenticated
(:class:`~hdrc3_delegation.authentication.Authenticator`); what fails is logged with its verdict
and dropped (never its key or signature); an authenticated message that is malformed or outside
the protocol is answered ``not-understood``. Accepted acts go to the
:class:`~hdrc3_delegation.contract_net.Contractor`, whose answers are signed and published on each
receiver's inbox. Outbound to the legacy side, the gateway is the platform-specific adapter: the
constraint server prices flights with this agent's ``path_planner`` (``motion_plan_info``), knows
its position from the Data Interface, and a commitment becomes a mission on this agent's
``tst_manager`` (create, execute, abort; progress from ``tst_status``).

The protocol runs in one worker thread that may block on those service calls (bounded waits);
the executor thread only queues messages and stores states.
"""

from __future__ import annotations

import math
import os
import queue
import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions

from hdrc3_base.answer_memory import RESEND_S, ensure_key
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_env import DISCOVERY_RANGE_VAR, DISCOVERY_RANGES, MAX_DOMAIN_ID
from hdrc3_base.ros_runtime import SERVICE_QOS, run_events_node
from hdrc3_delegation.acl import AclMessage, Performative
from hdrc3_delegation.authentication import Authenticator
from hdrc3_delegation.constraint_server import AgentProfile, ConstraintServer
from hdrc3_delegation.contract_net import LANGUAGE, PROTOCOL, Contractor, NodeReport, content
from hdrc3_delegation.keystore import load_keystore
from hdrc3_delegation.messages import from_msg, raw_fields, to_msg
from hdrc3_delegation.task_cost import MotionInfo, TaskCoster, Vec3
from hdrc3_interfaces.msg import AclMessage as AclMessageMsg
from hdrc3_interfaces.msg import HelicopterState, TstNodeStatus, TstReturn
from hdrc3_interfaces.srv import MotionPlanInfo, TstAbort, TstCreate, TstExecute
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import Capability
from hdrc3_tst.node import STATUS_QOS

ACL_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=200,
    durability=DurabilityPolicy.VOLATILE,
)
"""Speech acts: reliable, not latched (a late joiner must not receive old acts)."""
CALL_TIMEOUT_S = 10.0
MATCH_WAIT_S = 2.0
"""Longest wait for a new inbox publisher to match its receiver (an absent one: no match)."""
TICK_S = 0.2
POSITION_WAIT_S = 10.0
"""A speech act that arrives before the aircraft's first Data Interface sample waits up to this
(wall s) for it: the gateway starts before its aircraft publishes a state, and a cfp refused
for "does not know where it is yet" is lost to the auction (seen in a loaded CI run)."""
EARLY_LIMIT = 1_000
"""At most this many speech acts are held so (more are answered at once)."""


def inbox(agent: str) -> str:
    """The topic an agent's gateway receives speech acts on."""
    return f"/{agent}/acl_inbox"


class Outbox:
    """Signs and publishes speech acts on their receivers' inboxes.

    A receiver's publisher is made on the first act to it, and that act waits (bounded) until
    the publisher has matched a subscriber: a volatile writer drops what it publishes before
    discovery matched it, and the act would be lost on a quiet network, not on a partitioned one.
    """

    def __init__(self, node: Node, auth: Authenticator) -> None:
        self.node = node
        self.auth = auth
        self._publishers: dict[str, Any] = {}
        self._lock = threading.Lock()
        self._pause = threading.Event()
        self.sent = 0

    def send(self, messages: Sequence[AclMessage]) -> None:
        """Sign each with the wall clock and publish it to every receiver."""
        with self._lock:
            for msg in messages:
                for receiver in msg.receivers:
                    self._publisher(receiver)
                ros = to_msg(self.auth.sign(msg, time.time()))
                for receiver in msg.receivers:
                    self._publishers[receiver].publish(ros)
                    self.sent += 1

    def connect(self, receivers: Sequence[str]) -> None:
        """Make the publishers to these receivers now and wait (bounded) until they match."""
        with self._lock:
            for receiver in receivers:
                self._publisher(receiver)

    def _publisher(self, receiver: str) -> Any:
        publisher = self._publishers.get(receiver)
        if publisher is None:
            publisher = self.node.create_publisher(AclMessageMsg, inbox(receiver), ACL_QOS)
            self._publishers[receiver] = publisher
            deadline = time.monotonic() + MATCH_WAIT_S
            while not publisher.get_subscription_count() and time.monotonic() < deadline:
                self._pause.wait(0.005)  # discovery runs in DDS threads, not in this one
        return publisher


class Caller:
    """Blocking service calls from a thread other than the executor's, one client per service.

    Clients are kept: a new client would wait for discovery of its server on every call.
    """

    def __init__(self, node: Node) -> None:
        self.node = node
        self._clients: dict[str, Any] = {}

    def call(self, srv_type: Any, name: str, request: Any, timeout: float) -> Any | None:
        """The answer, or None when the service is not there or did not answer in time."""
        client = self._clients.get(name)
        if client is None:
            client = self.node.create_client(srv_type, name, qos_profile=SERVICE_QOS)
            self._clients[name] = client
        deadline = time.monotonic() + timeout
        if not client.wait_for_service(timeout_sec=timeout):
            return None
        ensure_key(request)  # a command: sent again with its key until answered, run once
        while (left := deadline - time.monotonic()) > 0.0:
            # every request here may be sent again (queries, keyed commands): a first answer
            # DDS drops (see hdrc3_base.answer_memory) costs one resend
            done = threading.Event()
            future = client.call_async(request)
            future.add_done_callback(lambda _, answered=done: answered.set())
            if done.wait(min(RESEND_S, left)):
                return future.result()
            client.remove_pending_request(future)
        return None


class RosMotion:
    """Motion-plan information from this agent's path planner node."""

    def __init__(self, caller: Caller, agent: str) -> None:
        self.caller = caller
        self.agent = agent

    def motion(self, start: Vec3, goal: Vec3, speed: float) -> MotionInfo:
        """Ask ``/<agent>/path_planner/motion_plan_info``."""
        request = MotionPlanInfo.Request(speed=speed, timeout=2.0)
        request.start.x, request.start.y, request.start.z = start
        request.goal.x, request.goal.y, request.goal.z = goal
        name = f"/{self.agent}/path_planner/motion_plan_info"
        answer = self.caller.call(MotionPlanInfo, name, request, CALL_TIMEOUT_S)
        if answer is None:
            return MotionInfo(False, reason=f"{name} did not answer")
        return MotionInfo(
            bool(answer.feasible), answer.length, answer.duration, answer.energy, answer.reason
        )


class TstManagerPort:
    """:class:`~hdrc3_delegation.contract_net.ContractorPort` over this agent's TST manager."""

    def __init__(self, node: Node, caller: Caller, agent: str) -> None:
        self.caller = caller
        self.agent = agent
        self.states: dict[str, dict[str, NodeReport]] = {}
        self._lock = threading.Lock()
        node.create_subscription(TstNodeStatus, f"/{agent}/tst_status", self._on_status, STATUS_QOS)

    def _on_status(self, msg: Any) -> None:
        if msg.agent != self.agent:
            return
        with self._lock:
            report = NodeReport(str(msg.state), str(msg.reason))
            self.states.setdefault(str(msg.mission), {})[str(msg.node_id)] = report

    def _call(self, srv_type: Any, service: str, request: Any) -> str:
        name = f"/{self.agent}/tst_manager/{service}"
        answer = self.caller.call(srv_type, name, request, CALL_TIMEOUT_S)
        if answer is None:
            return f"{name} did not answer"
        result = answer.result
        return "" if result.code == TstReturn.TST_OK else f"{result.reason} (code {result.code})"

    def create(self, mission: str, text: str, fixes: Sequence[str]) -> str:
        """Create the replica with the delegator's bindings."""
        request = TstCreate.Request(
            mission=mission, text=text, file="<delegated>", agents=[], fixed=list(fixes)
        )
        return self._call(TstCreate, "create", request)

    def execute(self, mission: str, node_id: str) -> str:
        """Start a node now."""
        # the delegator requests a subtree once every event before it happened (released)
        request = TstExecute.Request(
            mission=mission, node_id=node_id, epoch=math.nan, released=True
        )
        return self._call(TstExecute, "execute", request)

    def abort(self, mission: str, reason: str) -> None:
        """Abort the mission (an unknown mission is already gone)."""
        self._call(TstAbort, "abort", TstAbort.Request(mission=mission, node_id="", reason=reason))

    def node_states(self, mission: str) -> dict[str, NodeReport]:
        """The latest state of each node of the mission held here."""
        with self._lock:
            return dict(self.states.get(mission, {}))


class AclBus:
    """The speech-act side of a gateway on its own DDS domain (Figure 30's agent layer).

    The agent's platform (simulator, control, TST manager) stays on its own domain and on
    loopback; only this context, with its own domain and discovery range, meets other agents.
    The RMW reads the discovery range when a context starts, so it is set for that moment only.
    """

    def __init__(self, agent: str, domain: int, discovery: str) -> None:
        if not 0 <= domain <= MAX_DOMAIN_ID:
            raise ConfigError(f"acl_domain {domain} is outside 0..{MAX_DOMAIN_ID}")
        if discovery and discovery.upper() not in DISCOVERY_RANGES:
            raise ConfigError(f"acl_discovery {discovery!r}: one of {', '.join(DISCOVERY_RANGES)}")
        self.context = Context()
        previous = os.environ.get(DISCOVERY_RANGE_VAR)
        if discovery:
            os.environ[DISCOVERY_RANGE_VAR] = discovery.upper()
        try:
            rclpy.init(
                context=self.context,
                domain_id=domain,
                signal_handler_options=SignalHandlerOptions.NO,
            )
        finally:
            if previous is None:
                os.environ.pop(DISCOVERY_RANGE_VAR, None)
            else:
                os.environ[DISCOVERY_RANGE_VAR] = previous
        self.node = Node("gateway", namespace=f"/{agent}", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self._thread = threading.Thread(target=self._spin, name="acl-bus", daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        while self.context.ok():
            try:
                self.executor.spin_once(timeout_sec=TICK_S)
            except ExternalShutdownException:
                return

    def close(self) -> None:
        """Stop spinning and shut the context down."""
        self.context.try_shutdown()
        self._thread.join(timeout=2.0)
        self.executor.shutdown()


def parse_capabilities(names: Sequence[str]) -> frozenset[Capability]:
    """Capability names (``flight``, ``camera``, ``ptu``, ``hook``) -> values, or ConfigError."""
    try:
        return frozenset(Capability(n.strip()) for n in names if n.strip())
    except ValueError:
        known = ", ".join(c.value for c in Capability)
        raise ConfigError(f"unknown capability in {list(names)}; known: {known}") from None


class GatewayNode(Node):
    """The agent's gateway and contractor."""

    def __init__(self, context: Context) -> None:
        super().__init__("gateway", context=context)
        self.agent = self.get_namespace().strip("/")
        keystore = str(self.declare_parameter("keystore", "").value)
        world = str(self.declare_parameter("world", "revinge").value)
        agents = [str(a) for a in self.declare_parameter("agents", [""]).value if a]
        self.declare_parameter("speed", 1.0)
        caps = self.declare_parameter("capabilities", [c.value for c in Capability]).value
        budget = float(self.declare_parameter("energy_budget", 40e6).value)
        window = float(self.declare_parameter("window", 30.0).value)
        acl_domain = int(self.declare_parameter("acl_domain", -1).value)
        acl_discovery = str(self.declare_parameter("acl_discovery", "").value)
        if not keystore:
            raise ConfigError("parameter keystore is required (an `hdrc3 keys` file)")
        self.auth = Authenticator(self.agent, load_keystore(keystore), window)
        self.frame = frame_from_world(world)
        profile = AgentProfile(self.agent, parse_capabilities(list(caps)), budget)
        caller = Caller(self)
        coster = TaskCoster(RosMotion(caller, self.agent), self.frame.ground_up)
        self.server = ConstraintServer(profile, coster, None)
        port = TstManagerPort(self, caller, self.agent)
        peers = tuple(a for a in agents if a != self.agent)  # a whole mission may go on to them
        self.contractor = Contractor(self.agent, self.server, port, peers=peers)
        self.bus = AclBus(self.agent, acl_domain, acl_discovery) if acl_domain >= 0 else None
        acl_node = self.bus.node if self.bus is not None else self
        self.outbox = Outbox(acl_node, self.auth)
        self.refused = 0
        self._inbox: queue.Queue[Any] = queue.Queue(maxsize=10_000)
        self._early: list[tuple[float, Any]] = []
        """(arrival, message) held until the first Data Interface sample (worker thread only)."""
        acl_node.create_subscription(AclMessageMsg, inbox(self.agent), self._on_acl, ACL_QOS)
        self.create_subscription(
            HelicopterState, f"/{self.agent}/helicopter_state", self._on_state, 10
        )
        self._stop = threading.Event()
        self._worker = threading.Thread(target=self._work, name="gateway", daemon=True)
        self._worker.start()
        caps_text = ",".join(sorted(c.value for c in profile.capabilities))
        where = f"ACL on domain {acl_domain}" if self.bus is not None else "ACL on this domain"
        self.get_logger().info(f"gateway of {self.agent} ready: capabilities {caps_text}; {where}")

    def _on_acl(self, msg: Any) -> None:
        try:
            self._inbox.put_nowait(msg)
        except queue.Full:
            self.refused += 1
            self.get_logger().warning("inbox full: speech act dropped")

    def _on_state(self, msg: Any) -> None:
        position = self.frame.state_enu(msg)
        if position is not None:
            self.server.position = position

    def _work(self) -> None:
        while not self._stop.is_set():
            try:
                msg = self._inbox.get(timeout=TICK_S)
            except queue.Empty:
                msg = None
            if msg is not None and len(self._early) < EARLY_LIMIT:
                self._early.append((time.monotonic(), msg))
            elif msg is not None:  # a flood before the first sample: answered at once
                self._guarded(self._receive, msg)
            for held in self._due():
                self._guarded(self._receive, held)
            self._guarded(self._tick)

    def _tick(self) -> None:
        self.outbox.send(self.contractor.tick(time.time()))

    def _guarded(self, step: Callable[..., None], *args: Any) -> None:
        """One step of the worker; a failure is logged and the gateway answers on."""
        try:
            step(*args)
        except Exception as exc:  # the log says what broke
            self.get_logger().error(f"gateway step failed: {exc!r}")

    def _due(self) -> list[Any]:
        """The held messages to handle now: all once the position is known, else the expired."""
        if self.server.position is not None:
            due, self._early = [m for _, m in self._early], []
            return due
        expired = time.monotonic() - POSITION_WAIT_S
        due = [m for t, m in self._early if t <= expired]
        self._early = [(t, m) for t, m in self._early if t > expired]
        return due

    def _receive(self, ros: Any) -> None:
        now = time.time()
        decoded = from_msg(ros)
        if decoded.message is None:
            check = self.auth.verify_fields(raw_fields(ros), now)
            if check.accepted and decoded.unknown_performative:
                answer = AclMessage(
                    Performative.NOT_UNDERSTOOD,
                    self.agent,
                    (str(ros.sender),),
                    content(reason=decoded.reason),
                    LANGUAGE,
                    protocol=PROTOCOL,
                    conversation_id=str(ros.conversation_id)[:128],
                    in_reply_to=str(ros.reply_with)[:128],
                )
                self.outbox.send([answer])
                return
            self._refuse(str(ros.sender), f"malformed: {decoded.reason}")
            return
        msg = decoded.message
        check = self.auth.verify(msg, now)
        if not check.accepted:
            self._refuse(msg.sender, f"{check.verdict.value}: {check.reason}")
            return
        seen = len(self.contractor.events)
        answers = self.contractor.handle(msg, now)
        self.outbox.send(answers)
        for line in self.contractor.events[seen:]:
            self.get_logger().info(line)
        what = ", ".join(a.performative.value for a in answers) or "no answer"
        where = self.server.position
        at = "unknown" if where is None else "(" + ", ".join(f"{v:.1f}" for v in where) + ")"
        self.get_logger().info(
            f"{msg.performative.value} from {msg.sender} ({msg.conversation_id}): {what} "
            f"in {time.time() - now:.2f} s, at {at}"
        )

    def _refuse(self, sender: str, why: str) -> None:
        self.refused += 1
        self.get_logger().warning(f"refused a speech act from {sender[:40]!r}: {why}")

    def destroy_node(self) -> None:
        """Stop the worker and the ACL bus, then the node."""
        self._stop.set()
        self._worker.join(timeout=2.0)
        if self.bus is not None:
            self.bus.close()
        super().destroy_node()


def main() -> int:
    """Console script ``hdrc3-gateway``: exit 0 on SIGINT/SIGTERM, 2 on bad parameters."""
    return run_events_node(GatewayNode, "hdrc3-gateway")


if __name__ == "__main__":
    sys.exit(main())
