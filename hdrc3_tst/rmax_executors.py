"""The RMAX executors: one per elementary action type, through FCL/PPCL (sections 6.2, 6.3).

Each is a generator (:meth:`ActionExecutor.run`): it sends a command through its context, yields
while the command runs, and returns how the node ended. Flight actions take off first when the
aircraft is still on the ground (a mission need not start with ``take-off``; Example 6.1 does
not). Paths are streamed as the chapter's path following expects them (§7.2): the first
segment, then each next one when the control kernel asks for it.

Fly-to is a planned flight (:mod:`hdrc3_tst.planned_flight`): the agent's path planner gives the
segments, a change of its world model during the flight makes it replan. An agent without a path
planner flies straight with ``traj3d_flyto``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from types import MappingProxyType

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.coverage import (
    OVERLAP,
    CoverageStatus,
    Platform,
    pair_footprint_width,
    plan_part,
)
from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_tst.executor import (
    SUCCEEDED,
    ActionContext,
    ActionExecutor,
    Progress,
    failed,
    flight_bound,
)
from hdrc3_tst.executor_steps import DATA_TIMEOUT_S, Steps, airborne, finish, fly_to
from hdrc3_tst.payload_executors import PAYLOAD_EXECUTORS
from hdrc3_tst.planned_flight import PlannedFlight, segment_args
from hdrc3_tst.polyline import polyline
from hdrc3_tst.radiation_executor import RADIATION_EXECUTORS

SEGMENTS_DONE = "segments_done"
"""``ActionContext.memory`` key: segments of a streamed pattern flown to their end."""
SCAN_START = ("scan_start_east", "scan_start_north")
"""``ActionContext.memory`` keys: where a scan was planned from (its entry corner follows)."""
NADIR_TILT = math.pi / 2
"""rad: the PTU's tilt that points the cameras straight down (positive tilt looks down)."""
TURN_SPEED = 3.0
"""m/s on the U-turns of a coverage pattern (the path follower may slow further)."""
LRF_REACH = 40.0
"""m: the slant range within which the laser maps well (its returns go to 80 m; the attitude
error grows their height error with range)."""
LANDING_SPEED = 1.0
"""m/s, the order of the RMAX's final descent (for the bound of a landing)."""


def resumed(ctx: ActionContext, segments: list[PathSegment]) -> list[PathSegment]:
    """The segments still to fly: a resumed node starts again at the segment it was flying."""
    return segments[int(ctx.memory.get(SEGMENTS_DONE, 0)) :]


def stream(ctx: ActionContext, segments: list[PathSegment]) -> Steps:
    """Fly to the first segment's start, then send each segment when the previous asks (§7.2).

    ``ctx.memory[SEGMENTS_DONE]`` counts the segments flown to their end (of the node's whole
    pattern: ``segments`` are the ones :func:`resumed` left).
    """
    done = int(ctx.memory.get(SEGMENTS_DONE, 0))
    first = segments[0]
    outcome = yield from fly_to(ctx, first.start, first.target_velocity)
    if outcome.progress is not Progress.SUCCEEDED:
        return outcome
    previous, flying = ctx.send(FclCommand.TRAJ3D, **segment_args(first)), first
    for index, segment in enumerate(segments[1:], start=1):
        bound = flight_bound(flying.arc_length(), flying.target_velocity)
        outcome = yield from finish(ctx, previous, bound, lambda c: c.segment_requested)
        if outcome.progress is not Progress.SUCCEEDED:
            return failed(f"segment {index - 1}: {outcome.reason}")
        if not previous.segment_requested:
            return failed(f"path following ended after segment {index - 1} of {len(segments)}")
        # the PFC asks for the next segment while flying the last one: the one before is done
        ctx.memory[SEGMENTS_DONE] = done + index - 1
        previous, flying = ctx.send(FclCommand.TRAJ3D, **segment_args(segment)), segment
    bound = flight_bound(flying.arc_length(), flying.target_velocity)
    outcome = yield from finish(ctx, previous, bound)
    if outcome.progress is not Progress.SUCCEEDED:
        return failed(f"segment {len(segments) - 1}: {outcome.reason}")
    return outcome


class TakeOff(ActionExecutor):
    """``take-off``: FCL takeoff; already flying counts as done."""

    def run(self, ctx: ActionContext) -> Steps:
        """Take off unless the aircraft already flies."""
        return (yield from airborne(ctx))


class Land(ActionExecutor):
    """``land(heading)``: FCL land; the engine stops."""

    def run(self, ctx: ActionContext) -> Steps:
        """Land with the heading given in degrees."""
        heading = math.radians(ctx.number("heading"))
        state = ctx.state()
        height = state.up - ctx.frame.ground_up(state.east, state.north) if state else 0.0
        command = ctx.send(FclCommand.LAND, heading=heading)
        return (yield from finish(ctx, command, flight_bound(height, LANDING_SPEED)))


class Wait(ActionExecutor):
    """``wait(duration)``: nothing for a while (the network fixes TE - TS)."""

    def run(self, ctx: ActionContext) -> Steps:
        """Return once the duration has passed."""
        while ctx.elapsed < ctx.number("duration"):
            yield
        return SUCCEEDED


