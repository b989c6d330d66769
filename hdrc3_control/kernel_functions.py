"""The PFC's control functions in the control-function template (chapter 6.1.1, Figure 13).

Each class wraps one flight mode of the control core (hover, take-off, path following, fly-to,
landing, car following) into the template's single hook ``step(phase, memory, now)``: it reads
its inputs from the HCSM memory slots, writes its command and its status into the shared
:class:`FunctionContext`, and turns its status flags into function events (``Fn-*-EV``) that the
kernel posts to the automata. Braking runs outside Control Mode, triggered by ``Braking-AC`` as
in the Mode Switch of Figure 14 (:class:`BrakingConsumer`).
"""

from __future__ import annotations

import math
import struct
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field, replace

from hdrc3_base.errors import ConfigError
from hdrc3_control.braking import BrakeStatus, EmergencyBrake
from hdrc3_control.car_following import (
    CarFollower,
    CarFollowingConfig,
    FollowOutput,
    TargetEstimator,
    TargetFix,
)
from hdrc3_control.commands import (
    AttitudeCommand,
    EstimatedState,
    EstimatorHealth,
    Vec3,
    wrap_pi,
)
from hdrc3_control.event_codec import command_id_of, decode, encode
from hdrc3_control.hover import HoverController, HoverSetpoint, HoverStatus
from hdrc3_control.landing import (
    HeadingChoice,
    Landing,
    LandingAid,
    LandingConfig,
    LandingEvent,
    LandingPhase,
    LandingPlan,
    LandingSite,
    landing_heading,
    plan_landing,
)
from hdrc3_control.outer_loop import OuterLoop
from hdrc3_control.path_following import (
    OfferStatus,
    PathEvent,
    PathFollower,
    PathFollowingConfig,
    PathOutput,
    PathStatus,
)
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.ppc_modes import PadVision
from hdrc3_control.takeoff import Takeoff, TakeoffConfig, TakeoffStatus
from hdrc3_control.wind_estimate import WindEstimate
from hdrc3_hcsm.control_function import HookResult, Phase
from hdrc3_hcsm.memory import ActionFlags, MemoryBank

_POSE = struct.Struct("<4d")
"""Position-DO, Hovering-DO, Path-End-DO, Takeoff-End-DO: east, north, up, heading."""
YAW_TOLERANCE = math.radians(5.0)
YAW_RATE_SETTLED = 0.1
"""rad/s: heading counts as reached when the error and the yaw rate are this small."""
OFFER_REFUSALS: dict[OfferStatus, str] = {
    OfferStatus.TOO_LATE: "too late: safety braking engaged or path finished",
    OfferStatus.DISCONTINUOUS: "segment does not start where the current one ends",
    OfferStatus.NOT_EXPECTED: "the current segment ends with zero velocity",
    OfferStatus.TOO_LATE_TO_REPLACE: (
        "too late to replace the queued segment: its replacement needs a lower entry speed "
        "than the aircraft can still brake to"
    ),
}
"""Reasons of the Cmd-Rejected-EV that answers a next segment the PFCM refuses."""
TARGET_FIXES = 256
"""Ground fixes of the tracked car the kernel keeps (about 25 s of colour images)."""
NO_TRACK = "track: no colour track: engage ppcl_ip_color_tracker on the car first"


def pack_pose(position: Vec3, heading: float) -> bytes:
    """Encode a pose slot."""
    return _POSE.pack(position[0], position[1], position[2], heading)


def unpack_pose(data: bytes) -> tuple[Vec3, float] | None:
    """Decode a pose slot (None when the slot holds something else)."""
    if len(data) != _POSE.size:
        return None
    e, n, u, h = _POSE.unpack(data)
    if not all(math.isfinite(v) for v in (e, n, u, h)):
        return None
    return (e, n, u), h


