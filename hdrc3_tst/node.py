"""ROS 2 adapter: ``/<agent>/tst_manager``, the TST factory and executors of one agent (§6.3).

Services (``~/create``, ``~/execute``, ``~/abort``, ``~/pause``, ``~/set``, ``~/query``)
answer with a ``TstReturn`` code and reason; nothing a caller sends crashes the node. Node state
changes go to ``/<agent>/tst_status``, execution flags to ``/<agent>/execution_flags`` and every
path a fly-to plans to ``/<agent>/planned_path`` (all recorded). A child held by another agent is
started through that agent's ``execute`` service and followed on its status topic. The engines
tick on a steady 20 Hz timer and whenever a command's state changes, with the sim time of
``/clock``. Fly-to plans its path with ``/<agent>/path_planner`` and replans when that planner's
world model changes (parameter ``path_planner``, default true; false: fly straight).
Monitor violations on ``/<agent>/monitor_violations`` (the execution monitor's, §9.3) are
recovered from in the planned goal node they concern (``engine.on_violation``, §9.3.1); every
recovery step, and the new plan, goes to ``/<agent>/recovery_events`` (recorded).
"""

from __future__ import annotations

import gc
import math
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Header

from hdrc3_base.answer_memory import (
    RESEND_S,
    AnswerMemory,
    keyed,
    new_request_key,
    remembering,
)
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import SERVICE_QOS, run_events_node
from hdrc3_control.path_segment import PathSegment
from hdrc3_interfaces.msg import (
    ExecutionFlag,
    MonitorViolation,
    Path,
    RecoveryEvent,
    TstNodeStatus,
    TstReturn,
)
from hdrc3_interfaces.srv import (
    Plan,
    TstAbort,
    TstCreate,
    TstExecute,
    TstPause,
    TstQuery,
    TstSet,
)
from hdrc3_navigation.messages import segment_to_msg
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import ParamType
from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.distribution import involved_agents, parse_fix, parse_value
from hdrc3_tst.engine import EngineContext, ExecutionEngine, NodeRecord
from hdrc3_tst.goal_planning import PlanHandle, Stocked, stocked_loads
from hdrc3_tst.model import NodeKind, NodeRef, NodeState
from hdrc3_tst.network import FixStatus
from hdrc3_tst.recovery import RecoveryReport, RecoveryStep, Violation
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS
from hdrc3_tst.ros_navigation import RosNavigation
from hdrc3_tst.ros_platform import RosPlatform
from hdrc3_tst.worlds import WorldCache
from sim.world import ObjectKind
from sim.world_loader import load_world

TICK_PERIOD_S = 0.05
PEER_WAIT_S = 30.0
"""Wall seconds a call to another agent's manager may take, finding its service and resending
until answered, before the peer counts as unreachable."""
PLAN_TIMEOUT_S = 60.0
MAX_TEXT = 1_000_000
"""Characters of TST text a create request may carry."""
MAX_MISSIONS = 64
STATUS_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=1000,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
"""Node statuses: late subscribers (a client that starts following) get the recent ones."""
VIOLATION_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=50,
    durability=DurabilityPolicy.VOLATILE,
)
"""Violations: only the ones raised while this manager listens (never a past run's)."""
_STEP_CODES = {
    RecoveryStep.SUSPEND: RecoveryEvent.STEP_SUSPENDED,
    RecoveryStep.BRAKE: RecoveryEvent.STEP_BRAKED,
    RecoveryStep.HOVER: RecoveryEvent.STEP_HOVERING,
    RecoveryStep.APPLY_OPERATOR: RecoveryEvent.STEP_OPERATOR_APPLIED,
    RecoveryStep.REPLAN: RecoveryEvent.STEP_REPLANNED,
    RecoveryStep.GIVE_UP: RecoveryEvent.STEP_GAVE_UP,
    RecoveryStep.IGNORED: RecoveryEvent.STEP_IGNORED,
}
_FIX_CODES = {
    FixStatus.INCONSISTENT: TstReturn.TST_INCONSISTENT,
    FixStatus.UNKNOWN_VARIABLE: TstReturn.TST_UNKNOWN_NODE,
    FixStatus.BAD_VALUE: TstReturn.TST_INVALID,
}