class Hover(ActionExecutor):
    """``hover(duration)``: stay in the air in place (the PFC hovers between commands)."""

    def run(self, ctx: ActionContext) -> Steps:
        """Take off if needed, then stay until the duration has passed."""
        outcome = yield from airborne(ctx)
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
        while ctx.elapsed < ctx.number("duration"):
            state = ctx.state()
            if state is not None and state.failsafe:
                return failed(f"hover interrupted by a failsafe: {state.failsafe}")
            yield
        return SUCCEEDED


class FlyTo(ActionExecutor):
    """``fly-to(speed, destination)``: a planned flight (straight without a path planner)."""

    def run(self, ctx: ActionContext) -> Steps:
        """Take off if needed, then fly to the destination."""
        outcome = yield from airborne(ctx)
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
        (point,) = ctx.place("destination")
        speed = ctx.number("speed")
        if ctx.navigation is None:
            return (yield from fly_to(ctx, point, speed))
        goal = (float(point[0]), float(point[1]), float(point[2]))
        return (yield from PlannedFlight(ctx, ctx.navigation, goal, speed).run())


class FlyPath(ActionExecutor):
    """``fly-path(speed, path)``: streamed segments through the path's points."""

    def run(self, ctx: ActionContext) -> Steps:
        """Take off if needed, then stream the path's segments."""
        outcome = yield from airborne(ctx)
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
        points = [(p[0], p[1], p[2]) for p in ctx.place("path")]
        return (yield from stream(ctx, resumed(ctx, polyline(points, ctx.number("speed")))))


def between(
    ctx: ActionContext, start: PpclCommand, stop: PpclCommand, segments: list[PathSegment]
) -> Steps:
    """Fly a pattern with a payload function on: ``start``, the pattern, then ``stop``.

    ``stop`` is sent however the flight ended, also when the node is aborted or paused
    (``Stepper.close``: sent without waiting); a failed ``stop`` fails a flown pattern.
    """
    try:
        outcome = yield from finish(ctx, ctx.send(start))
        if outcome.progress is Progress.SUCCEEDED:
            outcome = yield from stream(ctx, resumed(ctx, segments))
    except GeneratorExit:
        ctx.send(stop)
        raise
    stopped = yield from finish(ctx, ctx.send(stop))
    if outcome.progress is Progress.SUCCEEDED and stopped.progress is not Progress.SUCCEEDED:
        return stopped
    return outcome


class ScanArea(ActionExecutor):
    """``scan-area(speed, area, altitude, part, parts)``: camera coverage for the saliency map.

    The coverage pattern (§11.1.1) of band ``part`` of ``parts`` equal bands of the area (so
    that concurrent scan nodes of several aircraft split it without talking), strips as wide as
    both cameras see (:func:`pair_footprint_width`). Before the pattern the PTU turns the
    cameras straight down and the PPC engages the saliency pipeline (``ppcl_ip_saliency``);
    after it, however it ended, ``ppcl_ip_abort`` stops the pipeline.
    """

    def run(self, ctx: ActionContext) -> Steps:
        """Take off if needed, point the cameras down, start image processing, fly the band."""
        outcome = yield from airborne(ctx)
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
        segments = self._pattern(ctx)
        if isinstance(segments, str):
            return failed(segments)
        outcome = yield from finish(ctx, ctx.send(PpclCommand.TURN_TO, pan=0.0, tilt=NADIR_TILT))
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
        return (yield from between(ctx, PpclCommand.IP_SALIENCY, PpclCommand.IP_ABORT, segments))

    @staticmethod
    def _pattern(ctx: ActionContext) -> list[PathSegment] | str:
        altitude = ctx.number("altitude")
        part, parts = ctx.number("part"), ctx.number("parts")
        return coverage(ctx, pair_footprint_width(altitude), part, parts)


def coverage(
    ctx: ActionContext, width: float, part: float = 1.0, parts: float = 1.0
) -> list[PathSegment] | str:
    """The coverage pattern of band ``part`` of ``parts`` of the node's area.

    Strips are ``width`` wide, flown at the node's altitude above the area's highest corner and
    entered at the corner nearest where the aircraft was when the node first planned it (a
    resumed node keeps its pattern).
    """
    corners = ctx.place("area")
    altitude, speed = ctx.number("altitude"), ctx.number("speed")
    if not (part.is_integer() and parts.is_integer() and 1 <= part <= parts):
        return f"part {part:g} of {parts:g}: parts are numbered 1..parts"
    if SCAN_START[0] not in ctx.memory:
        state = ctx.state()
        here = (state.east, state.north) if state is not None else corners[0][:2]
        ctx.memory.update(zip(SCAN_START, here, strict=True))
    start = (ctx.memory[SCAN_START[0]], ctx.memory[SCAN_START[1]])
    ground = max(ctx.frame.ground_up(c[0], c[1]) for c in corners)
    me = Platform(ctx.agent, width, speed, (start[0], start[1]))
    plan = plan_part(
        [c[:2] for c in corners],
        int(part),
        int(parts),
        me,
        ground + altitude,
        min(TURN_SPEED, speed),
    )
    if plan.status is not CoverageStatus.PLANNED:
        return f"{ctx.spec.name}: {plan.reason}"
    return list(plan.assignments[0].segments)