@dataclass
class FunctionContext:
    """What the kernel shares with its control functions in one tick."""

    terrain: Callable[[float, float], float]
    """Terrain height (ENU up) at east, north, m."""
    state: EstimatedState | None = None
    dt: float = 0.02
    command: AttitudeCommand | None = None
    """Set by the function that runs this tick."""
    integral: tuple[float, float] = (0.0, 0.0)
    """Wind trim handed from one function to the next."""
    failure: str = ""
    """Reason of the last function failure (Cmd-Rejected/Cmd-Failed text)."""
    events: list[tuple[str, bytes]] = field(default_factory=list)
    """Function events to post to the automata after this tick."""
    yaw_request: bool = False
    offer_pending: bool = False
    landing_sites: tuple[LandingSite, ...] = ()
    """The world's pads with the vision landing pattern."""
    vision_age: float = math.inf
    """Seconds since the navigation filter last accepted a vision fix (inf: never)."""
    vision_seen_age: float = math.inf
    """Seconds since the filter last received a vision fix, taken or rejected (inf: never)."""
    pad_vision: PadVision = PadVision.NONE
    """What the PPC can do for a vision landing (its latched ``ppc/pad_vision`` report; NONE
    until one arrives)."""
    camera_aim: Vec3 | None = None
    """Where the landing's search wants the camera to look this tick (ENU ground point; None:
    at the pad, or no landing): ``Landing.camera_aim``, the PTU's target while it searches."""
    wind: WindEstimate | None = None
    """The on-board wind estimate of this tick (``wind_estimate.WindEstimator``)."""
    notes: dict[int, str] = field(default_factory=dict)
    """Text for a command's Cmd-Finished-EV, by command id (what the function used)."""
    accept_notes: dict[int, str] = field(default_factory=dict)
    """Text for a command's Cmd-Accepted-EV, by command id (what the function plans on)."""
    target_fixes: deque[TargetFix] = field(default_factory=lambda: deque(maxlen=TARGET_FIXES))
    """The colour tracker's latest ground fixes of its car, in arrival order (kernel clock)."""

    def fail(self, reason: str) -> HookResult:
        """Record a failure reason and report FAILED to the template."""
        self.failure = reason
        return HookResult.FAILED

    def post(self, event: str, data: bytes) -> None:
        """Queue a function event for the automata."""
        self.events.append((event, data))


def _usable(ctx: FunctionContext) -> EstimatedState | None:
    state = ctx.state
    if state is None or state.health is EstimatorHealth.LOST:
        return None
    return state