def status_msg(mission: str, record: NodeRecord, parent: str, kind: str, stamp: Any) -> Any:
    """The status message of one node record."""
    return TstNodeStatus(
        header=_header(stamp),
        mission=mission,
        agent=record.agent,
        node_id=record.node_id,
        parent=parent,
        kind=kind,
        state=record.state.value,
        start=record.start,
        end=record.end,
        reason=record.reason,
    )


def _header(stamp: Any) -> Any:
    return Header(stamp=stamp)


class _Sink:
    """The engine's outputs of one mission, as messages and calls."""

    def __init__(self, manager: TstManagerNode, mission: str) -> None:
        self._manager, self._mission = manager, mission

    def status(self, record: NodeRecord) -> None:
        self._manager.publish_status(self._mission, record)

    def flag(
        self, node_id: str, action: str, executing: bool, args: Mapping[str, float | str]
    ) -> None:
        self._manager.publish_flag(self._mission, node_id, action, executing, args)

    def start_remote(self, ref: NodeRef, epoch: float) -> None:
        self._manager.call_remote(self._mission, ref, epoch)

    def abort_remote(self, ref: NodeRef, reason: str) -> None:
        self._manager.abort_remote(self._mission, ref, reason)

    def note(self, node_id: str, text: str) -> None:
        self._manager.get_logger().info(f"{self._mission}/{node_id}: {text}")

    def path(self, node_id: str, segments: tuple[PathSegment, ...]) -> None:
        self._manager.publish_path(segments)

    def recovery(self, report: RecoveryReport) -> None:
        self._manager.publish_recovery(self._mission, report)


class _Planner:
    """The ``task_planner`` service of this agent as the engine's planner port."""

    def __init__(self, node: Node) -> None:
        self._client = node.create_client(Plan, "plan", qos_profile=SERVICE_QOS)

    def request(self, domain: str, problem: str, control: str = "") -> PlanHandle:
        handle = PlanHandle(problem, control=control)
        if not self._client.service_is_ready():
            handle.answer(False, "no task_planner serves this agent (launch it: --nodes ...)")
            return handle
        request = Plan.Request(
            domain=domain, problem=problem, control=control, timeout=PLAN_TIMEOUT_S
        )
        future = self._client.call_async(request)

        def done(f: Any) -> None:
            r = f.result()
            solved = r.status == Plan.Response.STATUS_SOLVED
            handle.answer(solved, r.reason, r.actions, r.agents, r.starts, r.durations)

        future.add_done_callback(done)
        return handle


