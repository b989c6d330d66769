"""A planned flight (§7, Figure 18): plan, stream the segments, replan when the world changes.

The fly-to executor asks the path planner for a collision-free path of cubic segments from where
the aircraft is, sends the first segment as an FCL ``traj3d`` command and each next one when
path following asks for it (Request-Segment, §7.2). Interior waypoints where no cubic fits end
with zero velocity: the aircraft arrives and hovers there, and the rest starts as a new path.

While it flies, the executor watches the planner's runtime world model
(:class:`~hdrc3_navigation.runtime_world.RuntimeWorld`). When a no-fly zone or an obstacle
appears that the part of the path not yet flown would enter:

- if only segments after the one in flight conflict, it replans from the end of the segment in
  flight - where the aircraft will be when the next segment is due - leaving with that
  segment's end tangent, and sends the new first segment in place of the queued one (the PFC
  replaces a queued, not yet flown segment). The PFC always has a queued segment while the
  replan runs, so it never reaches its safety-braking point for want of one;
- if the segment in flight itself conflicts, or no path joins it, it stops it (the aircraft
  brakes and hovers where it is) and replans from the hover point.

A flight that cannot be planned, or whose path becomes invalid with no new path, fails its node
with the planner's reason.
"""

from __future__ import annotations

import math
from collections.abc import Generator
from dataclasses import dataclass, field

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.planner import MIN_FLIGHT_M, PlanRequest, PlanResult, PlanStatus
from hdrc3_platform_server.codes import FclCommand
from hdrc3_tst.executor import (
    SUCCEEDED,
    ActionContext,
    Progress,
    Status,
    failed,
    flight_bound,
)
from hdrc3_tst.executor_steps import fly_to
from hdrc3_tst.navigation_port import NavigationPort
from hdrc3_tst.platform_port import Command, CommandState

Steps = Generator[None, None, Status]
Vec3 = tuple[float, float, float]

PLAN_TIMEOUT_S = 2.0
"""The planner's own time budget per query (wall seconds)."""
ANSWER_WAIT_S = 60.0
"""Mission seconds to wait for the planner's answer (a path planner node may still start)."""
BUSY_RETRY_S = 20.0
"""Mission seconds a path start may be refused BUSY after a stop (the PFC is still braking)."""
MAX_REPLANS = 20
"""Replans of one flight before it gives up (a world changing faster than it can fly)."""
HOLD_RADIUS = 0.5
HOLD_S = 2.0
"""After a stop, the aircraft holds once it moves less than HOLD_RADIUS m in HOLD_S s."""
SETTLE_BOUND_S = 30.0
"""Mission seconds a stop may take to come to a hover."""
RECHECK = -1
"""A revision no world model has: the remaining path is checked again at the next tick."""
CLIMB_OUT_M = 12.0
"""m above the ground a flight that starts too low for the path planner (it keeps a margin from
the ground: the hover over a load a recovery left the aircraft in) first climbs straight up
to, clear of the planner's 6 m margin with a load hanging on the hook's carrying cable."""
CLIMB_OUT_SPEED = 2.0
"""m/s of that climb."""


def segment_args(segment: PathSegment) -> dict[str, float]:
    """The FCL ``traj3d`` arguments of a segment (the registry's field names)."""
    args: dict[str, float] = {"velocity": segment.target_velocity}
    args["end_velocity"] = segment.end_velocity
    for name, vec in (
        ("start", segment.start),
        ("end", segment.end),
        ("start_direction", segment.start_direction),
        ("end_direction", segment.end_direction),
    ):
        args.update({f"{name}_{axis}": float(v) for axis, v in zip("xyz", vec, strict=True)})
    return args


@dataclass
class _Sent:
    """A segment sent to the PFC and its command handle."""

    segment: PathSegment
    command: Command
    since: float
    """Mission time it was sent (queued) or taken into flight."""