class HoverFunction:
    """Hovering (Hover-Mode-AC): holds Hovering-DO; fcl_yaw changes its heading."""

    def __init__(self, ctx: FunctionContext) -> None:
        self.ctx = ctx
        self.controller: HoverController | None = None
        self.status = HoverStatus.STABILISING
        self.heading_error = 0.0
        self.yawing = False

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Template hook."""
        ctx = self.ctx
        if phase is Phase.INITIALIZING:
            state = _usable(ctx)
            if state is None:
                return ctx.fail("hover: no navigation solution")
            pose = unpack_pose(memory.read("Hovering-DO"))
            setpoint = HoverSetpoint.at(state) if pose is None else HoverSetpoint(*pose)
            self.controller = HoverController(setpoint, integral=ctx.integral)
            self.status, self.yawing = HoverStatus.STABILISING, False
            return HookResult.DONE
        ctl = self.controller
        if ctl is None:
            return ctx.fail("hover: not initialised")
        if phase is Phase.STOPPING:
            ctx.integral = ctl.loop.integral
            return HookResult.DONE
        state = ctx.state
        if state is None:
            return ctx.fail("hover: navigation solution lost")
        if ctx.yaw_request:
            ctx.yaw_request = False
            data = memory.read("Command-DO")
            decoded = decode(data, 1)
            if decoded.ok:
                ctl.setpoint = HoverSetpoint(ctl.setpoint.position, decoded.values[0] % math.tau)
                self.yawing = True
            else:
                reason = f"yaw: bad heading ({decoded.problem})"
                ctx.post("Fn-Failed-EV", encode(command_id_of(data), (), reason))
        out = ctl.update(state, ctx.dt)
        ctx.command = out.command
        self.status, self.heading_error = out.status, out.heading_error
        return HookResult.BUSY

    def yaw_done(self) -> bool:
        """Yaw-Done-CO: the fcl_yaw heading is held."""
        state = self.ctx.state
        return (
            self.yawing
            and state is not None
            and abs(self.heading_error) <= YAW_TOLERANCE
            and abs(state.rates[2]) <= YAW_RATE_SETTLED
        )


class TakeoffFunction:
    """Take-off (Takeoff-Mode-AC): climbs to the take-off height, then Takeoff-Done-CO."""

    def __init__(self, ctx: FunctionContext, config: TakeoffConfig) -> None:
        self.ctx = ctx
        self.core = Takeoff(config)
        self.done = False
        self.reported = False

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Template hook."""
        ctx = self.ctx
        if phase is Phase.INITIALIZING:
            state = _usable(ctx)
            if state is None:
                return ctx.fail("take-off: no navigation solution")
            self.done = self.reported = False
            status = self.core.start(state, now)
            if status is TakeoffStatus.REFUSED_NOT_ON_GROUND:
                return ctx.fail("take-off only from the ground")
            if status not in (TakeoffStatus.CLIMBING, TakeoffStatus.SPOOLING):
                return ctx.fail(f"take-off refused: {status.value}")
            return HookResult.DONE
        if phase is Phase.STOPPING:
            ctx.integral = self.core.loop.integral
            return HookResult.DONE
        state = ctx.state
        if state is None:
            return ctx.fail("take-off: navigation solution lost")
        out = self.core.update(state, now, ctx.dt)
        ctx.command = out.command
        if out.status is TakeoffStatus.DONE and out.hover_point is not None and not self.done:
            memory.write(
                "Takeoff-End-DO", pack_pose(out.hover_point.position, out.hover_point.heading)
            )
            self.done = True
        failed = out.status in (
            TakeoffStatus.FAILED_NO_LIFT,
            TakeoffStatus.NAVIGATION_LOST,
            TakeoffStatus.REFUSED_ENGINE,
        )
        if failed and not self.reported:
            self.reported = True
            reason = out.reason or f"take-off failed: {out.status.value}"
            ctx.failure = reason
            ctx.post("Fn-Failed-EV", encode(command_id_of(memory.read("Command-DO")), (), reason))
        return HookResult.BUSY


def segment_from(values: tuple[float, ...], command_id: int) -> PathSegment:
    """A Traj3D-EV payload's 14 numbers as a segment (ConfigError if degenerate)."""
    v = values
    return PathSegment(
        (v[0], v[1], v[2]),
        (v[3], v[4], v[5]),
        (v[6], v[7], v[8]),
        (v[9], v[10], v[11]),
        v[12],
        v[13],
        command_id,
    )


class _PathBase:
    """Shared RUNNING/STOPPING handling of the PFCM-based functions."""

    def __init__(self, ctx: FunctionContext, config: PathFollowingConfig) -> None:
        self.ctx = ctx
        self.config = config
        self.follower = PathFollower(config)
        self.status = PathStatus.IDLE
        self.last: PathOutput | None = None

    def _stop(self) -> HookResult:
        self.ctx.integral = self.follower.loop.integral
        return HookResult.DONE

    def _fly(self, memory: MemoryBank, now: float) -> PathOutput | None:
        state = self.ctx.state
        if state is None:
            return None
        out = self.follower.update(state, now)
        self.ctx.command = out.command
        self.status, self.last = out.status, out
        if out.hover_point is not None and (
            PathEvent.ARRIVED in out.events or PathEvent.STOPPED in out.events
        ):
            memory.write("Path-End-DO", pack_pose(out.hover_point, out.heading))
        return out