class TstManagerNode(Node):
    """Holds the missions of one agent and executes its nodes."""

    def __init__(self, context: Context | None = None, namespace: str | None = None) -> None:
        """Create the node (its namespace, from ``__ns`` or ``namespace``, names its agent)."""
        super().__init__("tst_manager", context=context, namespace=namespace)
        self.declare_parameter("world", "revinge")
        self.declare_parameter("agents", [""])
        self.declare_parameter("speed", 1.0)
        self.declare_parameter("sim_time", True)
        self.declare_parameter("path_planner", True)
        if self.get_parameter("sim_time").value:
            self.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        self.agent = self.get_namespace().strip("/")
        if not self.agent or "/" in self.agent:
            raise ConfigError(
                f"tst_manager runs in an agent's namespace, not {self.get_namespace()!r}"
            )
        world = str(self.get_parameter("world").value)
        self.frame = frame_from_world(world)
        self.stock = tuple(
            Stocked(
                o.id, o.mass, o.contents.value if o.contents else "", o.capacity or 0, o.on or ""
            )
            for o in load_world(world).objects
            if o.kind in (ObjectKind.BOX, ObjectKind.CARRIER) and o.mass is not None
        )
        """The world file's boxes and carriers: the loads goal nodes may move."""
        self.platform = RosPlatform(self, self.agent, self.frame, self._tick)
        self.navigation = (
            RosNavigation(self, self.agent, self._tick)
            if self.get_parameter("path_planner").value
            else None
        )
        self.planner = _Planner(self)
        self.worlds = WorldCache()
        """The worlds' facts, loaded once per world file for every mission created here."""
        self.engines: dict[str, ExecutionEngine] = {}
        self._status_pub = self.create_publisher(TstNodeStatus, "tst_status", STATUS_QOS)
        self._flag_pub = self.create_publisher(ExecutionFlag, "execution_flags", STATUS_QOS)
        self._path_pub = self.create_publisher(Path, "planned_path", STATUS_QOS)
        self._recovery_pub = self.create_publisher(RecoveryEvent, "recovery_events", STATUS_QOS)
        self.create_subscription(
            MonitorViolation, "monitor_violations", self._on_violation, VIOLATION_QOS
        )
        self._followed: set[str] = set()
        self._peers: dict[tuple[str, str], Any] = {}
        self._waiting: list[_PeerCall] = []
        self.answers: AnswerMemory[Any] = AnswerMemory()
        for srv_type, name, handler in (
            (TstCreate, "create", self._on_create),
            (TstExecute, "execute", self._on_execute),
            (TstAbort, "abort", self._on_abort),
            (TstPause, "pause", self._on_pause),
            (TstSet, "set", self._on_set),
            (TstQuery, "query", self._on_query),
        ):
            serve = self._guarded(handler)
            if keyed(srv_type.Request):  # the commands: a resend with its key runs once
                serve = remembering(self.answers, name, serve, _refuse)
            self.create_service(srv_type, f"~/{name}", serve, qos_profile=SERVICE_QOS)
        self.create_timer(TICK_PERIOD_S, self._tick, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(f"tst manager of {self.agent} up (world {self.frame.latitude:.5f})")

    # --- time ---------------------------------------------------------------------------
    def sim_now(self) -> float:
        """Sim time in seconds (0 until /clock arrives)."""
        return float(self.get_clock().now().nanoseconds) * 1e-9

    def _tick(self) -> None:
        self._retry_peers()
        now = self.sim_now()
        for engine in self.engines.values():
            engine.tick(now)

    # --- services -----------------------------------------------------------------------
    def _guarded(self, handler: Callable[[Any, Any], Any]) -> Callable[[Any, Any], Any]:
        def serve(request: Any, response: Any) -> Any:
            try:
                return handler(request, response)
            except Exception as exc:  # the node answers every request; the reason says why
                self.get_logger().error(f"request failed: {exc!r}")
                return _answer(response, TstReturn.TST_INVALID, f"internal error: {exc!r}")

        return serve

    def _engine(self, mission: str, response: Any) -> ExecutionEngine | None:
        engine = self.engines.get(mission)
        if engine is None:
            _answer(
                response, TstReturn.TST_UNKNOWN_MISSION, f"{self.agent} has no mission {mission!r}"
            )
        return engine

    def _on_create(self, request: Any, response: Any) -> Any:
        mission = str(request.mission)
        if not mission or len(mission) > 200:
            return _answer(response, TstReturn.TST_INVALID, "mission id must be 1-200 characters")
        if mission in self.engines:
            return _answer(response, TstReturn.TST_BUSY, f"mission {mission!r} exists already")
        if len(self.engines) >= MAX_MISSIONS:
            self._forget_finished()
        if len(request.text) > MAX_TEXT:
            return _answer(
                response, TstReturn.TST_INVALID, f"text longer than {MAX_TEXT} characters"
            )
        try:
            agents = tuple(str(a) for a in request.agents)
            file = str(request.file) or "<create>"
            loaded = load_text(str(request.text), file, agents, self.worlds)
        except ConfigError as exc:
            return _answer(response, TstReturn.TST_INVALID, str(exc))
        if loaded.status is not CheckStatus.OK or loaded.tst is None:
            code = (
                TstReturn.TST_INCONSISTENT
                if loaded.status is CheckStatus.INCONSISTENT
                else TstReturn.TST_INVALID
            )
            reasons = [str(d) for d in loaded.diagnostics]
            return _answer(response, code, reasons[0] if reasons else loaded.status.value, reasons)
        tst = loaded.tst
        world = str(self.get_parameter("world").value)
        if tst.world is not None and tst.world != world:
            return _answer(
                response,
                TstReturn.TST_INVALID,
                f"the mission is for world {tst.world}, not {world}",
            )
        for text in request.fixed:
            fix = parse_fix(str(text))
            if fix is None:
                return _answer(
                    response, TstReturn.TST_INVALID, f"malformed fix {text!r}: node.param=value"
                )
            result = tst.set(fix.node_id, fix.param, fix.value)
            if result.status is not FixStatus.OK:
                return _answer(
                    response, _FIX_CODES[result.status], result.reason, list(result.conflict)
                )
        if "" in involved_agents(tst):
            return _answer(
                response,
                TstReturn.TST_INVALID,
                "every node's agent P must be fixed (see hdrc3_tst.distribution)",
            )
        points = {n: p.coords[0] for n, p in tst.places.items() if p.kind is ParamType.POINT}
        context = EngineContext(
            self.agent,
            self.platform,
            self.planner,
            _Sink(self, mission),
            self.frame,
            RMAX_EXECUTORS,
            self.navigation,
            loads=stocked_loads(self.stock, points),
        )
        engine = ExecutionEngine(mission, tst, context)
        self.engines[mission] = engine
        for agent in involved_agents(tst):
            self._follow(agent)
        response.root = tst.tree.root
        response.nodes = [r.node_id for r in engine.local_records()]
        for record in engine.local_records():
            self.publish_status(mission, record)
        # collect the parse/resolve garbage now, not as a pause while nodes execute
        gc.collect()
        return _answer(response, TstReturn.TST_OK, "")

    def _on_execute(self, request: Any, response: Any) -> Any:
        engine = self._engine(str(request.mission), response)
        if engine is None:
            return response
        node_id = str(request.node_id)
        unknown = engine.materialize(node_id)
        if unknown:
            return _answer(response, TstReturn.TST_UNKNOWN_NODE, unknown)
        now = self.sim_now()
        epoch = float(request.epoch) if math.isfinite(request.epoch) else now
        reason = engine.execute(node_id, epoch, now, bool(request.released))
        if reason:
            return _answer(response, TstReturn.TST_BUSY, reason)
        return _answer(response, TstReturn.TST_OK, "")

    def _subtree(self, request: Any, response: Any) -> tuple[ExecutionEngine, str | None] | None:
        """The mission's engine and the request's subtree root (None: the whole mission).

        None when the mission or the node is unknown; ``response`` then holds the answer.
        """
        engine = self._engine(str(request.mission), response)
        if engine is None:
            return None
        node_id = str(request.node_id) or None
        if node_id is not None and node_id not in engine.records:
            _answer(response, TstReturn.TST_UNKNOWN_NODE, f"no node {node_id!r}")
            return None
        return engine, node_id

    def _on_abort(self, request: Any, response: Any) -> Any:
        found = self._subtree(request, response)
        if found is None:
            return response
        engine, node_id = found
        engine.abort(str(request.reason)[:500] or "aborted", node_id)
        return _answer(response, TstReturn.TST_OK, "")

    def _on_pause(self, request: Any, response: Any) -> Any:
        found = self._subtree(request, response)
        if found is None:
            return response
        engine, node_id = found
        changed = engine.resume(node_id) if request.resume else engine.pause(node_id)
        return _answer(response, TstReturn.TST_OK, f"{len(changed)} node(s)")

    def _on_set(self, request: Any, response: Any) -> Any:
        engine = self._engine(str(request.mission), response)
        if engine is None:
            return response
        status, reason, conflict = engine.set(
            str(request.node_id), str(request.param), parse_value(str(request.value))
        )
        if status is not FixStatus.OK:
            return _answer(response, _FIX_CODES[status], reason, list(conflict))
        return _answer(response, TstReturn.TST_OK, "")

    def _on_query(self, request: Any, response: Any) -> Any:
        engine = self._engine(str(request.mission), response)
        if engine is None:
            return response
        response.nodes = [self._status(engine, r) for r in engine.local_records()]
        return _answer(response, TstReturn.TST_OK, "")

    def _forget_finished(self) -> None:
        for mission in [m for m, e in self.engines.items() if e.finished]:
            del self.engines[mission]

    # --- outputs ------------------------------------------------------------------------
    def _status(self, engine: ExecutionEngine, record: NodeRecord) -> Any:
        node = engine.tst.tree.nodes[record.node_id]
        parent = (
            ""
            if node.parent is None
            else str(NodeRef(engine.records[node.parent.node_id].agent, node.parent.node_id))
        )
        kind = node.action if node.kind is NodeKind.ACTION else node.kind.value
        return status_msg(engine.mission, record, parent, kind, self.get_clock().now().to_msg())

    def publish_status(self, mission: str, record: NodeRecord) -> None:
        """Publish a node's state change."""
        self._status_pub.publish(self._status(self.engines[mission], record))

    def publish_flag(
        self,
        mission: str,
        node_id: str,
        action: str,
        executing: bool,
        args: Mapping[str, float | str],
    ) -> None:
        """Publish an execution flag with the action's arguments (numbers as ``%g``)."""
        self._flag_pub.publish(
            ExecutionFlag(
                header=_header(self.get_clock().now().to_msg()),
                mission=mission,
                agent=self.agent,
                node_id=node_id,
                action=action,
                executing=executing,
                argument_names=list(args),
                argument_values=[v if isinstance(v, str) else f"{v:g}" for v in args.values()],
            )
        )

    def publish_recovery(self, mission: str, report: RecoveryReport) -> None:
        """Publish one recovery step (and a new plan's actions)."""
        self._recovery_pub.publish(
            RecoveryEvent(
                header=_header(self.get_clock().now().to_msg()),
                mission=mission,
                agent=self.agent,
                node_id=report.node_id,
                monitor_id=report.monitor_id,
                recovery=report.recovery,
                step=_STEP_CODES[report.step],
                attempt=report.attempt,
                changes=list(report.changes),
                plan=[label.strip("() ") for label in report.plan],
                reason=report.reason,
            )
        )

    def _on_violation(self, msg: Any) -> None:
        """Recover the planned goal a violation of this agent concerns (§9.3.1)."""
        if msg.kind != MonitorViolation.KIND_VIOLATION or msg.agent != self.agent:
            return
        violation = Violation(
            str(msg.monitor_id),
            str(msg.recovery),
            bool(msg.emergency_brake),
            dict(zip(msg.argument_names, msg.argument_values, strict=False)),
        )
        node_id = str(msg.node_id)
        engines = [e for e in self.engines.values() if not node_id or node_id in e.records]
        if not engines:
            report = RecoveryReport(
                "",
                violation.monitor_id,
                violation.recovery,
                RecoveryStep.IGNORED,
                reason=f"no mission of {self.agent} holds node {node_id!r}",
            )
            self.publish_recovery("", report)
            return
        for engine in engines:
            try:
                engine.on_violation(violation, node_id)
            except Exception as exc:  # a recovery bug must not take the manager down
                self.get_logger().error(f"recovery from {violation.monitor_id} failed: {exc!r}")

    def publish_path(self, segments: tuple[PathSegment, ...]) -> None:
        """Publish a path an executor planned (local ENU of the world's origin)."""
        header = _header(self.get_clock().now().to_msg())
        header.frame_id = "world_enu"
        self._path_pub.publish(Path(header=header, segments=[segment_to_msg(s) for s in segments]))

    # --- other agents -------------------------------------------------------------------
    def _follow(self, agent: str) -> None:
        if agent == self.agent or agent in self._followed:
            return
        self._followed.add(agent)
        self.create_subscription(
            TstNodeStatus, f"/{agent}/tst_status", self._on_peer_status, STATUS_QOS
        )
        # the clients match the peer's services while the mission is being set up
        self._peer(TstExecute, agent, "execute")
        self._peer(TstAbort, agent, "abort")

    def _on_peer_status(self, msg: Any) -> None:
        engine = self.engines.get(str(msg.mission))
        if engine is None:
            return
        try:
            state = NodeState(str(msg.state))
        except ValueError:
            return
        engine.on_remote_status(
            str(msg.node_id), state, float(msg.start), float(msg.end), str(msg.reason)
        )
        engine.tick(self.sim_now())

    def _peer(self, srv_type: Any, agent: str, name: str) -> Any:
        key = (agent, name)
        if key not in self._peers:
            self._peers[key] = self.create_client(
                srv_type, f"/{agent}/tst_manager/{name}", qos_profile=SERVICE_QOS
            )
        return self._peers[key]

    def call_remote(self, mission: str, ref: NodeRef, epoch: float) -> None:
        """Ask another agent's manager to execute a child; a refusal fails the child."""
        engine = self.engines[mission]
        request = TstExecute.Request(mission=mission, node_id=ref.node_id, epoch=epoch)

        def done(f: Any) -> None:
            result = f.result().result
            if result.code != TstReturn.TST_OK:
                engine.on_remote_failure(
                    ref.node_id, f"{ref.agent} refused to execute {ref.node_id}: {result.reason}"
                )
            engine.tick(self.sim_now())

        def unreachable() -> None:
            engine.on_remote_failure(
                ref.node_id, f"no TST manager answers for agent {ref.agent} in {PEER_WAIT_S:g} s"
            )
            engine.tick(self.sim_now())

        self._send(
            _PeerCall(self._peer(TstExecute, ref.agent, "execute"), request, done, unreachable)
        )

    def abort_remote(self, mission: str, ref: NodeRef, reason: str) -> None:
        """Ask another agent's manager to abort a subtree."""
        request = TstAbort.Request(mission=mission, node_id=ref.node_id, reason=reason)
        client = self._peer(TstAbort, ref.agent, "abort")

        def unreachable() -> None:
            self.get_logger().error(f"could not abort {ref}: no TST manager answers")

        self._send(_PeerCall(client, request, lambda _f: None, unreachable))

    def _send(self, call: _PeerCall) -> None:
        """Send the call once the peer's service is matched (``_retry_peers`` sees to it)."""
        call.deadline = time.monotonic() + PEER_WAIT_S
        call.request.request_key = new_request_key()
        self._waiting.append(call)
        self._retry_peers()

    def _retry_peers(self) -> None:
        """Send the waiting calls whose service is matched; again after ``RESEND_S`` unanswered.

        DDS can drop a first answer; the key makes the peer run a call once. Past
        ``PEER_WAIT_S`` without an answer the peer is unreachable.
        """
        now = time.monotonic()
        for call in list(self._waiting):
            if call.future is not None and now - call.sent < RESEND_S:
                continue  # in flight
            if call.future is not None:
                call.client.remove_pending_request(call.future)
                call.future = None
            if now > call.deadline:
                self._waiting.remove(call)
                call.unreachable()
            elif call.client.service_is_ready():
                call.sent, call.future = now, call.client.call_async(call.request)
                call.future.add_done_callback(lambda f, c=call: self._answered(c, f))

    def _answered(self, call: _PeerCall, future: Any) -> None:
        if call.future is future and call in self._waiting:
            self._waiting.remove(call)
            call.done(future)


@dataclass
class _PeerCall:
    """A call to another agent's TST manager, sent until answered or given up."""

    client: Any
    request: Any
    done: Callable[[Any], None]
    unreachable: Callable[[], None]
    deadline: float = 0.0
    """Wall-clock (monotonic) end of all attempts."""
    sent: float = 0.0
    """Wall-clock (monotonic) time of the latest attempt."""
    future: Any = None
    """The latest attempt's answer to come (rclpy's Future is untyped); None between attempts."""


def _refuse(response: Any, reason: str) -> None:
    _answer(response, TstReturn.TST_INVALID, reason)


def _answer(response: Any, code: int, reason: str, conflict: list[str] | None = None) -> Any:
    response.result = TstReturn(code=code, reason=reason, conflict=conflict or [])
    return response


def main() -> int:
    """Console script ``hdrc3-tst-manager``: exit 0 on SIGINT/SIGTERM, 2 on bad parameters."""
    return run_events_node(TstManagerNode, "hdrc3-tst-manager")


if __name__ == "__main__":
    sys.exit(main())
