"""What an executor may ask of its platform: FCL/PPCL commands and the Data Interface (§6.2).

The executors are pure Python; the TST manager node gives them a :class:`PlatformPort` that
calls the Platform Server's services and follows its platform events
(``hdrc3_tst.ros_platform``), and the unit tests give them :class:`~hdrc3_tst.fake_platform.
FakePlatform`. Commands are named by the Platform Server's registry (``FclCommand``,
``PpclCommand``) and take its arguments by name, so nothing here repeats a service layout.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Protocol

from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_platform_server.hook_api import LABEL as HOOK_LABEL
from hdrc3_platform_server.hook_api import HookAction

AnyCommand = FclCommand | PpclCommand | HookAction

LET_GO: tuple[tuple[HookAction, float], ...] = ((HookAction.RELEASE, 0.0), (HookAction.RAISE, 0.0))
"""Hook commands (action, cable length) that let go of a load and wind the hook in, in order:
a pick-up starts with them, and so does a recovery whose load did not lift."""
"""What a command handle names: an FCL or PPCL command, or a ``ppcl_hook`` action."""


class CommandState(enum.Enum):
    """Where one command is: sent, accepted (running), or ended."""

    SENT = "sent"
    RUNNING = "running"
    FINISHED = "finished"
    FAILED = "failed"
    """Refused, failed, cancelled or unanswered: ``reason`` says which."""

    @property
    def ended(self) -> bool:
        """Finished or failed."""
        return self in (CommandState.FINISHED, CommandState.FAILED)


@dataclass
class Command:
    """A handle on one FCL/PPCL command; the port updates it as answers and events arrive."""

    command: AnyCommand
    args: dict[str, float] = field(default_factory=dict)
    state: CommandState = CommandState.SENT
    reason: str = ""
    command_id: int = 0
    segment_requested: bool = False
    """A traj3d segment whose path following asks for the next segment (§7.2)."""
    busy: bool = False
    """Refused BUSY: the platform still runs another command (it may be sent again)."""
    tag: str = ""
    """A hook command's object tag (ATTACH: the object the magnet must hold)."""

    @property
    def label(self) -> str:
        """``fcl_takeoff``, ``ppcl_look_at``, ``ppcl_hook`` ..."""
        if isinstance(self.command, HookAction):
            return HOOK_LABEL
        prefix = "fcl" if isinstance(self.command, FclCommand) else "ppcl"
        return f"{prefix}_{self.command.value}"

    def end(self, state: CommandState, reason: str = "") -> None:
        """Record the terminal outcome (the first one counts)."""
        if not self.state.ended:
            self.state, self.reason = state, reason


@dataclass(frozen=True)
class PlatformState:
    """The Data Interface sample executors decide on (local ENU of the world's origin)."""

    east: float
    north: float
    up: float
    on_ground: bool
    autonomous: bool
    failsafe: str = ""
    """The PFC's announcement of a navigation failsafe in force, "" when none."""
    battery: float = 1.0
    """State of charge, 0..1 (1 when the platform does not report it)."""


@dataclass(frozen=True)
class Sighting:
    """The hook camera's latest view of one tagged object: where it is from the winch."""

    offset: tuple[float, float, float]
    """m, local ENU, object (its grip point) minus winch."""
    time: float
    """s, sim time of the image."""


@dataclass(frozen=True)
class DoseSample:
    """One integration of the radiation detector (``/<agent>/sensors/radiation``)."""

    dose_rate: float
    """microsievert per hour at the aircraft."""
    counts: int
    integration_time: float
    """s."""
    time: float
    """s, sim time of the end of the integration."""


class PlatformPort(Protocol):
    """One agent's Platform Server, as executors use it."""

    def send(self, command: FclCommand | PpclCommand, **args: float) -> Command:
        """Send a command with its registry arguments; the handle tracks its outcome."""

    def hook(self, action: HookAction, length: float = 0.0, object_id: str = "") -> Command:
        """A ``ppcl_hook`` command (winch and magnet); the handle tracks its outcome."""

    def stop(self, command: Command, reason: str) -> None:
        """End a running command: FCL brakes to a hover (fcl_cancel), PPCL stops its mode.

        A stopped hook command leaves the hook as it is (a held load is not dropped).
        """

    def state(self) -> PlatformState | None:
        """The latest Data Interface sample, None before the first one."""

    def seen(self, tag: str) -> Sighting | None:
        """The hook camera's latest sighting of the object ``tag``, None if never seen."""

    def dose(self) -> DoseSample | None:
        """The radiation detector's latest sample, None before the first one."""
