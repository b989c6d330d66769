"""The FCL half of the command layer ("C-API", chapter sections 6.2.1-6.2.2, 7.2).

Semantics (the package README has the full table): no queue; an accepted command answers
``FCL_OK`` with a command id at once and ends later with exactly one terminal PlatformEvent
(finished, failed or cancelled) carrying that id; another command while one runs answers
``FCL_BUSY``; a command in the wrong state ``FCL_NOT_ACCEPTED`` with the reason; ``cancel`` and
``emergency_brake`` always answer ``FCL_OK``. traj3d segments stream: while a path is flown a new
segment is the next one, or replaces the next one if that has not been started yet.
"""

from __future__ import annotations

import enum
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

from hdrc3_base.errors import ConfigError
from hdrc3_control.event_codec import command_id_of, decode, encode
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.pfc_state import FAILSAFE_PREFIX, FlightMode
from hdrc3_hcsm.event import WireEvent
from hdrc3_platform_server import limits as check
from hdrc3_platform_server.codes import EventKind, FclCode, FclCommand
from hdrc3_platform_server.commands import FCL
from hdrc3_platform_server.completion import CompletionEvent, EventSink
from hdrc3_platform_server.drc import DrcKernel, FlightState, PlatformState, RefusalKind
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.limits import FlightLimits
from hdrc3_platform_server.platform_status import PfcSample

PFC_REPLIES = frozenset(
    {
        "Cmd-Accepted-EV",
        "Cmd-Rejected-EV",
        "Cmd-Finished-EV",
        "Traj-Arrived-EV",
        "Request-Segment-EV",
        "Cmd-Failed-EV",
        "Cmd-Cancelled-EV",
    }
)

FINAL_REPLIES = frozenset(
    {"Cmd-Rejected-EV", "Cmd-Finished-EV", "Traj-Arrived-EV", "Cmd-Failed-EV", "Cmd-Cancelled-EV"}
)


@dataclass(frozen=True, slots=True)
class FclAnswer:
    """Immediate answer of one FCL call (FclReturn)."""

    code: FclCode
    reason: str = ""
    command_id: int = 0


@dataclass(frozen=True, slots=True)
class Segment:
    """One cubic segment in local ENU (chapter 5.3): end points, tangents, velocities."""

    start: tuple[float, float, float]
    end: tuple[float, float, float]
    start_direction: tuple[float, float, float]
    end_direction: tuple[float, float, float]
    velocity: float
    end_velocity: float

    def numbers(self) -> tuple[float, ...]:
        """The 14 numbers of the Traj3D-EV payload."""
        return (
            *self.start,
            *self.end,
            *self.start_direction,
            *self.end_direction,
            self.velocity,
            self.end_velocity,
        )


class _Seg(enum.Enum):
    SENT = "sent"
    FLOWN = "flown"
    DONE = "done"


@dataclass
class _Active:
    command: FclCommand
    command_id: int
    outcome: tuple[EventKind, str] | None = None
    left_idle: bool = False
    heard: bool = False
    """The PFC replied about this command (so the PFC run that replied knows it)."""
    # traj3d only: segment ids in order, their end velocities and progress
    segments: list[int] = field(default_factory=list)
    end_velocity: dict[int, float] = field(default_factory=dict)
    progress: dict[int, _Seg] = field(default_factory=dict)

    def open_ids(self) -> list[int]:
        """Ids still waiting for their terminal event."""
        if self.command is not FclCommand.TRAJ3D:
            return [self.command_id]
        return [s for s in self.segments if self.progress[s] is not _Seg.DONE]

    def queued(self, segment_id: int) -> bool:
        """A next segment sent to the PFC but not started (it may still be replaced)."""
        return (
            self.command is FclCommand.TRAJ3D
            and segment_id != self.segments[0]
            and self.progress.get(segment_id) is _Seg.SENT
        )

    def ending_ids(self) -> list[int]:
        """Ids whose final reply ends the whole command: a path ends with a started segment."""
        return [s for s in self.open_ids() if not self.queued(s)]

    def running_id(self) -> int:
        """Id of what the PFC executes now: for a path, the segment in flight (not the first)."""
        return next(reversed(self.ending_ids()), self.command_id)


