"""The executor framework of elementary actions (section 6.3): one hook per executor.

The engine (``engine.py``) owns the lifecycle: it creates an executor when its node starts,
advances its one hook, the generator :meth:`ActionExecutor.run`, once per tick until it returns
a terminal :class:`Status`,
checks the node's timing against its T_S/T_E window, and on abort ends every command the
executor sent through its :class:`ActionContext` (FCL: brake to a hover). An executor therefore
never cleans up after itself and never blocks: it sends commands through the context, looks at
their handles and the Data Interface, and says whether it is still running.
"""

from __future__ import annotations

import enum
from collections.abc import Generator, Mapping
from dataclasses import dataclass, field

from hdrc3_control.path_segment import PathSegment
from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.hook_api import HookAction
from hdrc3_tst.actions import ActionSpec
from hdrc3_tst.navigation_port import NavigationPort
from hdrc3_tst.platform_port import Command, PlatformPort, PlatformState


class Progress(enum.Enum):
    """What an executor's update says."""

    RUNNING = "running"
    SUCCEEDED = "succeeded"
    FAILED = "failed"


@dataclass(frozen=True)
class Status:
    """An update's verdict; a failure carries its reason."""

    progress: Progress
    reason: str = ""


RUNNING = Status(Progress.RUNNING)
SUCCEEDED = Status(Progress.SUCCEEDED)


def failed(reason: str) -> Status:
    """A failure with its reason."""
    return Status(Progress.FAILED, reason)


COMMAND_BOUND_S = 60.0
"""Mission seconds any command may take beyond its own expected duration (take-off, landing,
braking, PTU moves); a command past its bound is stopped and fails its node."""
SLACK = 3.0
"""A flight may take this many times its length over its speed (turns, wind, braking)."""


def flight_bound(length: float, speed: float) -> float:
    """Mission seconds a flight (or one path segment) of ``length`` m at ``speed`` m/s may take."""
    return COMMAND_BOUND_S + SLACK * length / max(speed, 0.1)


@dataclass
class ActionContext:
    """What one running action node sees: its arguments, its platform, the mission clock."""

    node_id: str
    agent: str
    spec: ActionSpec
    args: Mapping[str, float | str]
    """Every type-specific parameter's value (open ones bound by the engine at start)."""
    points: Mapping[str, tuple[tuple[float, ...], ...]]
    """Declared areas, points and paths by name (local ENU metres)."""
    platform: PlatformPort
    frame: WorldFrame
    started: float
    """Mission time (s) the node started."""
    now: float = 0.0
    """Mission time (s) of the current tick."""
    commands: list[Command] = field(default_factory=list)
    """Every command sent for this node, in order (the engine stops them on abort)."""
    navigation: NavigationPort | None = None
    """The agent's path planner (None: the platform has none, flights go straight)."""
    notes: list[str] = field(default_factory=list)
    """What the executor did beyond its commands (plans, replans) since the last tick; the
    engine hands them to its sink after every tick."""
    paths: list[tuple[PathSegment, ...]] = field(default_factory=list)
    """Paths the executor planned since the last tick (handed to the sink likewise)."""
    memory: dict[str, float] = field(default_factory=dict)
    """What the executor keeps across a pause: each run of the node (start, resume) gets the
    same dict (a scan resumes at the segment it was flying)."""

    def send(self, command: FclCommand | PpclCommand, **args: float) -> Command:
        """Send a command for this node."""
        handle = self.platform.send(command, **args)
        self.commands.append(handle)
        return handle

    def hook(self, action: HookAction, length: float = 0.0, object_id: str = "") -> Command:
        """Send a ``ppcl_hook`` command for this node."""
        handle = self.platform.hook(action, length, object_id)
        self.commands.append(handle)
        return handle

    def name(self, name: str) -> str:
        """The name given for a place argument (a box's point is named by its tag)."""
        return str(self.args[name])

    def number(self, name: str) -> float:
        """A numeric argument."""
        value = self.args[name]
        assert isinstance(value, float | int), f"{name} is not numeric"
        return float(value)

    def place(self, name: str) -> tuple[tuple[float, ...], ...]:
        """The coordinates of a name argument (an area, point or path)."""
        return self.points[str(self.args[name])]

    def state(self) -> PlatformState | None:
        """The latest Data Interface sample."""
        return self.platform.state()

    @property
    def elapsed(self) -> float:
        """Seconds since the node started."""
        return self.now - self.started


class ActionExecutor:
    """One elementary action type on one platform: subclasses implement :meth:`run`."""

    def run(self, ctx: ActionContext) -> Generator[None, None, Status]:
        """Send commands, yield while waiting (one tick per yield), return the outcome."""
        raise NotImplementedError


class Stepper:
    """The framework's handle on one running executor: one :meth:`step` per tick."""

    def __init__(self, executor: ActionExecutor, ctx: ActionContext) -> None:
        self.ctx = ctx
        self._steps = executor.run(ctx)

    def close(self) -> None:
        """The node stops before its executor returned (abort, pause): let it clean up."""
        self._steps.close()

    def step(self, now: float) -> Status:
        """Advance the executor to mission time ``now``; RUNNING or its outcome."""
        self.ctx.now = now
        try:
            next(self._steps)
        except StopIteration as done:
            outcome: Status = done.value
            return outcome
        return RUNNING
