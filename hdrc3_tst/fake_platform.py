"""Fakes of the engine's ports for unit tests: a scripted platform, planner and sink.

:class:`FakePlatform` answers commands the way the Platform Server's semantics table says, with
outcomes a test scripts per command, and moves a point aircraft to where a fly command goes when
the test says the command finished. :class:`FakePathFollowing` adds the Platform Server's
path-following events for ``traj3d`` segments (Request-Segment, segment flown, a queued segment
replaced). Nothing here talks to ROS.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from hdrc3_control.path_segment import PathSegment
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_platform_server.hook_api import HookAction
from hdrc3_tst.engine import NodeRecord
from hdrc3_tst.goal_planning import PlanHandle
from hdrc3_tst.model import NodeRef, NodeState
from hdrc3_tst.platform_port import (
    Command,
    CommandState,
    DoseSample,
    PlatformState,
    Sighting,
)
from hdrc3_tst.recovery import RecoveryReport


@dataclass
class FakePlatform:
    """Commands are accepted (RUNNING) at once and end when the test calls :meth:`complete`."""

    sample: PlatformState | None = field(
        default_factory=lambda: PlatformState(0.0, 0.0, 0.0, on_ground=True, autonomous=True)
    )
    sent: list[Command] = field(default_factory=list)
    stopped: list[tuple[Command, str]] = field(default_factory=list)
    refuse: dict[FclCommand | PpclCommand, str] = field(default_factory=dict)
    """Commands answered as refused, with the reason."""
    sightings: dict[str, Sighting] = field(default_factory=dict)
    """What the hook camera sees, by tag (the test sets it)."""
    dose_sample: DoseSample | None = None
    """The radiation detector's latest sample (the test sets it)."""

    def seen(self, tag: str) -> Sighting | None:
        """The scripted sighting of ``tag``."""
        return self.sightings.get(tag)

    def dose(self) -> DoseSample | None:
        """The scripted radiation sample."""
        return self.dose_sample

    def send(self, command: FclCommand | PpclCommand, **args: float) -> Command:
        """Record the command; refused ones fail at once, the others run."""
        handle = Command(command, dict(args), command_id=len(self.sent) + 1)
        if command in self.refuse:
            handle.end(CommandState.FAILED, f"refused: {self.refuse[command]}")
        else:
            handle.state = CommandState.RUNNING
        self.sent.append(handle)
        return handle

    def hook(self, action: HookAction, length: float = 0.0, object_id: str = "") -> Command:
        """Record a hook command; it runs until the test completes it."""
        handle = Command(action, {"length": length}, command_id=len(self.sent) + 1, tag=object_id)
        handle.state = CommandState.RUNNING
        self.sent.append(handle)
        return handle

    def stop(self, command: Command, reason: str) -> None:
        """Record the stop; the command ends failed (FCL: cancelled, the aircraft hovers)."""
        self.stopped.append((command, reason))
        command.end(CommandState.FAILED, f"cancelled: {reason}")

    def state(self) -> PlatformState | None:
        """The scripted Data Interface sample."""
        return self.sample

    def running(self) -> list[Command]:
        """Commands not ended yet."""
        return [c for c in self.sent if not c.state.ended]

    def move_to(self, point: tuple[float, float, float]) -> None:
        """Put the aircraft (in the air) at ``point``."""
        s = self.sample
        autonomous = True if s is None else s.autonomous
        self.sample = PlatformState(point[0], point[1], point[2], False, autonomous)

    def complete(self, command: Command, ok: bool = True, reason: str = "") -> None:
        """End a command; a finished take-off leaves the ground, a finished land touches down."""
        command.end(CommandState.FINISHED if ok else CommandState.FAILED, reason)
        if ok and self.sample is not None and command.command is FclCommand.TAKEOFF:
            s = self.sample
            self.sample = PlatformState(s.east, s.north, s.up + 10.0, False, s.autonomous)
        if ok and self.sample is not None and command.command is FclCommand.LAND:
            s = self.sample
            self.sample = PlatformState(s.east, s.north, 0.0, True, s.autonomous)


