"""Executing the nodes one agent's TST manager holds (sections 6.3, 9.4): the control semantics.

The engine owns every node's lifecycle: it starts a node no earlier than its earliest start,
fixes its T_S and T_E in the constraint network when it starts and ends (so later windows
follow what happened, and a start or end the constraints forbid fails the node with the
conflicting constraints), binds open parameters when an action starts, fails a node whose latest
end passes, and applies the control semantics:

- **sequence** runs its children in order and fails with the first that fails;
- **concurrent** starts all children and succeeds when all have; when one fails, the others are
  aborted and the node fails;
- **if** asks its query once and runs the chosen branch; **while** asks before every round;
  **foreach** asks once for every binding of its variables, resolves one instance of its body
  per answer (``ResolvedTst.expand_foreach``) and then acts as a concurrent node over them (no
  answer: it succeeds); queries go to ``queries.py``;
- **call** runs the instantiated library tree; **goal** asks the planner, attaches the plan's
  nodes and then acts as a sequence. A monitor violation during a goal's plan
  (:meth:`ExecutionEngine.on_violation`) is recovered from as ``recovery.py`` decides (§9.3.1):
  the running step is aborted, the aircraft brakes if asked (FCL ``emergency_brake``) and hovers
  (the PFC hovers between commands), the new problem is planned once the brake has ended, and
  the goal continues with the new plan's nodes, or fails when recovery gives up. A planned step
  that fails on its own is recovered the same way with the ``step-failed`` operator when the
  recovery operators have one (the packaged ones do: plan again, twice at most).

A child on another agent is started through :class:`EngineSink.start_remote` and followed
through :meth:`ExecutionEngine.on_remote_status`. ``tick`` is called with the sim time; the
engine never blocks and never reads a wall clock.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Protocol

from hdrc3_control.path_segment import PathSegment
from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.hook_api import HookAction
from hdrc3_tst.actions import ACTIONS, ParamSpec, ParamType
from hdrc3_tst.executor import ActionContext, ActionExecutor, Progress, Status, Stepper
from hdrc3_tst.finite import SolveStatus
from hdrc3_tst.goal_planning import (
    GoalPlannerPort,
    GoalProblem,
    Load,
    PlanHandle,
    PlannedStep,
    StepsStatus,
    domain_text,
    goal_problem,
    here,
    plan_steps,
)
from hdrc3_tst.model import Node, NodeKind, NodeRef, NodeState, timepoints
from hdrc3_tst.navigation_port import NavigationPort
from hdrc3_tst.network import FixStatus
from hdrc3_tst.platform_port import LET_GO, Command, PlatformPort
from hdrc3_tst.queries import Answer, QueryDomain, ask, ask_all
from hdrc3_tst.recovery import (
    STEP_FAILED,
    Recovery,
    RecoveryReport,
    RecoveryStatus,
    RecoveryStep,
    Violation,
    default_recovery,
    progressed,
)
from hdrc3_tst.recovery_spec import RecoverySpec
from hdrc3_tst.resolver import InstanceStatus, Place, ResolvedTst
from hdrc3_tst.stn import TICKS_PER_S, Inconsistent

TICK_TOLERANCE_S = 1.0
"""Mission seconds a start or end may be seen after its latest time (one tick of the manager
at high sim speeds); it is then recorded at that latest time."""
SAME_TICK_S = 1e-6
"""Mission seconds an end may be seen before its earliest time when both fall in one tick: the
nanoseconds that strict bounds (``TS < TE``) add up to along a chain of ends seen at once."""


@dataclass
class NodeRecord:
    """What happened to one node: its state, mission times and reason."""

    node_id: str
    agent: str
    state: NodeState = NodeState.CREATED
    start: float = math.nan
    end: float = math.nan
    reason: str = ""
    released: bool = False
    """Its requester saw every event before its start happen: other agents' are not waited for."""
    # runtime of the control semantics
    stepper: Stepper | None = None
    cursor: int = 0
    started_children: set[str] = field(default_factory=set)
    chosen: str = ""
    rounds: int = 0
    plan: PlanHandle | None = None
    problem: GoalProblem | None = None
    """A goal node's planning problem (what recovery changes and plans again)."""
    steps: tuple[PlannedStep, ...] = ()
    """A goal node's current plan, as its children run it."""
    plans: int = 0
    """Plans a goal node has had (recovery plans again)."""
    recovery: Recovery | None = None
    """A goal node's failure counts per fault."""
    brake: Command | None = None
    """The emergency brake a recovering goal waits for before it plans."""
    letting_go: list[tuple[HookAction, float]] = field(default_factory=list)
    """Hook commands a recovering goal sends, one after the other, before it plans (let go of
    a load that did not lift, wind the hook in)."""
    hook: Command | None = None
    """The last of those sent."""
    recovering: Violation | None = None
    """The violation a goal node is planning again for."""
    remote_requested: bool = False
    memory: dict[str, float] = field(default_factory=dict)
    """An action executor's memory across pause and resume (``ActionContext.memory``)."""