class Traj3DFunction(_PathBase):
    """Path following (Traj3D-Mode-AC) on the segments of Traj3D-EV (Figures 18, 22, 23)."""

    def __init__(
        self, ctx: FunctionContext, config: PathFollowingConfig, start_tolerance: float
    ) -> None:
        super().__init__(ctx, config)
        self.start_tolerance = start_tolerance
        self.requested = -1
        """Segment whose Request-Segment-EV the automaton already sent."""

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Template hook."""
        ctx = self.ctx
        if phase is Phase.INITIALIZING:
            state = _usable(ctx)
            if state is None:
                return ctx.fail("traj3d: no navigation solution")
            decoded = decode(memory.read("Traj3D-DO"), 14)
            if not decoded.ok:
                return ctx.fail(f"traj3d: bad segment ({decoded.problem})")
            try:
                segment = segment_from(decoded.values, decoded.command_id)
            except ConfigError as exc:
                return ctx.fail(f"traj3d: {exc}")
            gap = math.dist(segment.start, state.position)
            if gap > self.start_tolerance:
                return ctx.fail(
                    f"traj3d: segment starts {gap:.1f} m from the aircraft "
                    f"(limit {self.start_tolerance:.1f} m)"
                )
            self.follower = PathFollower(self.config)
            self.follower.start(state, segment, ctx.integral)
            self.status = PathStatus.FOLLOWING
            # Traj3D (C.5) requests the next segment as soon as this one is accepted
            self.requested = segment.segment_id
            return HookResult.DONE
        if phase is Phase.STOPPING:
            return self._stop()
        if ctx.offer_pending:
            ctx.offer_pending = False
            self._offer(memory.read("Traj3D-Next-DO"))
        current = self.follower.current
        before = 0 if current is None else current.segment_id
        out = self._fly(memory, now)
        if out is None:
            return ctx.fail("traj3d: navigation solution lost")
        for event in out.events:
            if event is PathEvent.SEGMENT_SWITCHED:
                ctx.post("Fn-Switched-EV", encode(before))
            elif event is PathEvent.REQUEST_SEGMENT and out.segment_id != self.requested:
                ctx.post("Fn-Request-EV", encode(out.segment_id))
            elif event is PathEvent.ARRIVED:
                ctx.post("Fn-Arrived-EV", encode(out.segment_id))
            elif event is PathEvent.SAFETY_BRAKING:
                reason = "safety braking: the next segment did not arrive before the timeout"
                ctx.failure = reason
                ctx.post("Fn-Failed-EV", encode(out.segment_id, (), reason))
        if out.status is PathStatus.NAVIGATION_LOST:
            return ctx.fail("traj3d: navigation solution lost")
        return HookResult.BUSY

    def _offer(self, data: bytes) -> None:
        decoded = decode(data, 14)
        cid = command_id_of(data)
        if not decoded.ok:
            self.ctx.post("Fn-Offer-Refused-EV", encode(cid, (), f"bad segment: {decoded.problem}"))
            return
        try:
            segment = segment_from(decoded.values, cid)
        except ConfigError as exc:
            self.ctx.post("Fn-Offer-Refused-EV", encode(cid, (), str(exc)))
            return
        replaced = self.follower.pending
        status = self.follower.offer(segment)
        if status is OfferStatus.REPLACED and replaced is not None:
            # Traj3D (C.18) ends the dropped segment: its one final reply to the DRC
            reason = f"replaced by segment {cid}"
            self.ctx.post("Fn-Offer-Replaced-EV", encode(replaced.segment_id, (), reason))
        if status in (OfferStatus.ACCEPTED, OfferStatus.REPLACED):
            # the whole payload: Traj3D (C.8) keeps it, C.10 makes it Command-DO once flown
            self.ctx.post("Fn-Offer-Ok-EV", data)
        else:
            self.ctx.post("Fn-Offer-Refused-EV", encode(cid, (), OFFER_REFUSALS[status]))

    def single_segment(self, memory: MemoryBank) -> bool:
        """Single-Segment-CO: the first segment ends with zero velocity."""
        decoded = decode(memory.read("Traj3D-DO"), 14)
        return decoded.ok and decoded.values[13] <= 0.0


class FlytoFunction(_PathBase):
    """One straight segment (Flyto-Mode-AC): fcl_traj3d_flyto, or fcl_climb when vertical."""

    def __init__(
        self, ctx: FunctionContext, config: PathFollowingConfig, climb_speed: float
    ) -> None:
        super().__init__(ctx, config)
        self.climb_speed = climb_speed
        self.climb = False

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Template hook."""
        ctx = self.ctx
        if phase is Phase.INITIALIZING:
            state = _usable(ctx)
            if state is None:
                return ctx.fail("fly-to: no navigation solution")
            data = memory.read("Command-DO")
            flyto, climb = decode(data, 4), decode(data, 1)
            cid = command_id_of(data)
            e, n, _ = state.position
            if flyto.ok:
                target, speed = flyto.values[:3], flyto.values[3]
                self.climb = False
            elif climb.ok:
                target, speed = (e, n, climb.values[0]), self.climb_speed
                self.climb = True
            else:
                return ctx.fail(f"fly-to: bad command ({flyto.problem})")
            if speed <= 0.0:
                return ctx.fail(f"fly-to: velocity must be > 0, got {speed}")
            try:
                segment = PathSegment.straight(
                    state.position, (target[0], target[1], target[2]), speed, 0.0, cid
                )
            except ConfigError as exc:
                return ctx.fail(f"fly-to: {exc}")
            self.follower = PathFollower(self.config)
            self.follower.start(state, segment, ctx.integral)
            self.status = PathStatus.FOLLOWING
            return HookResult.DONE
        if phase is Phase.STOPPING:
            return self._stop()
        out = self._fly(memory, now)
        if out is None or out.status is PathStatus.NAVIGATION_LOST:
            return ctx.fail("fly-to: navigation solution lost")
        if PathEvent.ARRIVED in out.events:
            ctx.post("Fn-Done-EV" if self.climb else "Fn-Arrived-EV", encode(out.segment_id))
        return HookResult.BUSY