@dataclass
class FakePathFollowing:
    """``traj3d`` segments on a :class:`FakePlatform` as the Platform Server reports them.

    The first segment of a path flies at once (and requests its successor unless it ends at
    rest); a further one is queued; a segment sent while another is queued replaces it (the
    older one ends "CANCELLED replaced by segment N"). :meth:`advance` flies the segment in
    flight to its end: it finishes, the aircraft is at its end, and the queued one flies.
    """

    platform: FakePlatform
    flying: Command | None = None
    queued: Command | None = None
    flown: list[Command] = field(default_factory=list)
    """Segments flown to their end, in order."""
    replace: bool = True
    """False: refuse a segment while one is queued (a PFC without the replace operation)."""

    def tick(self) -> None:
        """Take in the traj3d commands sent since the last tick."""
        for command in self.platform.sent:
            if command.command is not FclCommand.TRAJ3D or command.state.ended:
                continue
            if command in (self.flying, self.queued):
                continue
            if self.flying is None or self.flying.state.ended:
                self.flying, self.queued = command, None
                command.segment_requested = command.args["end_velocity"] > 0.0
            elif self.queued is None:
                self.queued = command
            elif not self.replace:
                command.end(CommandState.FAILED, "rejected by the PFC: a segment is queued")
            else:
                self.queued.end(
                    CommandState.FAILED, f"CANCELLED replaced by segment {command.command_id}"
                )
                self.queued = command
        if self.flying is not None and self.flying.state.ended:
            self.flying = None

    def advance(self) -> None:
        """Fly the segment in flight to its end."""
        self.tick()
        flying = self.flying
        if flying is None:
            return
        a = flying.args
        self.platform.move_to((a["end_x"], a["end_y"], a["end_z"]))
        flying.end(CommandState.FINISHED, "segment flown")
        self.flown.append(flying)
        self.flying, self.queued = self.queued, None
        if self.flying is not None:
            self.flying.segment_requested = self.flying.args["end_velocity"] > 0.0


@dataclass
class FakePlanner:
    """Keeps every request; the test answers them."""

    requests: list[PlanHandle] = field(default_factory=list)

    def request(self, domain: str, problem: str, control: str = "") -> PlanHandle:
        """Record the request."""
        handle = PlanHandle(problem, control=control)
        self.requests.append(handle)
        return handle


@dataclass
class SolvingPlanner:
    """The real TALplanner core, answering each request at once (no ROS service)."""

    timeout: float = 30.0
    requests: list[PlanHandle] = field(default_factory=list)

    def request(self, domain: str, problem: str, control: str = "") -> PlanHandle:
        """Plan now and fill the handle."""
        handle = PlanHandle(problem, control=control)
        result = TaskPlanner().plan(PlanRequest(domain, problem, control), timeout=self.timeout)
        plan = result.plan
        handle.answer(
            result.status is PlanStatus.SOLVED,
            result.reason,
            [o.label for o in plan],
            [o.agent or "" for o in plan],
            [o.start for o in plan],
            [o.duration for o in plan],
        )
        self.requests.append(handle)
        return handle


@dataclass
class RecordingSink:
    """Records statuses, flags and remote requests."""

    statuses: list[tuple[str, NodeState, str]] = field(default_factory=list)
    flags: list[tuple[str, str, bool]] = field(default_factory=list)
    flag_args: dict[str, dict[str, float | str]] = field(default_factory=dict)
    remote_starts: list[NodeRef] = field(default_factory=list)
    remote_aborts: list[tuple[NodeRef, str]] = field(default_factory=list)
    notes: list[tuple[str, str]] = field(default_factory=list)
    paths: list[tuple[str, tuple[PathSegment, ...]]] = field(default_factory=list)
    recoveries: list[RecoveryReport] = field(default_factory=list)

    def status(self, record: NodeRecord) -> None:
        """Record a state change."""
        self.statuses.append((record.node_id, record.state, record.reason))

    def flag(
        self, node_id: str, action: str, executing: bool, args: Mapping[str, float | str]
    ) -> None:
        """Record an execution flag (and the arguments of the node's last flag)."""
        self.flags.append((node_id, action, executing))
        self.flag_args[node_id] = dict(args)

    def start_remote(self, ref: NodeRef, epoch: float) -> None:
        """Record a remote start."""
        self.remote_starts.append(ref)

    def abort_remote(self, ref: NodeRef, reason: str) -> None:
        """Record a remote abort."""
        self.remote_aborts.append((ref, reason))

    def note(self, node_id: str, text: str) -> None:
        """Record an executor's note."""
        self.notes.append((node_id, text))

    def path(self, node_id: str, segments: tuple[PathSegment, ...]) -> None:
        """Record a planned path."""
        self.paths.append((node_id, segments))

    def recovery(self, report: RecoveryReport) -> None:
        """Record a recovery step."""
        self.recoveries.append(report)
