"""Fakes of the engine's ports for unit tests: a scripted platform, planner and sink.

:class:`FakePlatform` answers commands the way the Platform Server's semantics table says, with
outcomes a test scripts per command, and moves a point aircraft to where a fly command goes when
the test says the command finished. Nothing here talks to ROS.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_tst.engine import NodeRecord
from hdrc3_tst.goal_planning import PlanHandle
from hdrc3_tst.model import NodeRef, NodeState
from hdrc3_tst.platform_port import Command, CommandState, PlatformState


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

    def send(self, command: FclCommand | PpclCommand, **args: float) -> Command:
        """Record the command; refused ones fail at once, the others run."""
        handle = Command(command, dict(args), command_id=len(self.sent) + 1)
        if command in self.refuse:
            handle.end(CommandState.FAILED, f"refused: {self.refuse[command]}")
        else:
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
class FakePlanner:
    """Keeps every request; the test answers them."""

    requests: list[PlanHandle] = field(default_factory=list)

    def request(self, domain: str, problem: str) -> PlanHandle:
        """Record the request."""
        handle = PlanHandle(problem)
        self.requests.append(handle)
        return handle


@dataclass
class RecordingSink:
    """Records statuses, flags and remote requests."""

    statuses: list[tuple[str, NodeState, str]] = field(default_factory=list)
    flags: list[tuple[str, str, bool]] = field(default_factory=list)
    remote_starts: list[NodeRef] = field(default_factory=list)
    remote_aborts: list[tuple[NodeRef, str]] = field(default_factory=list)

    def status(self, record: NodeRecord) -> None:
        """Record a state change."""
        self.statuses.append((record.node_id, record.state, record.reason))

    def flag(self, node_id: str, action: str, executing: bool) -> None:
        """Record an execution flag."""
        self.flags.append((node_id, action, executing))

    def start_remote(self, ref: NodeRef, epoch: float) -> None:
        """Record a remote start."""
        self.remote_starts.append(ref)

    def abort_remote(self, ref: NodeRef, reason: str) -> None:
        """Record a remote abort."""
        self.remote_aborts.append((ref, reason))