class IdSource:
    """Command ids shared by FCL and PPCL: unique, never 0 (0 means "not accepted")."""

    def __init__(self, start: int = 1) -> None:
        self.start = max(1, start)
        self._next = self.start
        self._ids: Iterator[int] = itertools.count(self.start)

    def next(self) -> int:
        """A fresh id."""
        self._next = next(self._ids) + 1
        return self._next - 1

    def issued(self, command_id: int) -> bool:
        """True if this source (this run of the server) gave out ``command_id``."""
        return self.start <= command_id < self._next


RESTARTED_PFC = "control kernel (PFC) restarted: the command was lost; the aircraft hovers"
"""Reason of the terminal event of a command the PFC forgot in a restart."""
RESTARTED_DRC = "platform server restarted: the PFC stopped the command and hovers"
"""Reason of the terminal event of a command accepted before the platform server restarted."""
ENDED_WHILE_DOWN = "the PFC ended it while the platform server was restarting"
"""Reason prefix of the terminal event of a command whose final reply reached the new server."""
RESTARTED_LOST = "platform server restarted: the command's outcome was lost while it was down"
"""Reason of a journal's command of an earlier run that the PFC neither runs nor replied about
(its final reply went to the dead server; a pending PPCL command's too)."""
LOST_AFTER_S = 1.0
"""PFC seconds after the restarted server's first PFC report before such commands are ended: a
final reply the PFC held for the new server (sent while no server subscribed) comes first."""
_MODE_COMMANDS: dict[int, FclCommand] = {
    FlightMode.TAKEOFF: FclCommand.TAKEOFF,
    FlightMode.TRAJ3D: FclCommand.TRAJ3D,
    FlightMode.FLYTO: FclCommand.TRAJ3D_FLYTO,
    FlightMode.LAND: FclCommand.LAND,
    FlightMode.BRAKING: FclCommand.EMERGENCY_BRAKE,
}
"""The FCL command a PFC mode runs (the label of an orphan's terminal event; others "fcl")."""