@dataclass
class PlannedFlight:
    """One planned flight to ``goal`` at ``speed``; :meth:`run` is the executor's generator."""

    ctx: ActionContext
    nav: NavigationPort
    goal: Vec3
    speed: float
    todo: list[PathSegment] = field(default_factory=list)
    """Segments not sent yet."""
    flying: _Sent | None = None
    """The segment path following flies now."""
    queued: _Sent | None = None
    """Sent, not yet flown: the PFC switches to it at the end of :attr:`flying`."""
    revision: int = 0
    """World model revision the remaining path was last checked against."""
    replans: int = 0
    replaced: _Sent | None = None
    """The queued segment a replacement was sent for, until the PFC took the replacement."""

    def run(self) -> Steps:
        """Plan from the aircraft's position, then stream, watch and replan until arrival."""
        self.revision = self.nav.world().revision
        start = self._position()
        if start is None:
            return failed("no Data Interface sample to plan from")
        if math.dist(start, self.goal) < MIN_FLIGHT_M:  # already there: nothing to fly
            return SUCCEEDED
        result = yield from self._query(start, None)
        ground = self.ctx.frame.ground_up(start[0], start[1])
        if result.status is PlanStatus.START_IN_OBSTACLE and start[2] < ground + CLIMB_OUT_M:
            up = (start[0], start[1], ground + CLIMB_OUT_M)
            climbed = yield from fly_to(self.ctx, up, min(self.speed, CLIMB_OUT_SPEED))
            if climbed.progress is not Progress.SUCCEEDED:
                return climbed
            result = yield from self._query(self._position() or up, None)
        no_path = self._accept(result)
        if no_path is not None:
            return no_path
        while True:
            refused = self._refused_replacement()
            if refused is not None:
                outcome = yield from self._stop_and_replan(refused)
                if outcome is not None:
                    return outcome
                continue
            self._follow_progress()
            problem = self._command_problem()
            if problem is not None:
                return problem
            if self.nav.world().revision != self.revision:
                outcome = yield from self._world_changed()
                if outcome is not None:
                    return outcome
            if self.flying is None and self.queued is None:
                if not self.todo:
                    return self._arrived()
                outcome = yield from self._start_leg()
                if outcome is not None:
                    return outcome
            elif self._next_wanted():
                self.queued = self._send(self.todo.pop(0))
            yield

    # --- progress of the PFC ---------------------------------------------------------------
    def _follow_progress(self) -> None:
        """Move queued -> flying when path following took it; drop a flown, finished leg."""
        queued, flying = self.queued, self.flying
        if queued is not None and (
            queued.command.segment_requested
            # the first segment of a path flies once accepted; a next one when its predecessor
            # is flown (the last segment of a path asks for no successor)
            or (flying is None and queued.command.state is not CommandState.SENT)
            or (flying is not None and flying.command.state is CommandState.FINISHED)
        ):
            self.flying, self.queued = _Sent(queued.segment, queued.command, self.ctx.now), None
        flying = self.flying
        if (
            flying is not None
            and self.queued is None
            and flying.command.state is CommandState.FINISHED
        ):
            self.flying = None  # the leg arrived (its last segment ends at rest)

    def _refused_replacement(self) -> str | None:
        """The PFC refused a replacement: the old segment, which conflicts, is still queued.

        The Platform Server answers a replacement OK at once; the PFC's verdict follows: the old
        segment ends CANCELLED ("replaced by segment N") when it took the new one, the new one
        ends FAILED ("rejected by the PFC: ...") when it did not.
        """
        queued, old = self.queued, self.replaced
        if old is None or queued is None:
            return None
        if old.command.state.ended:
            self.replaced = None  # taken: the new segment is the queued one
        elif queued.command.state is CommandState.FAILED:
            self.queued, self.replaced = old, None  # the PFC still has the old one queued
            return f"the replacement of the queued segment was refused ({queued.command.reason})"
        return None

    def _command_problem(self) -> Status | None:
        """A failed segment, or one flown far longer than it should take, fails the flight."""
        for sent in (self.flying, self.queued):
            if sent is not None and sent.command.state is CommandState.FAILED:
                return failed(f"segment {sent.command.command_id}: {sent.command.reason}")
        flying = self.flying
        if flying is not None:
            seg = flying.segment
            bound = flight_bound(seg.arc_length(), seg.target_velocity)
            if self.ctx.now - flying.since > bound:
                self.ctx.platform.stop(flying.command, f"segment not flown in {bound:.0f} s")
                return failed(f"a segment was not flown in {bound:.0f} s")
        return None

    def _next_wanted(self) -> bool:
        """Path following flies a segment that asked for its successor, and none is queued."""
        flying = self.flying
        return (
            flying is not None
            and self.queued is None
            and bool(self.todo)
            and flying.segment.end_velocity > 0.0
            and flying.command.segment_requested
        )

    def _send(self, segment: PathSegment) -> _Sent:
        command = self.ctx.send(FclCommand.TRAJ3D, **segment_args(segment))
        return _Sent(segment, command, self.ctx.now)

    def _start_leg(self) -> Generator[None, None, Status | None]:
        """Send the first segment of a leg; retried while the PFC is still busy braking."""
        segment = self.todo.pop(0)
        deadline = self.ctx.now + BUSY_RETRY_S
        while True:
            sent = self._send(segment)
            while sent.command.state is CommandState.SENT:
                yield
            if not sent.command.busy or self.ctx.now > deadline:
                break
            yield
        if sent.command.state is CommandState.FAILED:
            return failed(f"path start refused: {sent.command.reason}")
        self.queued = sent
        return None

    def _arrived(self) -> Status:
        state = self.ctx.state()
        if state is None:
            return SUCCEEDED
        miss = math.dist((state.east, state.north, state.up), self.goal)
        return SUCCEEDED if miss < 10.0 else failed(f"path ended {miss:.1f} m from the goal")

    # --- planning --------------------------------------------------------------------------
    def _position(self) -> Vec3 | None:
        state = self.ctx.state()
        return None if state is None else (state.east, state.north, state.up)

    def _query(self, start: Vec3, direction: Vec3 | None) -> Generator[None, None, PlanResult]:
        job = self.nav.plan(
            PlanRequest(
                start, self.goal, self.speed, timeout=PLAN_TIMEOUT_S, start_direction=direction
            )
        )
        deadline = self.ctx.now + ANSWER_WAIT_S
        while job.result is None and self.ctx.now <= deadline:
            yield
        if job.result is None:
            reason = f"the path planner did not answer in {ANSWER_WAIT_S:g} s"
            return PlanResult(PlanStatus.TIMEOUT, reason)
        return job.result

    def _plan_into_todo(
        self, start: Vec3, direction: Vec3 | None
    ) -> Generator[None, None, Status | None]:
        result = yield from self._query(start, direction)
        return self._accept(result)

    def _accept(self, result: PlanResult) -> Status | None:
        """Take a path's segments to fly; the failure when there is no path."""
        if not result.ok:
            return failed(f"path planner: {result.status.value}: {result.reason}")
        self.todo = list(result.segments)
        self.ctx.paths.append(result.segments)
        self.ctx.notes.append(
            f"planned {len(result.segments)} segments, {result.length:.0f} m "
            f"in {result.planning_time * 1e3:.0f} ms"
        )
        return None

    def _world_changed(self) -> Generator[None, None, Status | None]:
        """Check what is left of the path against the new world model; replan if it conflicts."""
        world = self.nav.world()
        self.revision = world.revision
        flying = self.flying
        if flying is not None:
            state = self.ctx.state()
            here = None if state is None else (state.east, state.north, state.up)
            s0 = 0.0 if here is None else flying.segment.closest_parameter(here, 0.0)
            hit = world.first_conflict([flying.segment], s0)
            if hit is not None:
                why = f"the segment in flight enters {hit.region}"
                return (yield from self._stop_and_replan(why))
        rest = [s.segment for s in (self.queued,) if s is not None] + self.todo
        conflict = world.first_conflict(rest)
        if conflict is None:
            return None
        why = f"the path enters {conflict.region} at {_fmt(conflict.position)}"
        if flying is None:
            # the path's first segment is sent but not flown yet: start over from here
            return (yield from self._stop_and_replan(why))
        if self._count_replan():
            return self._give_up(f"{why}; more than {MAX_REPLANS} replans")
        self.ctx.notes.append(f"replan: {why}")
        if flying.segment.end_velocity <= 0.0:
            # the segment in flight ends at rest: the rest starts there as a new leg
            outcome = yield from self._plan_into_todo(flying.segment.end, None)
            return None if outcome is None else self._give_up(f"{why}; {outcome.reason}")
        # replan from where the aircraft will be when the next segment is due (§7, Figure 18)
        result = yield from self._query(flying.segment.end, flying.segment.end_direction)
        if not result.ok:
            # no path joins the segment in flight (e.g. the new zone is just ahead of its end):
            # brake to a hover now, far from the zone, and plan from there without a tangent
            note = f"{why}; no path joins the segment in flight ({result.reason})"
            return (yield from self._stop_and_replan(note))
        self._follow_progress()
        if self.flying is not flying:
            self.revision = RECHECK  # path following moved on meanwhile: check again from there
            return None
        segments = list(result.segments)
        self.ctx.paths.append(result.segments)
        self.ctx.notes.append(
            f"replanned {len(segments)} segments, {result.length:.0f} m "
            f"in {result.planning_time * 1e3:.0f} ms"
        )
        if self.queued is not None:
            self.replaced = self.queued
            self.queued = self._send(segments.pop(0))  # the PFC replaces the queued segment
        self.todo = segments
        return None

    def _count_replan(self) -> bool:
        """Count a replan; True when there were too many."""
        self.replans += 1
        return self.replans > MAX_REPLANS

    def _stop_and_replan(self, why: str) -> Generator[None, None, Status | None]:
        """Brake to a hover (FCL cancel), wait until the aircraft holds, plan anew from there."""
        self.ctx.notes.append(f"stop: {why}")
        for sent in (self.flying, self.queued):
            if sent is not None:
                self.ctx.platform.stop(sent.command, why)
        self.flying = self.queued = self.replaced = None
        self.todo = []
        if self._count_replan():
            return failed(f"{why}; more than {MAX_REPLANS} replans")
        start = yield from self._settled()
        if start is None:
            return failed(f"{why}; the aircraft did not come to a hover")
        outcome = yield from self._plan_into_todo(start, None)
        return None if outcome is None else failed(f"{why}; {outcome.reason}")

    def _settled(self) -> Generator[None, None, Vec3 | None]:
        """The position once the aircraft moved less than HOLD_RADIUS in HOLD_S (bounded)."""
        deadline = self.ctx.now + SETTLE_BOUND_S
        mark, since = self._position(), self.ctx.now
        while self.ctx.now <= deadline:
            here = self._position()
            if here is not None and (mark is None or math.dist(here, mark) > HOLD_RADIUS):
                mark, since = here, self.ctx.now
            elif mark is not None and self.ctx.now - since >= HOLD_S:
                return mark
            yield
        return None

    def _give_up(self, reason: str) -> Status:
        """The path is no longer valid and there is no new one: brake to a hover, fail."""
        for sent in (self.flying, self.queued):
            if sent is not None:
                self.ctx.platform.stop(sent.command, reason)
        return failed(f"the path became invalid: {reason}")


def _fmt(p: Vec3) -> str:
    return "(" + ", ".join(f"{v:.0f}" for v in p) + ")"