class TrackFunction:
    """Reactive car following (Track-Mode-AC, fcl_track, §6.1): ``car_following.py``.

    Engages on a recent ground fix of the colour tracker's car and follows it until stopped;
    no accepted fix for ``lost_timeout`` posts ``Fn-Failed-EV`` (the Track automaton fails the
    command, the Mode Switch brakes and hovers).
    """

    def __init__(self, ctx: FunctionContext, config: CarFollowingConfig) -> None:
        self.ctx = ctx
        self.config = config
        self.estimator = TargetEstimator(config)
        self.follower = CarFollower(config)
        self.loop = OuterLoop(config.gains)
        self.taken = -math.inf
        """Time of the newest fix handed to the estimator."""
        self.command_id = 0
        self.reported = False
        self.last: FollowOutput | None = None

    def _take_fixes(self, since: float) -> None:
        for fix in sorted(self.ctx.target_fixes, key=lambda f: f.time):
            if fix.time > max(since, self.taken):
                self.estimator.update(fix)
                self.taken = fix.time

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Template hook."""
        ctx, c = self.ctx, self.config
        if phase is Phase.INITIALIZING:
            state = _usable(ctx)
            if state is None:
                return ctx.fail("track: no navigation solution")
            self.estimator.reset()
            self.taken, self.reported, self.last = -math.inf, False, None
            self._take_fixes(now - c.init_window)
            target = self.estimator.predict(now)
            if target is None or target.age > c.fix_recent:
                return ctx.fail(NO_TRACK)
            e, n, _ = state.position
            far = math.hypot(target.position[0] - e, target.position[1] - n)
            if far > c.max_range:
                return ctx.fail(
                    f"track: the tracked car is {far:.0f} m away (limit {c.max_range:.0f} m)"
                )
            self.command_id = command_id_of(memory.read("Command-DO"))
            self.follower.start(state, target)
            self.loop.reset(ctx.integral)
            return HookResult.DONE
        if phase is Phase.STOPPING:
            ctx.integral = self.loop.integral
            return HookResult.DONE
        state = ctx.state
        if state is None:
            return ctx.fail("track: navigation solution lost")
        self._take_fixes(-math.inf)
        target = self.estimator.predict(now)
        if target is None:
            return ctx.fail(NO_TRACK)
        if target.age > c.lost_timeout and not self.reported:
            self.reported = True
            reason = f"track: target lost for {c.lost_timeout:.1f} s"
            ctx.failure = reason
            ctx.post("Fn-Failed-EV", encode(self.command_id, (), reason))
        self.last = out = self.follower.update(state, target, ctx.dt)
        ctx.command = self.loop.update(state, out.reference, ctx.dt)
        return HookResult.BUSY


_AID_TEXT = {LandingAid.GPS: "GPS and barometer", LandingAid.VISION: "vision"}
"""How the landing's acceptance and final reply name the aid."""


