"""The Platform Server's pure core: DRC kernel + FCL/PPCL command layers + Data Interface.

The node (``node.py``) owns ROS: it calls :meth:`PlatformServerCore.on_pfc` for every PFC state
report, :meth:`on_camera` for every PPC camera report, :meth:`tick` periodically, and routes the
services to :attr:`fcl` / :attr:`ppcl`. Everything here runs on the caller's thread.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from hdrc3_hcsm.transport import Transport
from hdrc3_platform_server.codes import FclCode, FclCommand, PpclCode, PpclCommand
from hdrc3_platform_server.completion import TERMINAL, CompletionEvent, EventSink
from hdrc3_platform_server.data_interface import (
    CameraStateData,
    HelicopterStateData,
    RateGate,
    camera_state,
    helicopter_state,
)
from hdrc3_platform_server.drc import DrcKernel
from hdrc3_platform_server.fcl_api import FclAnswer, FlightCommandLayer, IdSource
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.hook_api import LABEL as HOOK_LABEL
from hdrc3_platform_server.hook_api import HookCommandLayer, HookSample, HookSetpoint
from hdrc3_platform_server.journal import CommandJournal
from hdrc3_platform_server.kernel_watch import KernelExit
from hdrc3_platform_server.limits import Limits
from hdrc3_platform_server.platform_status import CameraSample, PfcSample, PlatformStatus
from hdrc3_platform_server.ppcl_api import PayloadCommandLayer, PpclAnswer


class PlatformServerCore:
    """One agent's Platform Server without ROS."""

    def __init__(
        self,
        frame: WorldFrame,
        transport: Transport | None,
        sink: EventSink,
        *,
        id_start: int = 1,
        limits: Limits | None = None,
        settle_timeout: float = 15.0,
        stale_after: float = 2.0,
        journal: CommandJournal | None = None,
        hook: Callable[[HookSetpoint], None] | None = None,
    ) -> None:
        """``hook`` sends the payload hook's set-points (None: a server without a hook)."""
        lim = limits or Limits()
        self.journal = journal or CommandJournal(None)
        self._sink = sink
        self.frame = frame
        self.status = PlatformStatus(stale_after)
        self.kernel = DrcKernel(self.status, transport, settle_timeout=settle_timeout)
        self.ids = IdSource(id_start)
        self.fcl = FlightCommandLayer(
            self.kernel, frame, self._publish, self.ids, lim.flight, self.journal.earlier
        )
        self.ppcl = PayloadCommandLayer(
            self.kernel, frame, self._publish, self.ids, self.landing_active, lim.ptu
        )
        self.hook = HookCommandLayer(self._publish, self.ids, hook or _no_hook)
        self.gate = RateGate()

    def _publish(self, event: CompletionEvent) -> None:
        """Publish, then strike a terminal event's command off the journal.

        A crash in between ends that command twice rather than never.
        """
        self._sink(event)
        if event.kind in TERMINAL:
            self.journal.ended(event.command_id)

    def submit_fcl(self, command: FclCommand, args: Sequence[float], now: float) -> FclAnswer:
        """An FCL call; an accepted command is in the journal before the answer is returned."""
        answer = self.fcl.submit(command, args, now)
        if answer.code is FclCode.OK:
            self.journal.accepted(answer.command_id, command.label)
        return answer

    def submit_ppcl(self, command: PpclCommand, args: Sequence[float], now: float) -> PpclAnswer:
        """A PPCL call (journaled as :meth:`submit_fcl`)."""
        answer = self.ppcl.submit(command, args, now)
        if answer.code is PpclCode.OK:
            self.journal.accepted(answer.command_id, command.label)
        return answer

    def submit_hook(self, action: int, length: float, object_id: str, now: float) -> PpclAnswer:
        """A ppcl_hook call (journaled as :meth:`submit_fcl`)."""
        answer = self.hook.submit(action, length, object_id, now)
        if answer.code is PpclCode.OK:
            self.journal.accepted(answer.command_id, HOOK_LABEL)
        return answer

    def on_hook(self, sample: HookSample) -> None:
        """Take a carrying-sensor sample (ends hook commands)."""
        self.hook.on_sample(sample)

    def landing_active(self) -> bool:
        """True while fcl_land (vision-based landing) is in progress."""
        cur = self.fcl.current
        return cur is not None and cur.command is FclCommand.LAND

    def tick(self, now: float) -> None:
        """Run the DRC automaton once (replies from the PFC/PPC, timeouts)."""
        self.kernel.step(now)
        self.hook.tick(now)

    def on_pfc(self, sample: PfcSample) -> HelicopterStateData | None:
        """Take a PFC report; returns the Data Interface sample when one is due (25 Hz)."""
        self.status.update_pfc(sample)
        self.fcl.resync(sample)
        if not self.gate.due(sample.pfc_time):
            return None
        # The automaton runs at the DI rate here; replies also get a step from tick() and from
        # every service call, so 25 Hz of sim time is enough for the conditions.
        self.kernel.step(sample.received)
        cams = self.status.cameras.values()
        ppc_time = max((c.ipc_time for c in cams), default=None)
        return helicopter_state(
            sample, self.frame, sample.received, ppc_time, self.status.power_status
        )

    def on_world_reset(self, reason: str, now: float) -> None:
        """world_sim started the world over (``/world_sim/run`` RESET): running commands fail."""
        self.fcl.on_world_reset(reason, now)
        self.ppcl.on_world_reset(reason, now)
        self.hook.on_world_reset(reason, now)

    def on_kernel_exit(self, exited: KernelExit, now: float) -> None:
        """The launcher saw this agent's PFC or PPC process die: its commands fail now."""
        if exited.computer == "PFC":
            self.fcl.on_kernel_exit(exited.reason, now)
        else:
            self.ppcl.on_kernel_exit(exited.reason, now)

    def on_camera(self, sample: CameraSample) -> None:
        """Take a PPC camera report."""
        self.status.update_camera(sample)

    def camera_states(self) -> list[CameraStateData]:
        """Latest state of every camera the PPC reported (published with each DI sample)."""
        return [camera_state(c) for _, c in sorted(self.status.cameras.items())]


def _no_hook(setpoint: HookSetpoint) -> None:
    """Set-points of a server without a hook go nowhere (its commands then time out)."""
