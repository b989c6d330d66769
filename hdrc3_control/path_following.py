"""Path Following Control Mode (chapter 5.3, 7.2): virtual leader on cubic segments.

The control point moves along the path by error feedback (virtual leader)::

    ds/dt = (v . t + k_leader * (x - p(s)) . t) / |p'(s)|

which keeps it at the closest point. The outer loop tracks p(s) with the planned speed along the
tangent and the curvature feed-forward ``v^2 * kappa * n``. The planned speed is the segment's
target speed capped by V = sqrt(|phi_max g R|) and by braking to the segment's end speed.

Segment handling: the follower takes one segment as its input and holds at most one pending next
segment. It raises REQUEST_SEGMENT as soon as it accepts a segment as input whose end velocity is
not zero (more segments follow). A segment offered while another is pending replaces it (issue 13:
the executor replans the part not yet flown): the same continuity check against the segment in
flight, the velocity profile rebuilt for the new successor, refused when the aircraft could no
longer slow down to the new segment's entry speed with the braking deceleration. Once the follower
has switched to the pending segment, an offer is simply the next segment. If the next segment has
not arrived by the time the braking distance requires (the timeout, recomputed every tick from the
profile, the position and the speed), it brakes to a stop at the end of the current segment
(SAFETY_BRAKING, then STOPPED). The last segment ends with ARRIVED within 3 m of its end point.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import (
    AttitudeCommand,
    EstimatedState,
    EstimatorHealth,
    Vec3,
    wrap_2pi,
)
from hdrc3_control.outer_loop import OuterLoop, OuterLoopGains, Reference, accel_to_attitude
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.velocity_profile import (
    ProfileLimits,
    VelocityProfile,
    braking_distance,
    build_profile,
)


class PathStatus(enum.Enum):
    """Status flags of the PFCM in one tick."""

    IDLE = "idle"
    FOLLOWING = "following"
    SAFETY_BRAKING = "safety_braking"
    """Next segment missing at the timeout: braking to a stop at the end of this segment."""
    STOPPED = "stopped"
    """Stopped after safety braking (or a zero-velocity path); hover at ``hover_point``."""
    ARRIVED = "arrived"
    """Within the arrival radius of the final waypoint; hover at ``hover_point``."""
    NAVIGATION_LOST = "navigation_lost"


class PathEvent(enum.Enum):
    """One-shot events raised in a tick."""

    REQUEST_SEGMENT = "request_segment"
    SEGMENT_SWITCHED = "segment_switched"
    SAFETY_BRAKING = "safety_braking"
    STOPPED = "stopped"
    ARRIVED = "arrived"


class OfferStatus(enum.Enum):
    """Answer to :meth:`PathFollower.offer`."""

    ACCEPTED = "accepted"
    REPLACED = "replaced"
    """Accepted in place of the pending next segment, which is dropped (never flown)."""
    TOO_LATE = "too_late"
    """Safety braking already engaged (or the path finished): hover first, then start anew."""
    DISCONTINUOUS = "discontinuous"
    """The segment does not start where the current one ends."""
    NOT_EXPECTED = "not_expected"
    """The current segment ends with zero velocity: no next segment is expected."""
    TOO_LATE_TO_REPLACE = "too_late_to_replace"
    """The replacement needs a lower entry speed than the aircraft can still brake to; the
    pending segment stays."""


@dataclass(frozen=True, slots=True)
class PathFollowingConfig:
    """Gains and limits of the PFCM."""

    gains: OuterLoopGains = field(default_factory=OuterLoopGains)
    limits: ProfileLimits = field(default_factory=ProfileLimits)
    k_leader: float = 2.0
    """Control point feedback gain, 1/s."""
    accel: float = 1.5
    """Speed-up rate of the speed reference, m/s^2."""
    arrival_radius: float = 3.0
    stop_speed: float = 0.3
    """Speed below which braking counts as stopped, m/s."""
    reaction_time: float = 0.5
    """Braking margin: distance flown in this time before braking starts, s."""
    braking_margin: float = 2.0
    """Extra braking margin, m."""
    continuity_tolerance: float = 1.0
    """Largest gap between a segment's end and the next one's start, m."""
    heading_min_speed: float = 1.0
    """Below this reference speed the heading is held instead of following the tangent, m/s."""
    lookahead_time: float = 1.0
    """The speed reference anticipates profile reductions this far ahead (velocity-loop lag), s."""
    replace_speed_tolerance: float = 0.5
    """A replacement is refused when the speed reference exceeds the new profile's speed at the
    control point by more than this (it would need more than the braking deceleration), m/s."""

    def __post_init__(self) -> None:
        """Reject non-positive parameters."""
        values = (self.k_leader, self.accel, self.arrival_radius, self.stop_speed)
        if not all(math.isfinite(v) and v > 0.0 for v in values):
            raise ConfigError(f"path following parameters must be > 0, got {values}")


@dataclass(frozen=True, slots=True)
class PathOutput:
    """Command, status flags and diagnostics of one tick."""

    command: AttitudeCommand
    status: PathStatus
    events: tuple[PathEvent, ...]
    segment_id: int
    s: float
    """Control point parameter on the current segment."""
    control_point: Vec3
    cross_track: float
    """Distance from the control point, m."""
    speed_ref: float
    """Speed reference along the tangent, m/s."""
    speed_limit: float
    """Curvature-compatible speed at the control point, m/s."""
    distance_to_end: float
    """Along-path distance to the end of the current segment, m."""
    timeout: float
    """Sim time by which the next segment must arrive (inf if none is expected)."""
    hover_point: Vec3 | None
    """Where to hover after STOPPED/ARRIVED."""
    heading: float
    """Heading reference, rad."""


class PathFollower:
    """The PFCM control function core; :meth:`start`, :meth:`offer`, :meth:`update` per tick."""

    def __init__(self, config: PathFollowingConfig | None = None) -> None:
        """Create an idle follower."""
        self.config = config or PathFollowingConfig()
        self.loop = OuterLoop(self.config.gains)
        self._current: PathSegment | None = None
        self._pending: PathSegment | None = None
        self._profile: VelocityProfile | None = None
        self._status = PathStatus.IDLE
        self._events: list[PathEvent] = []
        self._s = 0.0
        self._speed_cmd = 0.0
        self._heading = 0.0
        self._time: float | None = None

    @property
    def status(self) -> PathStatus:
        """Status after the last tick."""
        return self._status

    @property
    def current(self) -> PathSegment | None:
        """Segment being flown."""
        return self._current

    @property
    def pending(self) -> PathSegment | None:
        """Next segment, if it has arrived."""
        return self._pending

    def start(
        self,
        state: EstimatedState,
        segment: PathSegment,
        integral: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        """Take ``segment`` as input (Ctrl-Init); ``integral`` hands the wind trim over."""
        self.loop.reset(integral)
        self._pending = None
        self._status = PathStatus.FOLLOWING
        self._events = []
        self._speed_cmd = max(0.0, float(np.dot(state.velocity, segment.tangent(0.0))))
        self._heading = state.heading
        self._time = None
        self._take(segment, state.position)

    def offer(self, segment: PathSegment) -> OfferStatus:
        """Hand the next segment over (Traj3D-EV while running); it replaces a pending one."""
        cur = self._current
        if cur is None or self._status is not PathStatus.FOLLOWING:
            return OfferStatus.TOO_LATE
        if cur.end_velocity <= 0.0:
            return OfferStatus.NOT_EXPECTED
        gap = float(np.linalg.norm(np.array(segment.start) - np.array(cur.end)))
        if gap > self.config.continuity_tolerance:
            return OfferStatus.DISCONTINUOUS
        profile = self._build(cur, segment)
        if self._pending is None:
            self._pending, self._profile = segment, profile
            return OfferStatus.ACCEPTED
        if self._speed_cmd > profile.speed_at(self._s) + self.config.replace_speed_tolerance:
            return OfferStatus.TOO_LATE_TO_REPLACE
        self._pending, self._profile = segment, profile
        return OfferStatus.REPLACED

    def update(self, state: EstimatedState, now: float) -> PathOutput:
        """One 50 Hz tick of the PFCM."""
        cur, prof = self._current, self._profile
        if cur is None or prof is None:
            raise ConfigError("path follower updated before start()")
        c = self.config
        dt = 0.0 if self._time is None else max(0.0, now - self._time)
        self._time = now
        x = np.array(state.position)
        v = np.array(state.velocity)
        self._advance(x, v, dt)
        cur, prof = self._current, self._profile
        assert cur is not None and prof is not None
        s = self._s
        point = cur.position(s)
        tangent = cur.tangent(s)
        d_rem = prof.length - prof.distance_at(s)
        along = float(v @ tangent)
        timeout = math.inf
        if self._status is PathStatus.FOLLOWING and self._pending is None and cur.end_velocity > 0:
            speed = max(along, self._speed_cmd)
            needed = self._braking_need(speed)
            # time until the braking point at the planned speed (or faster, if flying faster)
            cruise = max(speed, prof.speed_at(s), 0.5)
            timeout = now + max(0.0, d_rem - needed) / cruise
            if d_rem <= needed:
                self._status = PathStatus.SAFETY_BRAKING
                self._events.append(PathEvent.SAFETY_BRAKING)
                self._profile = prof = build_profile(cur, 0.0, c.limits)
        # speed reference: planned profile, reached with a bounded speed-up rate
        planned = prof.min_speed_ahead(s, max(along, self._speed_cmd) * c.lookahead_time)
        previous = self._speed_cmd
        self._speed_cmd = (
            min(planned, previous + c.accel * dt) if dt > 0 else min(planned, previous)
        )
        speed_ref = self._speed_cmd
        dv = (speed_ref - previous) / dt if dt > 0 else 0.0
        end = np.array(cur.end)
        final = cur.end_velocity <= 0.0 or self._status is not PathStatus.FOLLOWING
        hover_point: Vec3 | None = None
        if final and self._pending is None:
            braking = self._status is PathStatus.SAFETY_BRAKING or (
                self._status is PathStatus.FOLLOWING and cur.target_velocity <= 0.0
            )
            if braking and float(np.linalg.norm(v)) < c.stop_speed:
                self._status = PathStatus.STOPPED
                self._events.append(PathEvent.STOPPED)
            elif (
                self._status is PathStatus.FOLLOWING
                and float(np.linalg.norm(end - x)) < c.arrival_radius
            ):
                self._status = PathStatus.ARRIVED
                self._events.append(PathEvent.ARRIVED)
        if self._status is PathStatus.ARRIVED:
            hover_point = cur.end
        elif self._status is PathStatus.STOPPED:
            hover_point = (float(point[0]), float(point[1]), float(point[2]))
        command = self._command(state, point, tangent, cur.curvature_vector(s), speed_ref, dv, dt)
        events, self._events = tuple(self._events), []
        return PathOutput(
            command=command,
            status=self._status,
            events=events,
            segment_id=cur.segment_id,
            s=s,
            control_point=(float(point[0]), float(point[1]), float(point[2])),
            cross_track=float(np.linalg.norm(x - point)),
            speed_ref=speed_ref,
            speed_limit=prof.limit_at(s),
            distance_to_end=d_rem,
            timeout=timeout,
            hover_point=hover_point,
            heading=self._heading,
        )

    # ------------------------------------------------------------------ internals
    def _braking_need(self, speed: float) -> float:
        c = self.config
        return (
            braking_distance(speed, c.limits.braking_decel)
            + speed * c.reaction_time
            + c.braking_margin
        )

    def _build(self, segment: PathSegment, following: PathSegment | None) -> VelocityProfile:
        lim = self.config.limits
        if following is None:
            # until the next segment arrives, plan to pass the end at the end velocity
            return build_profile(segment, segment.end_velocity, lim)
        nxt = build_profile(following, following.end_velocity, lim)
        return build_profile(segment, segment.end_velocity, lim, max_end_speed=float(nxt.speed[0]))

    def _take(self, segment: PathSegment, position: Vec3) -> None:
        self._current = segment
        self._profile = self._build(segment, self._pending)
        self._s = segment.closest_parameter(position, 0.0)
        if segment.end_velocity > 0.0:
            self._events.append(PathEvent.REQUEST_SEGMENT)

    def _advance(self, x: np.ndarray, v: np.ndarray, dt: float) -> None:
        """Move the control point by the virtual-leader feedback; switch segments at s = 1."""
        cur = self._current
        assert cur is not None
        d1 = cur.derivative(self._s)
        n = float(np.linalg.norm(d1))
        t = d1 / n
        s_dot = (float(v @ t) + self.config.k_leader * float((x - cur.position(self._s)) @ t)) / n
        self._s = min(1.0, max(0.0, self._s + s_dot * dt))
        if self._s >= 1.0 and self._pending is not None and self._status is PathStatus.FOLLOWING:
            nxt, self._pending = self._pending, None
            self._events.append(PathEvent.SEGMENT_SWITCHED)
            pos = (float(x[0]), float(x[1]), float(x[2]))
            self._take(nxt, pos)

    def _command(
        self,
        state: EstimatedState,
        point: np.ndarray,
        tangent: np.ndarray,
        curvature: np.ndarray,
        speed: float,
        dv: float,
        dt: float,
    ) -> AttitudeCommand:
        c = self.config
        if state.health is EstimatorHealth.LOST:
            self._status = PathStatus.NAVIGATION_LOST
            ix, iy = self.loop.integral
            roll, pitch = accel_to_attitude(ix, iy, state.heading, c.gains.max_tilt)
            return AttitudeCommand(roll=roll, pitch=pitch)
        te, tn = float(tangent[0]), float(tangent[1])
        h2 = te * te + tn * tn
        yaw_rate = 0.0
        if speed >= c.heading_min_speed and h2 > 0.09:
            self._heading = wrap_2pi(math.atan2(te, tn))
            dte, dtn = speed * float(curvature[0]), speed * float(curvature[1])
            yaw_rate = (tn * dte - te * dtn) / h2
        centripetal = speed * speed
        ref = Reference(
            position=(float(point[0]), float(point[1]), float(point[2])),
            heading=self._heading,
            velocity=(speed * te, speed * tn, speed * float(tangent[2])),
            acceleration=(
                centripetal * float(curvature[0]) + dv * te,
                centripetal * float(curvature[1]) + dv * tn,
            ),
            yaw_rate=yaw_rate,
        )
        return self.loop.update(state, ref, dt)