def laser_swath_width(altitude: float, reach: float = LRF_REACH) -> float:
    """Width (m) of the ground the rotating laser maps well from ``altitude`` m.

    The chord of the circle where its ``reach`` meets the ground: the scan plane turns about the
    forward axis, so the half sphere in front reaches as far to the sides as ahead.
    """
    return 2.0 * math.sqrt(max(reach * reach - altitude * altitude, 0.0))


class LaserMapArea(ActionExecutor):
    """``laser-map-area(speed, area, altitude, rotation)``: an elevation map (§11.2).

    As the chapter's mapping TST node: PPCL sets the laser's angular (1 deg) and distance (1 cm,
    80 m) resolutions and a constant rotation speed, starts data collection, the aircraft flies a
    coverage pattern with strips as wide as the laser maps well (:func:`laser_swath_width`),
    and data collection stops however the flight ended. The ``laser_mapper`` node builds the map
    while the PPC collects and stores it in the path planner's GIS when collection stops.
    """

    def run(self, ctx: ActionContext) -> Steps:
        """Take off if needed, start the laser, fly the pattern, stop the laser."""
        outcome = yield from airborne(ctx)
        if outcome.progress is not Progress.SUCCEEDED:
            return outcome
        altitude = ctx.number("altitude")
        width = laser_swath_width(altitude)
        if width < 2.0 * altitude * OVERLAP:
            return failed(
                f"altitude {altitude:g} m: the laser maps well only within {LRF_REACH:g} m"
            )
        segments = coverage(ctx, width)
        if isinstance(segments, str):
            return failed(segments)
        for command, args in (
            (PpclCommand.LASER_ANGULAR_RESOLUTION, {"angular_resolution": 1.0}),
            (PpclCommand.LASER_DISTANCE_RESOLUTION, {"distance_resolution": 0.01}),
            (PpclCommand.LASER_ROTATION_SPEED, {"rotation_speed": ctx.number("rotation")}),
        ):
            outcome = yield from finish(ctx, ctx.send(command, **args))
            if outcome.progress is not Progress.SUCCEEDED:
                return outcome
        start, stop = (
            PpclCommand.LASER_START_DATA_COLLECTION,
            PpclCommand.LASER_STOP_DATA_COLLECTION,
        )
        return (yield from between(ctx, start, stop, segments))


class LookAt(ActionExecutor):
    """``look-at(target)``: PPCL look_at; done when the PTU is on target."""

    def run(self, ctx: ActionContext) -> Steps:
        """Point the PTU at the target."""
        (point,) = ctx.place("target")
        lon, lat, alt = ctx.frame.to_wgs84(point[0], point[1], point[2])
        command = ctx.send(
            PpclCommand.LOOK_AT, longitude=lon, latitude=lat, has_altitude=1.0, altitude=alt
        )
        return (yield from finish(ctx, command))


class PtuTurnTo(ActionExecutor):
    """``ptu-turn-to(pan, tilt)``: PPCL turn_to (degrees in the language, radians on the wire)."""

    def run(self, ctx: ActionContext) -> Steps:
        """Turn the PTU."""
        pan, tilt = math.radians(ctx.number("pan")), math.radians(ctx.number("tilt"))
        return (yield from finish(ctx, ctx.send(PpclCommand.TURN_TO, pan=pan, tilt=tilt)))


class CameraZoom(ActionExecutor):
    """``camera-zoom(camera, zoom)``: PPCL zoom; the factor maps linearly onto 0..1."""

    def run(self, ctx: ActionContext) -> Steps:
        """Set the zoom."""
        spec = ctx.spec.param("zoom")
        assert spec is not None and spec.minimum is not None and spec.maximum is not None
        value = (ctx.number("zoom") - spec.minimum) / (spec.maximum - spec.minimum)
        camera = ctx.number("camera")
        command = ctx.send(PpclCommand.ZOOM, camera_id=camera, value=value)
        return (yield from finish(ctx, command))


RMAX_EXECUTORS: Mapping[str, type[ActionExecutor]] = MappingProxyType(
    {
        "take-off": TakeOff,
        "land": Land,
        "hover": Hover,
        "fly-to": FlyTo,
        "fly-path": FlyPath,
        "scan-area": ScanArea,
        "laser-map-area": LaserMapArea,
        "look-at": LookAt,
        "ptu-turn-to": PtuTurnTo,
        "camera-zoom": CameraZoom,
        "wait": Wait,
        **PAYLOAD_EXECUTORS,
        **RADIATION_EXECUTORS,
    }
)
"""The RMAX's executor of every action in :data:`~hdrc3_tst.actions.ACTIONS` (a test checks)."""


__all__ = ["DATA_TIMEOUT_S", "RMAX_EXECUTORS", "airborne", "finish", "fly_to"]
