"""``ppcl_hook``: the winch and electromagnet hook that carries boxes (chapter section 11.1.2).

The chapter's AV picks up a box by hovering above it, lowering the device, attaching to the box
and raising the device. Each of these is one PPCL-style command here (``PpclHook.srv``): it is
validated and answered at once (``PPCL_OK`` with an id, or ``PPCL_NOT_ACCEPTED`` with a reason)
and ends with exactly one PlatformEvent, decided from the hook's own ``carrying`` sensor
(HookState: magnet, held object's tag, cable length, winch state, cable tension):

- LOWER finishes at the commanded cable length, or earlier when the cable goes slack (the hook
  rests on something): the winch is then stopped where it is.
- ATTACH energises the magnet; it finishes when an object is held, fails when it is another
  object than the one asked for (wrong box) or when nothing is held within ``attach_time``
  (the magnet is switched off again).
- RAISE winds in; it fails when the winch stalls (load too heavy) or the held load is lost.
- RELEASE de-energises; it finishes when nothing is held.

The hook is driven by the DRC directly (its set-point topic), not through the perception kernel:
it is a plain actuator without a control mode. A newer hook command replaces a running one
(CANCELLED), as PPCL modes do. Deadlines assume a winch of at least ``min_winch_speed``.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass

from hdrc3_platform_server.codes import EventKind, PpclCode
from hdrc3_platform_server.completion import CompletionEvent, EventSink
from hdrc3_platform_server.fcl_api import IdSource
from hdrc3_platform_server.ppcl_api import PpclAnswer

LABEL = "ppcl_hook"
"""PlatformEvent.command of every hook command."""
MAX_OBJECT_ID = 64


class HookAction(enum.IntEnum):
    """PpclHook.ACTION_*."""

    LOWER = 0
    ATTACH = 1
    RAISE = 2
    RELEASE = 3


class Winch(enum.IntEnum):
    """HookState.WINCH_*."""

    STOPPED = 0
    LOWERING = 1
    RAISING = 2
    STALLED = 3


@dataclass(frozen=True, slots=True)
class HookSample:
    """One sample of the carrying sensor (HookState), stamped in DRC time."""

    time: float
    carrying: bool
    object_id: str
    magnet: bool
    winch: int
    cable_length: float
    tension: float


@dataclass(frozen=True, slots=True)
class HookSetpoint:
    """What the DRC commands the hook (HookCommand)."""

    cable_length: float = 0.0
    magnet: bool = False


@dataclass(frozen=True, slots=True)
class HookLimits:
    """Checks and deadlines of the hook commands."""

    max_cable: float = 20.0
    """m of cable on the drum."""
    stowed_cable: float = 0.15
    """m: at most this much cable out is a wound-in hook (a raise to less ends there)."""
    length_tolerance: float = 0.03
    """m: a cable this close to its target has arrived."""
    slack_tension: float = 3.0
    """N: below this the cable is slack (the hook itself weighs more)."""
    slack_time: float = 1.0
    """s of slack cable before LOWER ends resting on something."""
    attach_time: float = 3.0
    """s for the magnet to grip."""
    release_time: float = 2.0
    """s for the magnet to let go."""
    stall_time: float = 3.0
    """s of a stalled winch before RAISE fails: a load that comes off the ground stalls the
    drum for a moment; the execution monitor's lift formulas (``default.monitors``) report a
    stall of 1 s first, so recovery knows the load was too heavy (section 9.3)."""
    min_winch_speed: float = 0.3
    """m/s the deadlines of LOWER and RAISE assume (plus ``margin``)."""
    margin: float = 5.0
    """s added to every winch deadline."""
    stale_after: float = 2.0
    """s without a carrying sample before commands are refused."""


@dataclass(slots=True)
class _Pending:
    command_id: int
    action: HookAction
    length: float
    object_id: str
    deadline: float
    was_carrying: bool
    since: float | None = None
    """Start of the current slack (LOWER) or stall (RAISE) period."""


class HookCommandLayer:
    """Validates, answers and finishes hook commands from the carrying sensor's samples."""

    def __init__(
        self,
        sink: EventSink,
        ids: IdSource,
        send: Callable[[HookSetpoint], None],
        limits: HookLimits | None = None,
    ) -> None:
        self.sink = sink
        self.ids = ids
        self.send = send
        self.limits = limits or HookLimits()
        self.latest: HookSample | None = None
        self.setpoint = HookSetpoint()
        self.pending: _Pending | None = None

    # --- commands -------------------------------------------------------------------------
    def submit(self, action: int, length: float, object_id: str, now: float) -> PpclAnswer:
        """Answer one ppcl_hook call at DRC time ``now``."""
        bad = self._problem(action, length, object_id, now)
        if bad is not None:
            return PpclAnswer(PpclCode.NOT_ACCEPTED, bad)
        act = HookAction(action)
        sample = self.latest
        assert sample is not None  # _problem refuses without a fresh sample
        cid = self.ids.next()
        if self.pending is not None:
            old = self.pending
            self.pending = None
            reason = f"replaced by {LABEL} {act.name.lower()} (command {cid})"
            self._end(old, EventKind.CANCELLED, reason, now)
        lim = self.limits
        here = sample.cable_length
        if act is HookAction.LOWER or act is HookAction.RAISE:
            setpoint = HookSetpoint(length, self.setpoint.magnet)
            deadline = now + abs(length - here) / lim.min_winch_speed + lim.margin
        elif act is HookAction.ATTACH:
            setpoint = HookSetpoint(self.setpoint.cable_length, True)
            deadline = now + lim.attach_time
        else:
            setpoint = HookSetpoint(self.setpoint.cable_length, False)
            deadline = now + lim.release_time
        self.pending = _Pending(cid, act, length, object_id, deadline, sample.carrying)
        self._command(setpoint)
        return PpclAnswer(PpclCode.OK, "", cid)

    def _problem(self, action: int, length: float, object_id: str, now: float) -> str | None:
        try:
            act = HookAction(action)
        except ValueError:
            return f"unknown hook action {action} (0 lower, 1 attach, 2 raise, 3 release)"
        if len(object_id) > MAX_OBJECT_ID or not object_id.isprintable():
            return f"object id must be at most {MAX_OBJECT_ID} printable characters"
        sample = self.latest
        if sample is None or now - sample.time > self.limits.stale_after:
            return "no data from the hook's carrying sensor (sensors/carrying): is world_sim up?"
        top = self.limits.max_cable
        if act in (HookAction.LOWER, HookAction.RAISE):
            if not (math.isfinite(length) and 0.0 <= length <= top):
                return f"cable length must be finite, within [0, {top:g}] m, got {length:g}"
            here = sample.cable_length
            if act is HookAction.LOWER and length < here - self.limits.length_tolerance:
                return f"lower to {length:.2f} m: {here:.2f} m of cable are out already (raise)"
            if act is HookAction.RAISE and length > here + self.limits.length_tolerance:
                return f"raise to {length:.2f} m: only {here:.2f} m of cable are out (lower)"
        if act is HookAction.ATTACH and sample.carrying:
            return f"the hook holds {sample.object_id!r} already (release it first)"
        return None

    def _command(self, setpoint: HookSetpoint) -> None:
        self.setpoint = setpoint
        self.send(setpoint)

    def _end(self, p: _Pending, kind: EventKind, reason: str, now: float) -> None:
        self.sink(CompletionEvent(p.command_id, LABEL, kind, reason, now))

    def _finish(self, kind: EventKind, reason: str, now: float) -> None:
        p = self.pending
        if p is None:
            return
        self.pending = None
        self._end(p, kind, reason, now)

    # --- sensor and clock -----------------------------------------------------------------
    def on_sample(self, sample: HookSample) -> None:
        """A carrying-sensor sample: decide the running command's outcome."""
        self.latest = sample
        p = self.pending
        if p is None:
            return
        lim = self.limits
        now = sample.time
        goal = max(p.length, lim.stowed_cable) if p.action is HookAction.RAISE else p.length
        if p.action is HookAction.RAISE:
            arrived = sample.cable_length <= goal + lim.length_tolerance
        else:
            arrived = abs(sample.cable_length - goal) <= lim.length_tolerance
        if p.action is HookAction.LOWER:
            if arrived and sample.winch == Winch.STOPPED:
                self._finish(EventKind.FINISHED, "", now)
            elif self._lasted(p, sample.tension < lim.slack_tension, now, lim.slack_time):
                self._command(HookSetpoint(sample.cable_length, self.setpoint.magnet))
                reason = f"the hook rests on something at {sample.cable_length:.2f} m of cable"
                self._finish(EventKind.FINISHED, reason, now)
        elif p.action is HookAction.ATTACH:
            if sample.carrying and p.object_id and sample.object_id != p.object_id:
                reason = f"wrong object: the magnet holds {sample.object_id!r}, not {p.object_id!r}"
                self._finish(EventKind.FAILED, reason, now)
            elif sample.carrying:
                self._finish(EventKind.FINISHED, sample.object_id, now)
        elif p.action is HookAction.RAISE:
            if p.was_carrying and not sample.carrying:
                self._finish(EventKind.FAILED, "the load was lost while raising", now)
            elif self._lasted(p, sample.winch == Winch.STALLED, now, lim.stall_time):
                self._command(HookSetpoint(sample.cable_length, self.setpoint.magnet))
                reason = f"winch stalled at {sample.tension:.0f} N: the load is too heavy"
                self._finish(EventKind.FAILED, reason, now)
            elif arrived and sample.winch == Winch.STOPPED:
                self._finish(EventKind.FINISHED, "", now)
        elif not sample.carrying:
            self._finish(EventKind.FINISHED, "", now)
        self.tick(now)

    @staticmethod
    def _lasted(p: _Pending, condition: bool, now: float, duration: float) -> bool:
        """True once ``condition`` has held for ``duration`` s (tracked in ``p.since``)."""
        if not condition:
            p.since = None
            return False
        if p.since is None:
            p.since = now
        return now - p.since >= duration

    def tick(self, now: float) -> None:
        """Fail a command past its deadline."""
        p = self.pending
        if p is None or now < p.deadline:
            return
        if p.action is HookAction.ATTACH:
            self._command(HookSetpoint(self.setpoint.cable_length, False))
            self._finish(EventKind.FAILED, "the magnet gripped nothing", now)
        elif p.action is HookAction.RELEASE:
            self._finish(EventKind.FAILED, "the magnet did not let go", now)
        else:
            self._finish(EventKind.FAILED, f"the winch did not reach {p.length:.2f} m", now)

    def on_world_reset(self, reason: str, now: float) -> None:
        """The simulated world started over: a running command fails; the set-point is stowed."""
        self._finish(EventKind.FAILED, f"simulation reset: {reason}", now)
        self.setpoint = HookSetpoint()
        self.latest = None