class EngineSink(Protocol):
    """Where the engine's outputs go (the node publishes and calls; tests record)."""

    def status(self, record: NodeRecord) -> None:
        """A node this agent holds changed state."""

    def flag(
        self, node_id: str, action: str, executing: bool, args: Mapping[str, float | str]
    ) -> None:
        """An action's executor started (True) or stopped (False), with the action's arguments."""

    def start_remote(self, ref: NodeRef, epoch: float) -> None:
        """Ask ``ref.agent``'s manager to execute ``ref.node_id``."""

    def abort_remote(self, ref: NodeRef, reason: str) -> None:
        """Ask ``ref.agent``'s manager to abort ``ref.node_id``."""

    def note(self, node_id: str, text: str) -> None:
        """An executor of a node said what it did (a plan, a replan)."""

    def path(self, node_id: str, segments: tuple[PathSegment, ...]) -> None:
        """An executor of a node planned a path (it flies it from now on)."""

    def recovery(self, report: RecoveryReport) -> None:
        """A step of a recovery from a monitor violation was carried out (§9.3.1)."""


@dataclass
class EngineContext:
    """The ports one agent's engine works with."""

    agent: str
    platform: PlatformPort
    planner: GoalPlannerPort
    sink: EngineSink
    frame: WorldFrame
    executors: Mapping[str, type[ActionExecutor]]
    navigation: NavigationPort | None = None
    """The agent's path planner for flight executors (None: straight flights)."""
    recovery: RecoverySpec = field(default_factory=default_recovery)
    """The recovery operators monitor formulas name."""
    loads: tuple[Load, ...] = ()
    """The boxes and carriers goal nodes may move, at locations among the mission's points."""