class LandingFunction:
    """Landing (Land-Mode-AC): on the pad's vision fixes or on GPS, touchdown, engine shutdown.

    Near a patterned pad without a recent fix it searches for the pattern first
    (``LandingPhase.SEARCH``); when the search times out the plan becomes a GPS landing on the
    pad's GIS position. The heading is chosen on board (:func:`landing_heading`: into the
    estimated wind, ``FunctionContext.wind``) and re-chosen until the descent starts when the
    estimate moves by more than ``heading_hysteresis``. The Cmd-Finished-EV of the command says
    which aid the landing used, how a search went and the heading and wind
    (``FunctionContext.notes``). A plan that engages the PPC's pad state estimation
    (``LandingPlan.engage``) posts ``Fn-Pad-Engage-EV`` as it starts and ``Fn-Pad-Release-EV``
    when it stops (the Pad Vision automaton forwards them to the PPC).
    """

    def __init__(self, ctx: FunctionContext, config: LandingConfig) -> None:
        self.ctx = ctx
        self.core = Landing(config)
        self.phase = LandingPhase.APPROACH
        self.plan: LandingPlan | None = None
        self.requested: float | None = None
        """The land command's heading (None: none given)."""
        self.heading: HeadingChoice | None = None
        self.command_id = 0
        self.lowest_fix: float | None = None
        """Lowest height above the pad at which a vision fix was fresh, m."""
        self.engaged = False
        """This landing engaged the PPC's pad state estimation (released when it stops)."""

    def step(self, phase: Phase, memory: MemoryBank, now: float) -> HookResult:
        """Template hook."""
        ctx = self.ctx
        if phase is Phase.INITIALIZING:
            state = ctx.state
            if state is None:
                return ctx.fail("landing: no navigation solution")
            data = memory.read("Land-DO")
            land = decode(data, 1)
            pose = unpack_pose(data)
            self.requested = None
            if land.ok and math.isfinite(land.values[0]):
                self.requested = land.values[0] % math.tau
            elif pose is not None:
                self.requested = pose[1]
            config = self.core.config
            self.heading = landing_heading(self.requested, state.heading, ctx.wind, config)
            e, n, _ = state.position
            ground, sites = ctx.terrain(e, n), ctx.landing_sites
            self.plan = plan_landing(
                state,
                self.heading.heading,
                ground,
                ctx.vision_age,
                sites,
                config,
                pad_vision=ctx.pad_vision,
            )
            self.command_id, self.lowest_fix = command_id_of(data), None
            self.phase = self.core.start(
                state, self.plan.target, ctx.integral, self.plan.search_height
            )
            if self.phase is LandingPhase.REFUSED_ON_GROUND:
                return ctx.fail("landing refused: already on the ground")
            if self.plan.engage:
                ctx.post("Fn-Pad-Engage-EV", b"")
                self.engaged = True
            if self.command_id != 0:
                ctx.accept_notes[self.command_id] = self._plans()
            self._note()
            return HookResult.DONE
        if phase is Phase.STOPPING:
            if self.engaged:
                ctx.post("Fn-Pad-Release-EV", b"")
                self.engaged = False
            return HookResult.DONE
        state = ctx.state
        if state is None:
            return ctx.fail("landing: navigation solution lost")
        precise, recent = False, self.core.config.vision_recent
        if self.plan is not None and self.plan.aid is LandingAid.VISION:
            precise = ctx.vision_age <= recent
        seen = ctx.vision_seen_age <= recent
        self._rechoose(state)
        ctx.camera_aim = self.core.camera_aim(state, now, seen)
        out = self.core.update(state, now, ctx.dt, precise=precise, seen=seen)
        if out.events:
            self._searched(out.events)
        if precise and self.phase not in (LandingPhase.SEARCH, LandingPhase.APPROACH):
            lowest = max(0.0, out.height_above_ground)
            if self.lowest_fix is None or lowest < self.lowest_fix - 0.05:
                self.lowest_fix = lowest
                self._note()
        ctx.command = replace(out.command, engine_off=out.engine_shutdown)
        if out.phase is LandingPhase.DESCENT and self.phase is not LandingPhase.DESCENT:
            self._note()  # the heading and the wind it was chosen in, as the descent starts
        self.phase = out.phase
        return HookResult.BUSY

    def _rechoose(self, state: EstimatedState) -> None:
        """Before the descent: turn with the wind estimate when it has moved enough."""
        target, config = self.core.target, self.core.config
        if target is None or self.phase not in (LandingPhase.SEARCH, LandingPhase.APPROACH):
            return
        choice = landing_heading(self.requested, state.heading, self.ctx.wind, config)
        if abs(wrap_pi(choice.heading - target.heading)) <= config.heading_hysteresis:
            if self.heading is not None:
                self.heading = replace(self.heading, wind=choice.wind)
            return
        if self.core.turn(choice.heading):
            self.heading = choice
            self._note()

    def _searched(self, events: tuple[LandingEvent, ...]) -> None:
        """The search ended: a vision landing goes on, or the plan becomes a GPS landing."""
        plan, took = self.plan, self.core.search_time
        if plan is None or plan.search_height is None or took is None:
            return
        up = f"{plan.search_height:.1f} m"
        if LandingEvent.SEARCH_TIMED_OUT in events:
            reason = f"no vision fix of pad {plan.pad}: the search from {up} failed ({took:.0f} s)"
            self.plan = replace(plan, aid=LandingAid.GPS, reason=reason)
        else:
            reason = f"{plan.reason} (found after a {took:.1f} s search from {up})"
            self.plan = replace(plan, reason=reason)
        self._note()

    def _plans(self) -> str:
        """What the command's acceptance says: the aid planned on and why."""
        plan = self.plan
        if plan is None:
            return ""
        text = f"landing on {_AID_TEXT[plan.aid]}: {plan.reason}"
        if plan.aid is LandingAid.VISION and plan.search_height is not None:
            text += f"; searching for the pattern from {plan.search_height:.1f} m first"
        return text

    def _note(self) -> None:
        """What the command's final reply says about the aid."""
        plan = self.plan
        if plan is None or self.command_id == 0:
            return
        text = f"landed on {_AID_TEXT[plan.aid]}: {plan.reason}"
        if plan.aid is LandingAid.VISION and self.lowest_fix is not None:
            text += f", fixes down to {self.lowest_fix:.1f} m above it"
        if self.heading is not None:
            text += f"; {self.heading.describe()}"
        self.ctx.notes[self.command_id] = text


class BrakingConsumer:
    """Emergency braking started by Braking-AC (Mode Switch A.2), run until a function runs."""

    def __init__(self, ctx: FunctionContext, config: PathFollowingConfig) -> None:
        self.ctx = ctx
        self.config = config
        self.brake: EmergencyBrake | None = None
        self.active = False
        self.status = BrakeStatus.BRAKING
        self.command: AttitudeCommand | None = None

    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        """Start on the flag; brake every tick while active."""
        state = self.ctx.state
        if flags.is_set("Braking-AC") and state is not None:
            self.brake = EmergencyBrake(self.config)
            self.brake.start(state, self.ctx.integral)
            self.active, self.status = True, BrakeStatus.BRAKING
        if not self.active or self.brake is None or state is None:
            self.command = None
            return
        out = self.brake.update(state, now)
        self.command, self.status = out.command, out.status

    def stop(self) -> None:
        """The next function has taken over."""
        if self.active and self.brake is not None:
            self.ctx.integral = self.brake.follower.loop.integral
        self.active, self.command = False, None

    def done(self) -> bool:
        """Braking-Done-CO."""
        return self.active and self.status is BrakeStatus.STOPPED