class FlightCommandLayer:
    """Validates, answers and forwards FCL commands; turns PFC replies into PlatformEvents."""

    def __init__(
        self,
        kernel: DrcKernel,
        frame: WorldFrame,
        sink: EventSink,
        ids: IdSource,
        limits: FlightLimits | None = None,
        earlier: dict[int, str] | None = None,
    ) -> None:
        self.kernel = kernel
        self.frame = frame
        self.sink = sink
        self.ids = ids
        self.limits = limits or FlightLimits()
        self.current: _Active | None = None
        self.last_mode: int | None = None
        self.orphans: set[int] = set()
        """Commands of an earlier run of this server that the PFC reported and that were ended."""
        self.pfc_lost = False
        """The launcher saw the PFC die while a command ran: the command ended then, and the
        Flight automaton goes back to Idle once the new PFC is heard (nothing is sent to a dead
        PFC: an event for it would wait in the transport and reach the new one out of turn)."""
        self.earlier = earlier
        """Id -> command of the commands earlier runs left open (their journal, see
        :mod:`~hdrc3_platform_server.journal`); None without a journal: any id this run did not
        give out is taken for one."""
        self._first_report: float | None = None
        kernel.listeners.append(self)

    # --- helpers --------------------------------------------------------------------------
    def _emit(self, command_id: int, command: FclCommand, kind: EventKind, reason: str) -> None:
        self.sink(CompletionEvent(command_id, command.label, kind, reason, self.kernel.status.now))

    def _sync_ids(self) -> None:
        cur = self.current
        self.kernel.current_ids = frozenset(cur.ending_ids()) if cur else frozenset()

    def _end_current(self, kind: EventKind, reason: str) -> None:
        cur = self.current
        if cur is None:
            return
        for cid in cur.open_ids():
            if cur.queued(cid) and kind is EventKind.FINISHED:
                self._emit(cid, cur.command, EventKind.CANCELLED, "the path ended before it")
            else:
                self._emit(cid, cur.command, kind, reason)
        self.current = None
        self._sync_ids()

    def busy_with(self) -> str | None:
        """Description of the command in progress, or None when idle."""
        cur = self.current
        if cur is None:
            return None
        return f"{cur.command.label} (command {cur.command_id}) is being executed"

    def _start(self, command: FclCommand, numbers: Sequence[float], now: float) -> FclAnswer:
        """Offer the command to the DRC automaton: its transitions decide the answer."""
        spec = FCL[command]
        cid = self.ids.next()
        self.kernel.post(spec.api_event, encode(cid, numbers))
        if spec.api_event in self.kernel.step(now).unconsumed:
            refusal = self.kernel.refusal(spec.api_event, command.label)
            if refusal.kind is RefusalKind.BUSY:
                return FclAnswer(FclCode.BUSY, self.busy_with() or refusal.reason)
            return FclAnswer(FclCode.NOT_ACCEPTED, refusal.reason)
        active = _Active(command, cid)
        if command is FclCommand.TRAJ3D:
            active.segments.append(cid)
            active.end_velocity[cid] = numbers[-1]
            active.progress[cid] = _Seg.SENT
        self.current = active
        self._sync_ids()
        return FclAnswer(FclCode.OK, "", cid)

    # --- the commands ---------------------------------------------------------------------
    def submit(self, command: FclCommand, args: Sequence[float], now: float) -> FclAnswer:
        """Answer one FCL call at DRC time ``now``; ``args`` as the service defines them."""
        values, reason = check.arguments(command.label, FCL[command].names, args)
        if reason is None:
            numbers, reason = self._arguments(command, values)
        if reason is not None:
            return FclAnswer(FclCode.NOT_ACCEPTED, reason)
        if command is FclCommand.CANCEL:
            return self._cancel(now)
        if command is FclCommand.EMERGENCY_BRAKE:
            return self._brake(now)
        cur = self.current
        if command is FclCommand.TRAJ3D and cur is not None and cur.command is command:
            return self._next_segment(cur, numbers, now)
        if cur is not None:
            # the DRC automaton takes a command during an emergency brake (its flight state is
            # the brake's target, hovering); the brake still owes its outcome: busy until then
            return FclAnswer(FclCode.BUSY, self.busy_with() or "a command is being executed")
        return self._start(command, numbers, now)

    def _cancel(self, now: float) -> FclAnswer:
        cid = self.ids.next()
        self._end_current(EventKind.CANCELLED, f"cancelled by fcl_cancel (command {cid})")
        self.kernel.post(FCL[FclCommand.CANCEL].api_event, encode(cid))
        self.kernel.step(now)
        self._emit(cid, FclCommand.CANCEL, EventKind.FINISHED, "")
        return FclAnswer(FclCode.OK, "", cid)

    def _brake(self, now: float) -> FclAnswer:
        cid = self.ids.next()
        self._end_current(EventKind.CANCELLED, f"emergency brake (command {cid})")
        platform = self.kernel.platform()
        if platform is not PlatformState.AIR:
            why = (
                "manual flight mode: the pilot flies, nothing to brake"
                if platform is PlatformState.MANUAL
                else "not flying: nothing to brake"
            )
            self.kernel.post(FCL[FclCommand.CANCEL].api_event, encode(cid))
            self.kernel.step(now)
            self._emit(cid, FclCommand.EMERGENCY_BRAKE, EventKind.FINISHED, why)
            return FclAnswer(FclCode.OK, why, cid)
        self.current = _Active(FclCommand.EMERGENCY_BRAKE, cid)
        self._sync_ids()
        self.kernel.post(FCL[FclCommand.EMERGENCY_BRAKE].api_event, encode(cid))
        self.kernel.step(now)
        return FclAnswer(FclCode.OK, "", cid)

    def _next_segment(self, cur: _Active, numbers: Sequence[float], now: float) -> FclAnswer:
        """A further segment of the path in progress (Figures 17-18)."""
        last = cur.segments[-1]
        replace = len(cur.segments) > 1 and cur.progress[last] is _Seg.SENT
        if not replace and cur.end_velocity[last] == 0.0:
            return FclAnswer(
                FclCode.BUSY,
                f"the path ends with segment {last} (end velocity 0); wait for it to finish",
            )
        cid = self.ids.next()
        event = FCL[FclCommand.TRAJ3D].api_event
        self.kernel.post(event, encode(cid, numbers))
        if event in self.kernel.step(now).unconsumed:  # the path is over: Flight left Path
            return FclAnswer(FclCode.BUSY, self.busy_with() or "the path has ended")
        # The PFC ends a replaced segment itself (Cmd-Cancelled-EV "replaced by segment N",
        # Traj3D C.18) before it accepts the new one; should only the new one's Cmd-Accepted-EV or
        # Request-Segment-EV come, the old one is cancelled then, with the same reason. If the PFC
        # refuses the replacement, the old one stays queued.
        cur.segments.append(cid)
        cur.end_velocity[cid] = numbers[-1]
        cur.progress[cid] = _Seg.SENT
        self._sync_ids()
        return FclAnswer(FclCode.OK, "replaces the next segment" if replace else "", cid)

    # --- arguments ------------------------------------------------------------------------
    def _arguments(
        self, command: FclCommand, a: tuple[float, ...]
    ) -> tuple[tuple[float, ...], str | None]:
        """Command-specific checks of finite arguments; the numbers sent to the PFC."""
        lim = self.limits
        if command in (FclCommand.LAND, FclCommand.YAW):
            (heading,) = a
            bad = check.angle("heading", heading)
            return ((heading % math.tau,) if bad is None else ()), bad
        if command is FclCommand.CLIMB:
            (altitude,) = a
            up = altitude - self.frame.altitude
            pfc = self.kernel.status.pfc
            east, north = (pfc.position_enu[0], pfc.position_enu[1]) if pfc else (0.0, 0.0)
            return (up,), check.position(self.frame, lim, east, north, up, "climb target")
        if command is FclCommand.TRAJ3D_FLYTO:
            lon, lat, alt, vel = a
            bad = (
                check.wgs84(lon, lat) or check.altitude(self.frame, alt) or check.velocity(lim, vel)
            )
            if bad:
                return (), bad
            e, n, u = self.frame.to_enu(lon, lat, alt)
            return (e, n, u, vel), check.position(self.frame, lim, e, n, u, "fly-to target")
        if command is FclCommand.TRAJ3D:
            seg = Segment(
                (a[0], a[1], a[2]),
                (a[3], a[4], a[5]),
                (a[6], a[7], a[8]),
                (a[9], a[10], a[11]),
                a[12],
                a[13],
            )
            return seg.numbers(), self._segment_problem(seg)
        return (), None

    def _segment_problem(self, seg: Segment) -> str | None:
        lim = self.limits
        bad = check.velocity(lim, seg.velocity)
        if bad:
            return bad
        if not 0.0 <= seg.end_velocity <= seg.velocity:
            return f"end velocity {seg.end_velocity:g} m/s must be within [0, velocity]"
        for point, what in ((seg.start, "segment start"), (seg.end, "segment end")):
            bad = check.position(self.frame, lim, *point, what)
            if bad:
                return bad
        if math.dist(seg.start, seg.end) > lim.max_segment_length:
            return f"segment longer than {lim.max_segment_length:g} m"
        try:  # the PFC's own definition of a flyable cubic segment (chord, tangents)
            PathSegment(
                seg.start,
                seg.end,
                seg.start_direction,
                seg.end_direction,
                seg.velocity,
                seg.end_velocity,
            )
        except ConfigError as exc:
            return str(exc).removeprefix("segment 0: ")
        return None

    # --- replies from the PFC -------------------------------------------------------------
    def on_wire(self, event: WireEvent, now: float) -> None:
        """Correlate a PFC reply with the command in progress (older ids are ignored)."""
        if event.name == "PFC-Fault-EV":
            # plain UTF-8 text (no id): a navigation or sensor fault the PFC is handling
            text = event.data.decode("utf-8", errors="replace").strip() or "fault"
            if text.startswith(FAILSAFE_PREFIX):
                # the PFC's own action (brake + hover, emergency landing, its end): no command's
                # event; the interrupted command gets its own Cmd-Failed-EV with this reason
                self.sink(
                    CompletionEvent(0, "pfc_failsafe", EventKind.INFO, text, self.kernel.status.now)
                )
                return
            cur = self.current
            self.sink(
                CompletionEvent(
                    cur.running_id() if cur else 0,
                    cur.command.label if cur else "pfc_fault",
                    EventKind.INFO,
                    f"PFC fault: {text}",
                    self.kernel.status.now,
                )
            )
            return
        if event.name not in PFC_REPLIES:
            return
        cur = self.current
        cid = command_id_of(event.data)  # 0 for a short payload: never an open id
        if event.name in FINAL_REPLIES:
            # a command of the server's previous run ended while it was down: its final reply
            # was held by the PFC's transport until this run subscribed
            self._orphan(cid, "fcl", now, *_final_outcome(event))
        if cur is None or cid not in cur.open_ids():
            return
        cur.heard = True
        name = event.name
        if name == "Request-Segment-EV":
            self._segment_started(cur, cid)
        elif name == "Cmd-Accepted-EV":
            # the PFC's note, if any (fcl_land: which aid it plans on, and why)
            note = _reason(event.data, "")
            accepted = f"accepted by the PFC: {note}" if note else "accepted by the PFC"
            self._emit(cid, cur.command, EventKind.INFO, accepted)
            if cur.queued(cid):
                self._replaced_before(cur, cid)
        elif cur.queued(cid) and name in ("Cmd-Rejected-EV", "Cmd-Failed-EV", "Cmd-Cancelled-EV"):
            # a reply about a next segment only: the path goes on with the segment in flight
            cur.progress[cid] = _Seg.DONE
            if name == "Cmd-Cancelled-EV":
                self._emit(cid, cur.command, EventKind.CANCELLED, _reason(event.data, "cancelled"))
            else:
                prefix = "rejected by the PFC: " if name == "Cmd-Rejected-EV" else ""
                self._emit(
                    cid, cur.command, EventKind.FAILED, prefix + _reason(event.data, "failed")
                )
        elif (
            name == "Cmd-Finished-EV"
            and cur.command is FclCommand.TRAJ3D
            and cid != cur.segments[-1]
        ):
            # the PFC left this segment for the next one, which is now the one in flight (the
            # last segment of a path may get no Request-Segment-EV: nothing follows it)
            self._segment_started(cur, cur.segments[cur.segments.index(cid) + 1], request=False)
        elif name == "Traj-Arrived-EV" and cur.queued(cid):
            self._segment_started(cur, cid, request=False)
            cur.outcome = cur.outcome or (EventKind.FINISHED, "")
        elif name in ("Cmd-Finished-EV", "Traj-Arrived-EV"):
            # the PFC's note, if any (fcl_land: which aid it landed on)
            cur.outcome = cur.outcome or (EventKind.FINISHED, _reason(event.data, ""))
        elif name == "Cmd-Cancelled-EV":
            cur.outcome = (EventKind.CANCELLED, _reason(event.data, "cancelled by the PFC"))
        elif name == "Cmd-Rejected-EV":
            cur.outcome = (EventKind.FAILED, "rejected by the PFC: " + _reason(event.data, "?"))
        else:
            cur.outcome = (EventKind.FAILED, _reason(event.data, "failed in the PFC"))

    def _segment_started(self, cur: _Active, segment_id: int, *, request: bool = True) -> None:
        """``segment_id`` is in flight: earlier segments are done; forward the PFC's request."""
        if cur.command is not FclCommand.TRAJ3D or segment_id not in cur.progress:
            return
        if cur.progress[segment_id] is not _Seg.SENT and not request:
            return
        self._replaced_before(cur, segment_id)
        index = cur.segments.index(segment_id)
        for earlier in cur.segments[:index]:
            if cur.progress[earlier] is not _Seg.DONE:
                cur.progress[earlier] = _Seg.DONE
                self._emit(earlier, FclCommand.TRAJ3D, EventKind.FINISHED, "segment flown")
        cur.progress[segment_id] = _Seg.FLOWN
        self._sync_ids()
        if request:
            self._emit(
                segment_id, FclCommand.TRAJ3D, EventKind.SEGMENT_REQUEST, "send the next segment"
            )

    def _replaced_before(self, cur: _Active, segment_id: int) -> None:
        """Cancel the queued segments sent before ``segment_id``: the PFC replaced them."""
        for earlier in cur.segments[: cur.segments.index(segment_id)]:
            if cur.queued(earlier):
                cur.progress[earlier] = _Seg.DONE
                self._emit(
                    earlier,
                    FclCommand.TRAJ3D,
                    EventKind.CANCELLED,
                    f"replaced by segment {segment_id}",
                )
        self._sync_ids()

    # --- restarts (docs/realtime_events.md, "Restarts") -----------------------------------------
    def _stop_pfc(self) -> None:
        """Put the Flight automaton back in Idle; the PFC is told to cancel (it then hovers)."""
        self.kernel.post(FCL[FclCommand.CANCEL].api_event, encode(self.ids.next()))

    def _orphan(
        self,
        command_id: int,
        label: str,
        now: float,
        kind: EventKind = EventKind.FAILED,
        reason: str = RESTARTED_DRC,
    ) -> bool:
        """End a command of an earlier run of this server once; True if it was news.

        With a journal only the commands it lists end (the others ended before the restart).
        """
        if not command_id or self.ids.issued(command_id) or command_id in self.orphans:
            return False
        if self.earlier is not None:
            if command_id not in self.earlier:
                return False
            label = self.earlier[command_id] or label
        self.orphans.add(command_id)
        self.sink(CompletionEvent(command_id, label, kind, reason, now))
        return True

    def _end_lost(self, sample: PfcSample, now: float) -> None:
        """End the journal's commands the PFC neither runs nor replied about (once)."""
        if self.earlier is None:
            return
        if self._first_report is None:
            self._first_report = sample.pfc_time
        if sample.pfc_time - self._first_report < LOST_AFTER_S:
            return
        for command_id in sorted(self.earlier.keys() - self.orphans - {sample.command_id}):
            self._orphan(command_id, "fcl", now, EventKind.FAILED, RESTARTED_LOST)

    def on_restart(self, computer: str, now: float) -> None:
        """A restarted PFC forgot the command it replied about: it ends FAILED, Flight is idle.

        The notice comes with the new PFC's first events, before they are correlated: a
        command it is about to reply to (sent after the restart) has not been heard yet.
        """
        if computer != "PFC":
            return
        if self.pfc_lost or (self.current is not None and self.current.heard):
            self._end_current(EventKind.FAILED, RESTARTED_PFC)
            self._stop_pfc()
            self.pfc_lost = False

    def on_kernel_exit(self, reason: str, now: float) -> None:
        """The PFC process died (the launcher saw it): the running command ends FAILED now.

        The Flight automaton keeps its state (new commands are answered busy) until the new PFC
        is heard (:meth:`on_restart`, or its boot mode in :meth:`resync`), which puts it back in
        Idle and tells the new PFC to cancel, as for a restart the launcher did not report.
        """
        if self.current is not None:
            self._end_current(EventKind.FAILED, reason)
            self.pfc_lost = True

    def on_world_reset(self, reason: str, now: float) -> None:
        """The simulated world started over (sim/WORLD_SIM.md): the running command ends FAILED."""
        if self.current is not None:
            self._end_current(EventKind.FAILED, f"simulation reset: {reason}")
            self._stop_pfc()
            self.kernel.step(now)

    def resync(self, sample: PfcSample) -> None:
        """Compare the PFC's report (mode, command id) with the command this server runs.

        A command id this run of the server never gave out belongs to a run before a restart:
        it ends FAILED (once) and the PFC is told to cancel it. A PFC back in its boot mode
        while a command runs has restarted (also when none of its events arrived yet).
        """
        command = _MODE_COMMANDS.get(sample.mode)
        label = command.label if command is not None else "fcl"
        now = max(self.kernel.status.now, sample.received)
        if self._orphan(sample.command_id, label, now) and self.current is None:
            self._stop_pfc()
        self._end_lost(sample, now)
        if sample.mode == FlightMode.BOOT and (self.current is not None or self.pfc_lost):
            self._end_current(EventKind.FAILED, RESTARTED_PFC)
            self._stop_pfc()
            self.pfc_lost = False

    def after_step(self, now: float) -> None:
        """End the command once the Flight automaton is back in Idle."""
        cur = self.current
        if cur is None:
            return
        if self.kernel.flight() is not FlightState.IDLE:
            cur.left_idle = True
            return
        if not cur.left_idle and cur.outcome is None:
            cur.outcome = (EventKind.FAILED, "the DRC automaton did not take the command")
        kind, reason = cur.outcome or (EventKind.FINISHED, "")
        self._end_current(kind, reason)


def _final_outcome(event: WireEvent) -> tuple[EventKind, str]:
    """Terminal kind and reason of a final reply that reached a restarted server."""
    if event.name in ("Cmd-Finished-EV", "Traj-Arrived-EV"):
        return EventKind.FINISHED, ENDED_WHILE_DOWN
    if event.name == "Cmd-Cancelled-EV":
        return EventKind.CANCELLED, f"{ENDED_WHILE_DOWN}: {_reason(event.data, 'cancelled')}"
    prefix = "rejected by the PFC: " if event.name == "Cmd-Rejected-EV" else ""
    return EventKind.FAILED, f"{ENDED_WHILE_DOWN}: {prefix}{_reason(event.data, 'failed')}"


def _reason(data: bytes, default: str) -> str:
    # text with invalid UTF-8 is still shown (replaced bytes): it only names a reason
    return decode(data, 0, with_reason=True).reason.strip() or default