class ExecutionEngine:
    """One mission's nodes on one agent."""

    def __init__(self, mission: str, tst: ResolvedTst, ctx: EngineContext) -> None:
        """Hold every node of ``tst`` whose agent is ``ctx.agent``; follow the others."""
        self.mission = mission
        self.tst = tst
        self.ctx = ctx
        self.epoch = math.nan
        self.now = 0.0
        self.records: dict[str, NodeRecord] = {
            n.node_id: NodeRecord(n.node_id, tst.agent_of(n.node_id))
            for n in tst.tree.nodes.values()
        }
        self._running: list[str] = []
        self._advancing: set[str] = set()
        self._stopping: set[str] = set()
        """Nodes whose subtree is being aborted: their children's endings do not advance them."""
        self.loads = ctx.loads
        """Where the boxes and carriers are as this agent's planned goals left them: a goal
        planned later starts from there, not from the world file's stock."""
        self.lift_capacity: float | None = None
        """kg this agent's helicopter was found to lift at most (a recovery lowered it); goal
        nodes planned later start from it (None: the domain's assumption)."""

    # --- queries ------------------------------------------------------------------------
    def holds(self, node_id: str) -> bool:
        """True if this agent's manager holds the node."""
        rec = self.records.get(node_id)
        return rec is not None and rec.agent == self.ctx.agent

    def local_records(self) -> list[NodeRecord]:
        """The records of the nodes this agent holds, in tree order."""
        order = [n.node_id for _, n in self.tst.tree.walk()]
        order += [i for i in self.records if i not in order]
        return [self.records[i] for i in order if self.holds(i)]

    @property
    def finished(self) -> bool:
        """No node of this agent runs."""
        return not self._running

    # --- commands -----------------------------------------------------------------------
    def execute(self, node_id: str, epoch: float, now: float, released: bool = False) -> str:
        """Start a node this agent holds; "" or why not.

        ``released``: the requester (a delegator, which hears every agent) saw every start and
        end the constraints put before the node's start happen; this replica, which may not hear
        the other agents (another host), does not wait for their events before it.
        """
        reason = self.materialize(node_id)
        if reason:
            return reason
        if not self.holds(node_id):
            return f"{self.ctx.agent} does not hold node {node_id!r}"
        rec = self.records[node_id]
        if rec.state is not NodeState.CREATED:
            return f"node {node_id} is {rec.state.value}"
        if math.isnan(self.epoch):
            self.epoch = epoch
        self.now = now - self.epoch
        rec.state = NodeState.RUNNING  # waits for its earliest start inside _advance
        rec.start = math.nan
        rec.released = released
        self._running.append(node_id)
        self.tick(now)
        return ""

    def materialize(self, node_id: str) -> str:
        """Make sure a node exists; "" or why not.

        An instance of a foreach that another agent expanded is resolved from its id
        (``f[uav1]/body``).
        """
        if node_id in self.records:
            return ""
        instance = self.tst.materialize(node_id)
        self._record(instance.nodes)
        return "" if instance.status is InstanceStatus.OK else instance.reason

    def abort(self, reason: str, node_id: str | None = None) -> list[str]:
        """Abort running nodes (all, or the subtree of ``node_id``); the ids aborted."""
        targets = [n for n in self._running if node_id is None or self._under(n, node_id)]
        for nid in targets:
            self._abort(nid, reason)
        return targets

    def pause(self, node_id: str | None = None) -> list[str]:
        """Pause running actions (all, or under ``node_id``): their commands end; the ids."""
        paused = []
        for nid in list(self._running):
            rec = self.records[nid]
            if rec.stepper is None or (node_id is not None and not self._under(nid, node_id)):
                continue
            self._stop_commands(nid, "paused")
            rec.stepper, rec.state = None, NodeState.PAUSED
            self.ctx.sink.status(rec)
            paused.append(nid)
        return paused

    def resume(self, node_id: str | None = None) -> list[str]:
        """Start paused actions again (all, or under ``node_id``); the ids resumed."""
        resumed = []
        for nid in list(self._running):
            rec, node = self.records[nid], self.tst.tree.nodes[nid]
            if rec.state is not NodeState.PAUSED:
                continue
            if node_id is not None and not self._under(nid, node_id):
                continue
            rec.state = NodeState.RUNNING
            reason = self._start_action(node, rec, rec.start)
            if reason:
                self._finish(rec, NodeState.FAILED, reason)
            else:
                self.ctx.sink.status(rec)
            resumed.append(nid)
        return resumed

    def set(
        self, node_id: str, param: str, value: float | str
    ) -> tuple[FixStatus, str, tuple[str, ...]]:
        """Mixed initiative: fix a parameter (refused when it conflicts or already passed)."""
        rec = self.records.get(node_id)
        if rec is not None and rec.state.finished:
            return FixStatus.BAD_VALUE, f"node {node_id} has already {rec.state.value}", ()
        result = self.tst.set(node_id, param, value)
        return result.status, result.reason, result.conflict

    def on_remote_status(
        self, node_id: str, state: NodeState, start: float, end: float, reason: str
    ) -> None:
        """A node another agent holds changed state (its manager's status topic)."""
        rec = self.records.get(node_id)
        if rec is None or self.holds(node_id):
            return
        rec.state, rec.reason = state, reason
        node = self.tst.tree.nodes.get(node_id)
        # The holder is authoritative: its times go into this replica of the network when
        # they fit (a replica's own fixes may differ by a tick; then the holder's are kept).
        for param, t in (("TS", start), ("TE", end)):
            if (
                node is not None
                and math.isfinite(t)
                and node.params[param] not in self.tst.network.values
            ):
                self.tst.network.fix(
                    node.params[param], t, f"{node_id}.{param} reported by {rec.agent}"
                )
        rec.start, rec.end = start, end

    def on_remote_failure(self, node_id: str, reason: str) -> None:
        """The other agent's manager could not be asked to execute a child."""
        rec = self.records.get(node_id)
        if rec is not None and not rec.state.finished:
            rec.state, rec.reason = NodeState.FAILED, reason

    # --- the loop -----------------------------------------------------------------------
    def tick(self, now: float) -> None:
        """Advance every running node to sim time ``now``."""
        if math.isnan(self.epoch):
            return
        self.now = now - self.epoch
        for node_id in list(self._running):
            rec = self.records[node_id]
            if rec.state is NodeState.RUNNING:
                self._advance(node_id)
            elif rec.state is NodeState.PAUSED:
                self._check_deadline(node_id)

    def _advance(self, node_id: str) -> None:
        # a child ending inside its parent's advance re-enters here: the outer call goes on
        if node_id in self._advancing:
            return
        self._advancing.add(node_id)
        try:
            self._advance_once(node_id)
        finally:
            self._advancing.discard(node_id)

    def _advance_once(self, node_id: str) -> None:
        rec = self.records[node_id]
        node = self.tst.tree.node(node_id)
        if math.isnan(rec.start) and not self._begin(node, rec):
            return
        if not self._check_deadline(node_id):
            return
        kind = node.acts_as
        if kind is NodeKind.FOREACH:
            self._expand_foreach(node, rec)
        elif kind is NodeKind.ACTION:
            self._advance_action(node, rec)
        elif kind is NodeKind.GOAL:
            self._advance_goal(node, rec)
        elif kind in (NodeKind.SEQUENCE, NodeKind.CALL):
            if node.kind is NodeKind.GOAL and self._recover_failed_step(node, rec):
                return
            self._advance_sequence(node, rec)
        elif kind is NodeKind.CONCURRENT:
            self._advance_concurrent(node, rec)
        else:
            self._advance_conditional(node, rec)

    def _check_deadline(self, node_id: str) -> bool:
        """Fail the node (stopping its subtree) when its latest end has passed; False then."""
        te = self.tst.tree.nodes[node_id].params["TE"]
        latest_end = self.tst.network.window(te).latest
        if self.now > latest_end + TICK_TOLERANCE_S and te not in self.tst.network.values:
            self._fail_running(
                node_id, f"deadline: not done at {self.now:.1f} s, latest end {latest_end:.1f} s"
            )
            return False
        return True

    def _begin(self, node: Node, rec: NodeRecord) -> bool:
        """Start the node when its earliest start has come and nothing due before it pends."""
        ts = node.params["TS"]
        window = self.tst.network.window(ts)
        if self.now < window.earliest:
            return False
        pending = self._pending_before(node)
        if pending:
            return self._wait(rec, window.latest, pending)
        start = self._observed(ts)
        if ts not in self.tst.network.values:
            fixed = self.tst.network.fix(ts, start, f"{node.node_id} started at {start:.3f} s")
            if fixed.status is not FixStatus.OK:
                self._finish(
                    rec, NodeState.FAILED, _conflict(f"started at {start:.1f} s", fixed.conflict)
                )
                return False
        rec.start, rec.reason = start, ""
        if node.kind is NodeKind.ACTION:
            reason = self._start_action(node, rec, self.now)
            if reason:
                self._finish(rec, NodeState.FAILED, reason)
                return False
        self.ctx.sink.status(rec)
        return True

    def _pending_before(self, node: Node) -> list[str]:
        """The starts and ends the constraints put before the node's start, not yet happened.

        Events not yet observed lie in the future, so a node whose start is tied to them waits
        (a dispatcher's rule for Simple Temporal Networks): a sibling ordered before it by a
        ``where`` clause, a node on another agent that must start first. Of two starts due at
        the same time (``s3 = u3``) whose nodes both wait to begin, the leader (:meth:`_leads`)
        begins and the other follows at the leader's recorded time (:meth:`_observed`). A start
        that what happened already pins to a time (a child of another agent's node that has
        begun, tied to its start) is not waited for. The ancestors have started: the parent
        started this node (when it lives on another agent, this replica may not have heard of
        their starts yet). The start of a node whose parent has not begun is the parent's to
        wait for. A node its requester released waits for no other agent's event.
        """
        events = self._events()
        released = self.records[node.node_id].released
        ancestors = set()
        parent = node.parent
        while parent is not None and parent.node_id in self.tst.tree.nodes:
            ancestors.add(parent.node_id)
            parent = self.tst.tree.nodes[parent.node_id].parent
        pending = []
        for var, distance in self.tst.network.stn.no_later_than(node.params["TS"]).items():
            event = events.get(var)
            if event is None:
                continue
            node_id, param = event
            if param == "TS" and node_id in ancestors:
                continue
            other = self.records[node_id]
            if released and other.agent != self.ctx.agent:
                continue
            if param == "TS":
                if math.isfinite(other.start) or self._waits_for_parent(node_id):
                    continue
                ready = other.state is NodeState.RUNNING  # started by its parent, waiting
                if distance == (0, 0) and (
                    self._pinned(var) or (ready and self._leads(node, node_id, var))
                ):
                    continue
            elif other.state.finished:
                continue
            pending.append(f"{other.agent}/{node_id}.{param}")
        return sorted(pending)

    def _leads(self, node: Node, other_id: str, var: str) -> bool:
        """The node starts first of two ready nodes whose starts are equal (``var`` the other's).

        One of them must begin and the other follow, or each would fix its own tick's time
        (20 ms apart in one run). The leader is the lower (agent, node id); the follower waits
        until it hears of the leader's start, which pins its own to that time. A start that
        only must not come after ``var`` (not equal to it) follows.
        """
        ours = (self.records[node.node_id].agent, node.node_id)
        if ours >= (self.records[other_id].agent, other_id):
            return False
        back = self.tst.network.stn.no_later_than(var).get(node.params["TS"])
        return back == (0, 0)

    def _pinned(self, var: str) -> bool:
        """Whether what happened fixes the variable's time (a child tied to its parent's start).

        Such a start happens then, whether or not this replica has heard of it yet.
        """
        window = self.tst.network.window(var)
        return window.earliest == window.latest

    def _waits_for_parent(self, node_id: str) -> bool:
        """The node's parent has not begun: the parent's own start is the one to wait for.

        Its descendants (a monitor-single's hover and look-at, tied to its start) come along.
        """
        parent = self.tst.tree.nodes[node_id].parent
        record = None if parent is None else self.records.get(parent.node_id)
        return record is not None and math.isnan(record.start)

    def _events(self) -> dict[str, tuple[str, str]]:
        """Each start and end variable of the tree as it is now: its node and TS or TE.

        Not the steps of a plan a recovery abandoned: they stay in ``tree.nodes`` as the
        record, but their goal no longer lists them, and they will never start or end.
        """
        return timepoints(n for n in self.tst.tree.nodes.values() if not self._abandoned(n))

    def _abandoned(self, node: Node) -> bool:
        """Whether the node, or an ancestor, is no longer among its parent's children."""
        nodes = self.tst.tree.nodes
        while node.parent is not None and node.parent.node_id in nodes:
            parent = nodes[node.parent.node_id]
            if all(c.node_id != node.node_id for c in parent.children):
                return True
            node = parent
        return False

    def _wait(self, rec: NodeRecord, latest: float, pending: list[str]) -> bool:
        """Wait for ``pending`` (said in the node's status once); fail it past its latest start."""
        if self.now > latest + TICK_TOLERANCE_S:
            self._finish(
                rec,
                NodeState.FAILED,
                f"not started by its latest start {latest:.1f} s: waiting for "
                + ", ".join(pending),
            )
            return False
        reason = "waiting for " + ", ".join(pending)
        if rec.reason != reason:
            rec.reason = reason
            self.ctx.sink.status(rec)
        return False

    # --- elementary actions -------------------------------------------------------------
    def _start_action(self, node: Node, rec: NodeRecord, started: float) -> str:
        spec = ACTIONS[node.action]
        executor = self.ctx.executors.get(node.action)
        if executor is None:
            return f"{self.ctx.agent} has no executor for {node.action}"
        args: dict[str, float | str] = {}
        for pspec in spec.params:
            value, reason = self._bind(node, pspec)
            if value is None:
                return reason
            args[pspec.name] = value
        points = {name: place.coords for name, place in self.tst.places.items()}
        action_ctx = ActionContext(
            node.node_id,
            self.ctx.agent,
            spec,
            args,
            points,
            self.ctx.platform,
            self.ctx.frame,
            started,
            self.now,
            navigation=self.ctx.navigation,
            memory=rec.memory,
        )
        rec.stepper = Stepper(executor(), action_ctx)
        self.ctx.sink.flag(node.node_id, node.action, True, action_ctx.args)
        return ""

    def _bind(self, node: Node, pspec: ParamSpec) -> tuple[float | str | None, str]:
        """The parameter's value, binding an open one (preferred value, else a solution)."""
        var = node.params[pspec.name]
        net = self.tst.network
        if var in net.values:
            return net.values[var], ""
        candidates: list[float | str] = []
        if pspec.preferred is not None:
            candidates.append(pspec.preferred)
        solution = net.finite.solve()
        if solution.status is SolveStatus.CONSISTENT and var in solution.witness:
            candidates.append(solution.witness[var])
        for value in candidates:
            if (
                net.fix(var, value, f"{node.node_id}.{pspec.name} bound at start").status
                is FixStatus.OK
            ):
                return value, ""
        return None, f"no value of {node.node_id}.{pspec.name} satisfies the constraints"

    def _advance_action(self, node: Node, rec: NodeRecord) -> None:
        assert rec.stepper is not None
        try:
            status = rec.stepper.step(self.now)
        except Exception as exc:  # an executor bug fails its node, never the manager
            status = Status(Progress.FAILED, f"executor error: {exc!r}")
        action_ctx = rec.stepper.ctx
        for text in action_ctx.notes:
            self.ctx.sink.note(node.node_id, text)
        for segments in action_ctx.paths:
            self.ctx.sink.path(node.node_id, segments)
        action_ctx.notes.clear()
        action_ctx.paths.clear()
        if status.progress is Progress.RUNNING:
            return
        self.ctx.sink.flag(node.node_id, node.action, False, action_ctx.args)
        if status.progress is Progress.SUCCEEDED:
            self._succeed(rec)
        else:
            self._finish(rec, NodeState.FAILED, status.reason)

    # --- control nodes ------------------------------------------------------------------
    def _child(self, ref: NodeRef) -> NodeRecord:
        return self.records[ref.node_id]

    def _start_child(self, parent: NodeRecord, child_id: str, advance: bool = True) -> None:
        """Start a child here (advanced at once unless ``advance`` is False) or on its agent."""
        rec = self.records[child_id]
        parent.started_children.add(child_id)
        if self.holds(child_id):
            if rec.state is NodeState.CREATED:
                rec.state = NodeState.RUNNING
                rec.start = math.nan
                self._running.append(child_id)
                if advance:
                    self._advance(child_id)
            return
        if not rec.remote_requested:
            rec.remote_requested = True
            self.ctx.sink.start_remote(NodeRef(rec.agent, child_id), self.epoch)

    def _advance_sequence(self, node: Node, rec: NodeRecord) -> None:
        children = [c.node_id for c in node.children]
        while rec.cursor < len(children):
            child_id = children[rec.cursor]
            child = self.records[child_id]
            if child_id not in rec.started_children:
                self._start_child(rec, child_id)
            if child.state is NodeState.SUCCEEDED:
                rec.cursor += 1
                continue
            if child.state.finished:
                self._finish(
                    rec, NodeState.FAILED, f"{child_id} {child.state.value}: {child.reason}"
                )
            return
        self._succeed(rec)

    def _advance_concurrent(self, node: Node, rec: NodeRecord) -> None:
        children = [c.node_id for c in node.children]
        # all are started before any begins: children whose starts are tied to each other
        # (monitor-single's hover, measurement and look-at at one T_S) begin in the same tick
        new = [c for c in children if c not in rec.started_children]
        for child_id in new:
            self._start_child(rec, child_id, advance=False)
        for child_id in new:
            if self.holds(child_id) and self.records[child_id].state is NodeState.RUNNING:
                self._advance(child_id)
        failed = [
            c for c in children if self.records[c].state in (NodeState.FAILED, NodeState.ABORTED)
        ]
        if failed:
            first = self.records[failed[0]]
            reason = f"{first.node_id} {first.state.value}: {first.reason}"
            for child_id in children:
                self._abort_child(child_id, f"sibling {reason}")
            self._finish(rec, NodeState.FAILED, reason)
        elif all(self.records[c].state is NodeState.SUCCEEDED for c in children):
            self._succeed(rec)

    def _advance_conditional(self, node: Node, rec: NodeRecord) -> None:
        assert node.condition is not None
        if rec.chosen:
            child = self.records[rec.chosen]
            if not child.state.finished:
                return
            if child.state is not NodeState.SUCCEEDED:
                self._finish(
                    rec, NodeState.FAILED, f"{child.node_id} {child.state.value}: {child.reason}"
                )
                return
            if node.kind is not NodeKind.WHILE:
                self._succeed(rec)
                return
            self._reset(child.node_id)
            rec.chosen = ""
            rec.rounds += 1
        # variables are named by their source names (call instances by a prefix)
        values = self.tst.network.values
        answer = ask(node.condition, self.ctx.agent, values, self.ctx.platform.state())
        if answer.answer is Answer.UNKNOWN:
            self._finish(rec, NodeState.FAILED, answer.reason)
            return
        holds = answer.answer is Answer.TRUE
        children = [c.node_id for c in node.children]
        if node.kind is NodeKind.IF:
            rec.chosen = children[0] if holds else children[1]
        elif not holds:
            self._succeed(rec)
            return
        else:
            rec.chosen = children[0]
        rec.started_children.discard(rec.chosen)
        self._start_child(rec, rec.chosen)

    def _expand_foreach(self, node: Node, rec: NodeRecord) -> None:
        """Ask the query once, instantiate the body per answer, then run them concurrently."""
        assert node.condition is not None
        domain = QueryDomain(
            self.tst.agents,
            frozenset(self.ctx.executors),
            {name: place.kind for name, place in self.tst.places.items()},
        )
        answers = ask_all(
            node.condition,
            node.loop_vars,
            domain,
            self.ctx.agent,
            self.tst.network.values,
            self.ctx.platform.state(),
        )
        if answers.answer is Answer.UNKNOWN:
            self._finish(rec, NodeState.FAILED, answers.reason)
            return
        if not answers.bindings:
            self._succeed(rec)
            return
        instance = self.tst.expand_foreach(node.node_id, answers.bindings)
        self._record(instance.nodes)
        if instance.status is not InstanceStatus.OK:
            self._finish(rec, NodeState.FAILED, f"foreach instance: {instance.reason}")
            return
        listed = ", ".join(",".join(b) for b in answers.bindings)
        self.ctx.sink.note(node.node_id, f"{len(answers.bindings)} instances: {listed}")
        self._advance_concurrent(node, rec)

    def _record(self, node_ids: tuple[str, ...]) -> None:
        """Records for nodes added at run time (foreach instances), held by their agents."""
        for node_id in node_ids:
            self.records.setdefault(node_id, NodeRecord(node_id, self.tst.agent_of(node_id)))

    def _reset(self, node_id: str) -> None:
        """Make a loop body runnable again (its times are fixed per round only in the record)."""
        for _, sub in self.tst.tree.walk(node_id):
            r = self.records[sub.node_id]
            self.records[sub.node_id] = NodeRecord(sub.node_id, r.agent)

    # --- goals --------------------------------------------------------------------------
    def _advance_goal(self, node: Node, rec: NodeRecord) -> None:
        if rec.brake is not None and not rec.brake.state.ended:
            return
        if rec.hook is not None and not rec.hook.state.ended:
            return
        if rec.letting_go:
            action, length = rec.letting_go.pop(0)
            rec.hook = self.ctx.platform.hook(action, length)
            return
        if rec.plan is None:
            if rec.problem is None:
                state = self.ctx.platform.state()
                if state is None:
                    return
                position = (state.east, state.north, state.up)
                points = {
                    n: p.coords[0] for n, p in self.tst.places.items() if p.kind is ParamType.POINT
                }
                rec.problem = goal_problem(node, self.ctx.agent, position, points, self.loads)
                if self.lift_capacity is not None:
                    rec.problem = replace(rec.problem, lift_capacity=self.lift_capacity)
                self.tst.places.setdefault(
                    here(self.ctx.agent), Place(ParamType.POINT, (position,))
                )
            problem = rec.problem
            rec.plan = self.ctx.planner.request(domain_text(), problem.text(), problem.control())
            return
        if not rec.plan.done:
            return
        if not rec.plan.solved:
            self._replanned(rec, (), f"planning {node.action}: {rec.plan.reason}")
            self._finish(rec, NodeState.FAILED, f"planning {node.action}: {rec.plan.reason}")
            return
        steps = plan_steps(rec.plan.labels, rec.plan.agents, rec.plan.starts, rec.plan.durations)
        if steps.status is not StepsStatus.OK:
            self._replanned(rec, (), steps.reason)
            self._finish(rec, NodeState.FAILED, steps.reason)
            return
        self._replanned(rec, rec.plan.labels, "")
        try:
            self._attach(node, steps.steps)
        except Inconsistent as exc:
            self._finish(
                rec, NodeState.FAILED, _conflict("the plan", tuple(e.label for e in exc.cycle))
            )
            return
        self._advance_sequence(node, rec)

    def _attach(self, goal: Node, steps: tuple[PlannedStep, ...]) -> None:
        """Add the plan's steps as this goal's children (a sequence on this agent).

        The first plan's nodes are ``goal/1``, ``goal/2``...; a recovery's plan ``n`` are
        ``goal/n.1``... (the old plan's nodes stay, as the record of what ran).
        """
        net = self.tst.network
        refs: list[NodeRef] = []
        previous_te: str | None = None
        goal_rec = self.records[goal.node_id]
        goal_rec.plans += 1
        goal_rec.steps = steps
        goal_rec.cursor, goal_rec.started_children = 0, set()
        prefix = f"{goal.node_id}/" if goal_rec.plans == 1 else f"{goal.node_id}/{goal_rec.plans}."
        for index, step in enumerate(steps):
            node_id = f"{prefix}{index + 1}"
            params: dict[str, str] = {"P": goal.params["P"]}
            for key in ("TS", "TE"):
                params[key] = f"{node_id}.{key}"
                net.declare(params[key], ParamType.TIME)
            stn = net.stn
            label = f"{node_id}: planned for goal {goal.node_id}"
            stn.add(params["TS"], params["TE"], 0.0, False, f"{label}: TS <= TE")
            stn.add(goal.params["TS"], params["TS"], 0.0, False, f"{label}: starts within")
            stn.add(params["TE"], goal.params["TE"], 0.0, False, f"{label}: ends within")
            if previous_te is not None:
                stn.add(previous_te, params["TS"], 0.0, False, f"{label}: after the previous step")
            for pspec in ACTIONS[step.action].params:
                var = f"{node_id}.{pspec.name}"
                net.declare(
                    var,
                    pspec.type,
                    tuple(n for n, p in self.tst.places.items() if p.kind is pspec.type),
                )
                params[pspec.name] = var
                if pspec.name in step.args:
                    net.values[var] = step.args[pspec.name]
            self.tst.tree.add(
                Node(
                    node_id,
                    NodeKind.ACTION,
                    params,
                    NodeRef(step.agent, goal.node_id),
                    action=step.action,
                )
            )
            self.records[node_id] = NodeRecord(node_id, step.agent)
            refs.append(NodeRef(step.agent, node_id))
            previous_te = params["TE"]
        self.tst.tree.expand(goal.node_id, NodeKind.SEQUENCE, refs)

    # --- recovery (section 9.3.1) ------------------------------------------------------
    def on_violation(self, violation: Violation, node_id: str) -> RecoveryReport:
        """Recover the running planned goal that ``node_id`` belongs to ("": any of them).

        Returns the last step carried out (IGNORED when no planned goal of this agent runs).
        """
        goal_id = self._goal_of(node_id)
        if goal_id is None:
            ignored = RecoveryReport(
                "",
                violation.monitor_id,
                violation.recovery,
                RecoveryStep.IGNORED,
                reason=f"no running planned goal of {self.ctx.agent} holds {node_id or 'it'}",
            )
            self.ctx.sink.recovery(ignored)
            return ignored
        rec, goal = self.records[goal_id], self.tst.tree.node(goal_id)
        assert rec.problem is not None  # _goal_of only finds planned goals
        if rec.recovery is None:
            rec.recovery = Recovery(self.ctx.recovery)
        state = self.ctx.platform.state()
        if state is None:
            position = rec.problem.locations[rec.problem.start]
        else:
            position = (state.east, state.north, state.up)
        decision = rec.recovery.decide(violation, rec.problem, self._done(goal), position)
        reason = f"recovering from {violation.monitor_id}"
        self._stopping.add(goal_id)
        try:
            for child in goal.children:
                self._abort_child(child.node_id, reason)
        finally:
            self._stopping.discard(goal_id)

        def report(step: RecoveryStep, why: str, changes: tuple[str, ...] = ()) -> RecoveryReport:
            out = RecoveryReport(
                goal_id,
                violation.monitor_id,
                violation.recovery,
                step,
                decision.attempt,
                changes=changes,
                reason=why,
            )
            self.ctx.sink.recovery(out)
            return out

        last = report(RecoveryStep.SUSPEND, reason)
        if RecoveryStep.BRAKE in decision.steps:
            rec.brake = self.ctx.platform.send(FclCommand.EMERGENCY_BRAKE)
            last = report(RecoveryStep.BRAKE, f"{violation.monitor_id} asks for a brake")
        last = report(RecoveryStep.HOVER, "the flight control hovers between commands")
        if decision.status is not RecoveryStatus.REPLAN or decision.problem is None:
            last = report(RecoveryStep.GIVE_UP, decision.reason)
            self._finish(rec, NodeState.FAILED, decision.reason)
            return last
        for name, xyz in decision.places.items():
            self.tst.places[name] = Place(ParamType.POINT, (xyz,))
        if decision.problem.lift_capacity != rec.problem.lift_capacity:
            self.lift_capacity = decision.problem.lift_capacity  # learnt for later goals too
        last = report(RecoveryStep.APPLY_OPERATOR, decision.reason, decision.changes)
        if decision.released:  # magnet off, hook wound in, then plan
            rec.letting_go = list(LET_GO)
        self.tst.tree.collapse(goal_id)
        rec.problem, rec.plan, rec.recovering = decision.problem, None, violation
        self._advance(goal_id)
        return last

    def _done(self, goal: Node) -> list[PlannedStep]:
        """The steps of a planned goal's current plan that succeeded, in order."""
        steps = self.records[goal.node_id].steps
        children = [self.records[c.node_id] for c in goal.children]
        return [s for s, r in zip(steps, children, strict=False) if r.state is NodeState.SUCCEEDED]

    def _recover_failed_step(self, goal: Node, rec: NodeRecord) -> bool:
        """Recover a planned goal whose current step failed, when the operators say how.

        The failure is recovered like a violation of the ``step-failed`` operator
        (:data:`STEP_FAILED`), one fault per action name: the goal plans again from where the
        aircraft is and what the succeeded steps did. True when that recovery was started.
        """
        if STEP_FAILED not in self.ctx.recovery.operators or rec.cursor >= len(goal.children):
            return False
        step_id = goal.children[rec.cursor].node_id
        step = self.records[step_id]
        if step.state is not NodeState.FAILED or rec.problem is None:
            return False
        action = self.tst.tree.node(step_id).action
        violation = Violation(
            f"{STEP_FAILED}@{step_id}",
            STEP_FAILED,
            arguments={"action": action},
            cause=f"{step_id} ({action}) failed: {step.reason}",
        )
        return self.on_violation(violation, step_id).step is not RecoveryStep.IGNORED

    def _goal_of(self, node_id: str) -> str | None:
        """The running, planned goal node this agent holds that ``node_id`` is under."""
        goals = [
            n
            for n in self._running
            if self.tst.tree.nodes[n].kind is NodeKind.GOAL
            and self.records[n].problem is not None
            and self.records[n].state is NodeState.RUNNING
        ]
        if not node_id:
            return goals[0] if goals else None
        if node_id not in self.tst.tree.nodes:
            return None
        return next((g for g in goals if self._under(node_id, g)), None)

    def _replanned(self, rec: NodeRecord, labels: tuple[str, ...], reason: str) -> None:
        """Report a recovering goal's new plan (or why it has none)."""
        violation, rec.recovering = rec.recovering, None
        if violation is None:
            return
        step = RecoveryStep.REPLAN if not reason else RecoveryStep.GIVE_UP
        attempt = 0 if rec.recovery is None else rec.recovery.attempts(violation)
        self.ctx.sink.recovery(
            RecoveryReport(
                rec.node_id,
                violation.monitor_id,
                violation.recovery,
                step,
                attempt,
                plan=labels,
                reason=reason or f"{len(labels)} actions",
            )
        )

    # --- endings ------------------------------------------------------------------------
    def _succeed(self, rec: NodeRecord) -> None:
        node = self.tst.tree.node(rec.node_id)
        te = node.params["TE"]
        end = self._observed(te)
        if te not in self.tst.network.values:
            fixed = self.tst.network.fix(te, end, f"{rec.node_id} ended at {end:.3f} s")
            if fixed.status is not FixStatus.OK:
                self._finish(
                    rec, NodeState.FAILED, _conflict(f"ended at {end:.1f} s", fixed.conflict)
                )
                return
        self._finish(rec, NodeState.SUCCEEDED, "", end)

    def _observed(self, var: str) -> float:
        """The time a start or end happened: now, or its latest time when a tick passed it.

        The engine sees time at its ticks, so an end due between two ticks (a wait's or a
        hover's, fixed by its duration) is seen up to a tick late; within
        :data:`TICK_TOLERANCE_S` it is recorded at the latest time the network allows. An end
        seen in the very tick of its lower bound (an action done at once: a PTU already pointed,
        a fly-to to where the aircraft is; then its parent) happened within that tick, after the
        bound: it is recorded at the bound, one STN tick (1 ns) later when strict (``TS < TE``).
        """
        window = self.tst.network.window(var)
        if window.latest < self.now <= window.latest + TICK_TOLERANCE_S:
            return window.latest
        if not math.isfinite(window.earliest):
            return self.now
        # in the network's whole nanoseconds: a float ``now`` a hair past the bound is the bound
        earliest = round(window.earliest * TICKS_PER_S)
        early = earliest - round(self.now * TICKS_PER_S)
        strict = window.earliest_strict
        if 0 <= early <= SAME_TICK_S * TICKS_PER_S and (early > 0 or strict):
            return (earliest + strict) / TICKS_PER_S
        return self.now

    def _finish(
        self, rec: NodeRecord, state: NodeState, reason: str, at: float | None = None
    ) -> None:
        if rec.state.finished:
            return
        rec.state, rec.reason, rec.end = state, reason, self.now if at is None else at
        if math.isnan(rec.start):
            rec.start = self.now
        rec.stepper = None
        if rec.node_id in self._running:
            self._running.remove(rec.node_id)
        if rec.problem is not None:  # a planned goal: what its steps did to the loads holds
            self.loads = progressed(rec.problem, self._done(self.tst.tree.node(rec.node_id))).loads
        self.ctx.sink.status(rec)
        # the parent reacts in the same tick (a sequence starts the next child at once)
        parent = self.tst.tree.nodes[rec.node_id].parent
        if (
            parent is not None
            and parent.node_id in self._running
            and parent.node_id not in self._stopping
        ):
            self._advance(parent.node_id)

    def _fail_running(self, node_id: str, reason: str) -> None:
        self._stop(node_id, NodeState.FAILED, reason)

    def _abort(self, node_id: str, reason: str) -> None:
        self._stop(node_id, NodeState.ABORTED, reason)

    def _stop(self, node_id: str, state: NodeState, reason: str) -> None:
        rec = self.records[node_id]
        if rec.state.finished:
            return
        self._stopping.add(node_id)
        try:
            self._abort_subtree(node_id, reason)
        finally:
            self._stopping.discard(node_id)
        self._finish(rec, state, reason)

    def _abort_subtree(self, node_id: str, reason: str) -> None:
        """Stop the node's commands, and abort its running children."""
        node = self.tst.tree.node(node_id)
        self._stop_commands(node_id, reason)
        for child in node.children:
            self._abort_child(child.node_id, f"parent {node_id}: {reason}")

    def _stop_commands(self, node_id: str, reason: str) -> None:
        """End every command the node's executor sent that has not ended."""
        rec = self.records[node_id]
        if rec.stepper is None:
            return
        for command in rec.stepper.ctx.commands:
            if not command.state.ended:
                self.ctx.platform.stop(command, reason)
        rec.stepper.close()
        action = self.tst.tree.nodes[node_id].action
        self.ctx.sink.flag(node_id, action, False, rec.stepper.ctx.args)

    def _abort_child(self, child_id: str, reason: str) -> None:
        child = self.records[child_id]
        if child.state.finished:
            return
        if self.holds(child_id):
            if child.state in (NodeState.RUNNING, NodeState.PAUSED):
                self._abort(child_id, reason)
        elif child.remote_requested:
            self.ctx.sink.abort_remote(NodeRef(child.agent, child_id), reason)

    def _under(self, node_id: str, ancestor: str) -> bool:
        current: str | None = node_id
        while current is not None:
            if current == ancestor:
                return True
            parent = self.tst.tree.nodes[current].parent
            current = parent.node_id if parent is not None else None
        return False


def _conflict(what: str, conflict: tuple[str, ...]) -> str:
    return (
        f"{what} conflicts with: {'; '.join(conflict)}" if conflict else f"{what} is inconsistent"
    )
