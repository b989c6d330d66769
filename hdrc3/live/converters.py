"""Converters: one per live channel, from ROS messages (or the world file) to encoded messages.

Pure: a converter gets the decoded ROS message, the agent whose namespace it came from and the
receive time (wall-clock ns, injected by the caller) and returns :class:`Output` values. Time
stamps in visual messages are that receive time, so that transforms and scene entities of all
channels share one clock with the log times; sim time stays in the JSON payloads.
"""

from __future__ import annotations

import json
import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Protocol

from foxglove.messages import (
    CompressedImage,
    CubePrimitive,
    CylinderPrimitive,
    FrameTransform,
    FrameTransforms,
    LinePrimitive,
    LinePrimitiveLineType,
    Log,
    LogLevel,
    SceneEntity,
    SceneEntityDeletion,
    SceneEntityDeletionType,
    SceneUpdate,
    SpherePrimitive,
    TextPrimitive,
    TriangleListPrimitive,
    Vector3,
)

from hdrc3.live.geometry import (
    WORLD_FRAME,
    attitude_quaternion,
    color,
    point,
    pose,
    quaternion,
    timestamp,
)
from hdrc3.live.images import ImageProblem, jpeg
from hdrc3.live.scene import ZONE, outline, prism, world_scene
from hdrc3.live.wire import encode_json
from hdrc3.message_types import constant_names
from hdrc3.mission_log import MONITOR_KINDS, RECOVERY_STEPS
from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.stamps import stamp_s
from hdrc3_hcsm.trace import TraceRecord
from hdrc3_interfaces.msg import MonitorViolation, PlatformEvent, RecoveryEvent
from hdrc3_navigation.messages import segment_from_msg
from hdrc3_perception.saliency_map import Location, MapError, MapParams, locations_from_geojson
from sim.world import World

POSE_PERIOD_NS = 40_000_000
"""Aircraft transforms at 25 Hz (wall clock): what a viewer needs, whatever the sim speed."""
TRACK_PERIOD_NS = 500_000_000
TRACK_STEP_M = 0.5
"""A track gets a new point when the aircraft moved this far."""
TRACK_MAX_POINTS = 4000
PATH_SAMPLES = 12
"""Points per cubic segment of a planned path."""
AGENT_COLORS = ((0.1, 0.6, 1.0), (1.0, 0.6, 0.1), (0.7, 0.3, 1.0), (0.2, 0.9, 0.4))


@dataclass(frozen=True, slots=True)
class Output:
    """One encoded message; ``key`` names what it replaces on a latched channel (the agent)."""

    key: str
    data: bytes


class SkipReason(StrEnum):
    """Why a converter dropped a source message (counted per converter, logged by the node)."""

    NON_FINITE = "non-finite values"
    MALFORMED_TRACE = "HCSM trace record not readable"
    MALFORMED_PATH = "planned path segment not valid"
    UNKNOWN_ENCODING = "image encoding not supported"
    BAD_IMAGE_SIZE = "image size does not match its data"
    ENCODER_FAILED = "JPEG encoder failed"
    MALFORMED_MAP = "saliency map is not a GeoJSON map of hdrc3_perception"


class Converter(Protocol):
    """Turns the messages of a channel's sources into that channel's messages."""

    skipped: Counter[SkipReason]
    """Source messages dropped so far, by reason."""

    def start(self, now_ns: int) -> list[Output]:
        """Messages known before any source message (the world), usually none."""

    def wants(self, source: str, agent: str, now_ns: int) -> bool:
        """False if a message from ``/<agent>/<source>`` at ``now_ns`` would give nothing.

        Lets a caller skip decoding it (a camera image the rate limit would drop).
        """

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """Messages for one ROS message from ``/<agent>/<source>``."""


def agent_color(agent: str, alpha: float = 1.0) -> Any:
    """A stable colour per agent name."""
    r, g, b = AGENT_COLORS[sum(agent.encode()) % len(AGENT_COLORS)]
    return color(r, g, b, alpha)


class ConverterBase:
    """No start messages, every message wanted, a skip counter."""

    def __init__(self, world: World) -> None:
        self.skipped: Counter[SkipReason] = Counter()

    def start(self, now_ns: int) -> list[Output]:
        """No messages before the sources'."""
        return []

    def wants(self, source: str, agent: str, now_ns: int) -> bool:
        """Every message may give output."""
        return True

    def _skip(self, reason: SkipReason) -> list[Output]:
        self.skipped[reason] += 1
        return []


class WorldConverter(ConverterBase):
    """The world file as one scene update, once (channel without sources)."""

    def __init__(self, world: World) -> None:
        super().__init__(world)
        self._world = world

    def start(self, now_ns: int) -> list[Output]:
        """The whole world scene."""
        return [Output("world", world_scene(self._world, now_ns).encode())]

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """No sources."""
        return []


class RateLimiter:
    """Lets one message per key through every ``period_ns`` on average (wall clock)."""

    def __init__(self, period_ns: int) -> None:
        self.period_ns = period_ns
        self._due: dict[str, int] = {}

    def ready(self, key: str, now_ns: int) -> bool:
        """True if ``key`` may send at ``now_ns`` (schedules nothing)."""
        due = self._due.get(key)
        return due is None or now_ns >= due

    def due(self, key: str, now_ns: int) -> bool:
        """True if ``key`` may send at ``now_ns``; schedules its next slot."""
        if not self.ready(key, now_ns):
            return False
        due = self._due.get(key)
        # keep the average period exact (a late message does not delay the next slot), but
        # never catch up a long pause in a burst: the next slot is at least half a period away
        nxt = now_ns + self.period_ns if due is None else due + self.period_ns
        self._due[key] = max(nxt, now_ns + self.period_ns // 2)
        return True


class TransformConverter(ConverterBase):
    """Ground truth -> ``world -> <agent>`` frame transforms at 25 Hz per agent."""

    def __init__(self, world: World, period_ns: int = POSE_PERIOD_NS) -> None:
        super().__init__(world)
        self._limit = RateLimiter(period_ns)

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """One FrameTransforms message when the agent's slot is due."""
        if not self._limit.due(agent, now_ns):
            return []
        x, y, z = (float(v) for v in msg.position_enu)
        q = attitude_quaternion(float(msg.roll), float(msg.pitch), float(msg.heading))
        if not all(math.isfinite(v) for v in (x, y, z, *q)):
            return self._skip(SkipReason.NON_FINITE)
        tf = FrameTransform(
            timestamp=timestamp(now_ns),
            parent_frame_id=WORLD_FRAME,
            child_frame_id=agent,
            translation=Vector3(x=x, y=y, z=z),
            rotation=quaternion(q),
        )
        return [Output(agent, FrameTransforms(transforms=[tf]).encode())]


class AircraftConverter(ConverterBase):
    """The aircraft model (fuselage, rotor disc, name) in its own frame, once per agent."""

    def __init__(self, world: World) -> None:
        super().__init__(world)
        self._seen: set[str] = set()

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The model of a newly seen agent."""
        if agent in self._seen:
            return []
        self._seen.add(agent)
        body = CubePrimitive(
            pose=pose(0, 0, 0.4), size=Vector3(x=3.6, y=0.7, z=1.0), color=agent_color(agent)
        )
        disc = Vector3(x=3.1, y=3.1, z=0.05)
        rotor = CylinderPrimitive(pose=pose(0, 0, 1.1), size=disc, color=color(0.2, 0.2, 0.2, 0.5))
        name = TextPrimitive(
            pose=pose(0, 0, 2.5),
            billboard=True,
            font_size=14.0,
            scale_invariant=True,
            color=color(1, 1, 1),
            text=agent,
        )
        entity = SceneEntity(
            timestamp=timestamp(now_ns),
            frame_id=agent,
            id=f"aircraft/{agent}",
            frame_locked=True,
            cubes=[body],
            cylinders=[rotor],
            texts=[name],
        )
        return [Output(agent, SceneUpdate(entities=[entity]).encode())]


def _line_entity(entity_id: str, agent: str, pts: Sequence[tuple[float, ...]], now_ns: int,
                 thickness: float, alpha: float) -> SceneEntity:  # fmt: skip
    line = LinePrimitive(
        type=LinePrimitiveLineType.LineStrip,
        pose=pose(),
        thickness=thickness,
        scale_invariant=True,
        points=[point(*p) for p in pts],
        color=agent_color(agent, alpha),
    )
    return SceneEntity(
        timestamp=timestamp(now_ns), frame_id=WORLD_FRAME, id=entity_id, lines=[line]
    )


class TrackConverter(ConverterBase):
    """Ground truth -> each agent's flown track as a line, refreshed twice a second."""

    def __init__(self, world: World, period_ns: int = TRACK_PERIOD_NS) -> None:
        super().__init__(world)
        self._limit = RateLimiter(period_ns)
        self._tracks: dict[str, list[tuple[float, float, float]]] = {}

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """Add the position to the track; the whole track when the agent's slot is due."""
        x, y, z = (float(v) for v in msg.position_enu)
        if not all(math.isfinite(v) for v in (x, y, z)):
            return self._skip(SkipReason.NON_FINITE)
        track = self._tracks.setdefault(agent, [])
        if not track or math.dist(track[-1], (x, y, z)) >= TRACK_STEP_M:
            track.append((x, y, z))
            if len(track) > TRACK_MAX_POINTS:
                del track[1::2]  # halve the resolution, keep the whole flight
        if len(track) < 2 or not self._limit.due(agent, now_ns):
            return []
        entity = _line_entity(f"track/{agent}", agent, track, now_ns, 2.0, 0.8)
        return [Output(agent, SceneUpdate(entities=[entity]).encode())]


class PlannedPathConverter(ConverterBase):
    """``planned_path`` -> the agent's planned path as a sampled curve (empty path: removed)."""

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The path's curve, or a deletion of the agent's path entity."""
        entity_id = f"planned_path/{agent}"
        pts: list[tuple[float, ...]] = []
        for i, seg_msg in enumerate(msg.segments):
            try:
                segment = segment_from_msg(seg_msg, i)
            except Hdrc3Error:  # a malformed path is not drawn (the planner validates its own)
                return self._skip(SkipReason.MALFORMED_PATH)
            first = 0 if not pts else 1
            pts += [
                tuple(float(v) for v in segment.position(k / PATH_SAMPLES))
                for k in range(first, PATH_SAMPLES + 1)
            ]
        if len(pts) < 2:
            gone = SceneEntityDeletion(
                timestamp=timestamp(now_ns), type=SceneEntityDeletionType.MatchingId, id=entity_id
            )
            return [Output(agent, SceneUpdate(deletions=[gone]).encode())]
        entity = _line_entity(entity_id, agent, pts, now_ns, 4.0, 0.5)
        return [Output(agent, SceneUpdate(entities=[entity]).encode())]


class GisConverter(ConverterBase):
    """``path_planner/gis_state`` -> runtime no-fly zones and obstacles of every agent's GIS."""

    def __init__(self, world: World) -> None:
        super().__init__(world)
        self._zones: dict[str, list[SceneEntity]] = {}

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """All agents' GIS volumes (replacing what the channel showed)."""
        entities = []
        for kind, zones, tint in (
            ("no_fly_zone", msg.no_fly_zones, ZONE),
            ("obstacle", msg.obstacles, color(0.9, 0.8, 0.1, 0.35)),
        ):
            for zone in zones:
                ring = list(zip(zone.polygon_east, zone.polygon_north, strict=False))
                floor, ceiling = float(zone.floor), float(zone.ceiling)
                values = [floor, ceiling, *(c for p in ring for c in p)]
                if len(ring) < 3 or floor > ceiling or not all(map(math.isfinite, values)):
                    continue
                volume = TriangleListPrimitive(
                    pose=pose(), points=prism(ring, floor, ceiling), color=tint
                )
                edge = LinePrimitive(
                    type=LinePrimitiveLineType.LineLoop,
                    pose=pose(),
                    thickness=2.0,
                    scale_invariant=True,
                    points=outline(ring, ceiling),
                    color=agent_color(agent),
                )
                entities.append(
                    SceneEntity(
                        timestamp=timestamp(now_ns),
                        frame_id=WORLD_FRAME,
                        id=f"gis/{agent}/{kind}/{zone.name}",
                        triangles=[volume],
                        lines=[edge],
                    )
                )
        self._zones[agent] = entities
        clear = SceneEntityDeletion(timestamp=timestamp(now_ns), type=SceneEntityDeletionType.All)
        every = [e for agent_zones in self._zones.values() for e in agent_zones]
        return [Output("gis", SceneUpdate(deletions=[clear], entities=every).encode())]


def _time_or_none(seconds: float) -> float | None:
    return float(seconds) if math.isfinite(seconds) else None


class TstConverter(ConverterBase):
    """``tst_status`` -> the latest state of every TST node of every agent, as one JSON table."""

    def __init__(self, world: World) -> None:
        super().__init__(world)
        self._nodes: dict[tuple[str, str, str], dict[str, Any]] = {}

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The whole table with the node of ``msg`` updated."""
        key = (str(msg.mission), str(msg.agent) or agent, str(msg.node_id))
        row: dict[str, Any] = {
            "mission": key[0],
            "agent": key[1],
            "node_id": str(msg.node_id),
            "parent": str(msg.parent),
            "kind": str(msg.kind),
            "state": str(msg.state),
            # NaN until known: JSON has no NaN (a browser's JSON.parse refuses it), so null
            "start": _time_or_none(msg.start),
            "end": _time_or_none(msg.end),
            "reason": str(msg.reason),
            "time": stamp_s(msg.header.stamp),
        }
        self._nodes[key] = row
        table = {"changed": row, "nodes": [self._nodes[k] for k in sorted(self._nodes)]}
        return [Output("tst", encode_json(table))]


class HcsmConverter(ConverterBase):
    """``hcsm/trace`` (JSON trace records) -> each agent's active HCSM states."""

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The configuration after the record's micro step (a bad record is skipped)."""
        try:
            record = TraceRecord.from_json(str(msg.data))
        except Hdrc3Error:
            return self._skip(SkipReason.MALFORMED_TRACE)
        payload = {
            "agent": agent,
            "computer": record.computer,
            "time": record.time,
            "event": record.event,
            "transitions": [f"{t.source} -> {t.target}" for t in record.transitions],
            "active_states": list(record.configuration),
        }
        return [Output(f"{agent}/{record.computer}", encode_json(payload))]


EVENT_LEVELS = {0: LogLevel.Info, 1: LogLevel.Error, 2: LogLevel.Warning, 3: LogLevel.Debug}
EVENT_KINDS = constant_names(PlatformEvent, "KIND_")
VIOLATION_LEVELS = {
    MonitorViolation.KIND_VIOLATION: LogLevel.Error,
    MonitorViolation.KIND_STALE_DATA: LogLevel.Warning,
    MonitorViolation.KIND_REFUSED: LogLevel.Warning,
}


def _platform_event(agent: str, msg: Any) -> tuple[LogLevel, str, str]:
    kind = int(msg.kind)
    text = f"{msg.command} #{msg.command_id} {EVENT_KINDS.get(kind, f'kind {kind}')}"
    return EVENT_LEVELS.get(kind, LogLevel.Info), f"{agent}/platform_server", text


def _execution_flag(agent: str, msg: Any) -> tuple[LogLevel, str, str]:
    state = "executing" if msg.executing else "done"
    text = f"{msg.mission}: {msg.agent or agent}/{msg.node_id} {msg.action} {state}"
    return LogLevel.Info, f"{agent}/tst_manager", text


def _monitor_violation(agent: str, msg: Any) -> tuple[LogLevel, str, str]:
    kind = int(msg.kind)
    word = MONITOR_KINDS.get(kind, f"kind {kind}")
    level = VIOLATION_LEVELS.get(kind, LogLevel.Warning)
    text = f"monitor {msg.monitor_id} {word}: {msg.formula}"
    bound = ", ".join(
        f"{n}={v}" for n, v in zip(msg.argument_names, msg.argument_values, strict=False)
    )
    if bound:
        text += f" [{bound}]"
    if msg.node_id:
        text += f" (node {msg.node_id} {msg.action})"
    if msg.recovery:
        text += f"; recovery {msg.recovery}"
    if msg.emergency_brake:
        text += "; emergency brake"
    return level, f"{msg.agent or agent}/execution_monitor", text


def _recovery_event(agent: str, msg: Any) -> tuple[LogLevel, str, str]:
    step = int(msg.step)
    word = RECOVERY_STEPS.get(step, f"step {step}")
    text = f"{msg.mission}: {msg.node_id} {word} ({msg.monitor_id}, attempt {msg.attempt})"
    if msg.recovery:
        text += f"; operator {msg.recovery}"
    if msg.changes:
        text += f"; changed {', '.join(msg.changes)}"
    if msg.plan:
        text += f"; plan {' / '.join(msg.plan)}"
    # the goal node fails: as bad as a failed command; every other step is progress
    level = LogLevel.Error if step == RecoveryEvent.STEP_GAVE_UP else LogLevel.Info
    return level, f"{msg.agent or agent}/tst_recovery", text


EVENT_SOURCES = {
    "platform_events": _platform_event,
    "execution_flags": _execution_flag,
    "monitor_violations": _monitor_violation,
    "recovery_events": _recovery_event,
}
"""Source suffix -> (level, log name, text) of one of its messages."""


class EventConverter(ConverterBase):
    """Platform events, TST execution flags, monitor violations, recoveries -> log lines.

    Levels: a failed command, a violated monitor formula and a recovery that gave up are errors;
    a cancelled command, stale monitor data and a formula that could not be activated are
    warnings; execution flags and the other recovery steps are info.
    """

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """One log line."""
        describe = EVENT_SOURCES.get(source)
        if describe is None:
            return []
        level, name, text = describe(agent, msg)
        if getattr(msg, "reason", ""):
            text += f": {msg.reason}"
        line = Log(
            timestamp=timestamp(now_ns),
            level=level,
            message=f"[t={stamp_s(msg.header.stamp):.2f}] {text}",
            name=name,
        )
        return [Output(agent, line.encode())]


IMAGE_PERIOD_NS = 200_000_000
"""Camera images at 5 Hz per camera and agent at most (the cameras publish up to 25 Hz)."""
IMAGE_MAX_WIDTH = 640
JPEG_QUALITY = 75
IMAGE_PROBLEMS = {
    ImageProblem.UNKNOWN_ENCODING: SkipReason.UNKNOWN_ENCODING,
    ImageProblem.BAD_SIZE: SkipReason.BAD_IMAGE_SIZE,
    ImageProblem.ENCODER_FAILED: SkipReason.ENCODER_FAILED,
}


class ImageConverter(ConverterBase):
    """``camera/<kind>/image_raw`` -> a JPEG ``CompressedImage``, rate-limited per agent.

    Rate and size, from measurement (``hdrc3/live/README.md``): at 640x480 a JPEG costs
    0.7-0.9 ms and decoding the ROS message 0.1 ms, so both cameras at 5 Hz cost the converter
    about 1 % of one core at full size (no downscale needed; 25 Hz would be 5-6 %). What costs
    more is the DDS delivery of every image (up to 25 Hz) to the live view, which no rate limit
    avoids: images the limit would drop are not even decoded (:meth:`wants`), and the node
    subscribes to a camera only while a client watches it. 5 Hz is enough to see what a camera
    sees and keeps the WebSocket at about 50-150 kB/s per camera. The frame is the camera's
    optical frame (``<agent>/color_optical``); the stamp is the receive time like every live
    channel's (the exposure's sim time is in the ROS topic).
    """

    def __init__(
        self,
        world: World,
        period_ns: int = IMAGE_PERIOD_NS,
        max_width: int = IMAGE_MAX_WIDTH,
        quality: int = JPEG_QUALITY,
    ) -> None:
        super().__init__(world)
        self._limit = RateLimiter(period_ns)
        self._max_width = max_width
        self._quality = quality

    def wants(self, source: str, agent: str, now_ns: int) -> bool:
        """True when the agent's slot is due."""
        return self._limit.ready(agent, now_ns)

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """One JPEG when the agent's slot is due; bad images are skipped (and counted)."""
        if not self._limit.due(agent, now_ns):
            return []
        data = jpeg(msg, self._max_width, self._quality)
        if isinstance(data, ImageProblem):
            return self._skip(IMAGE_PROBLEMS[data])
        kind = source.split("/")[1] if source.count("/") == 2 else "camera"
        image = CompressedImage(
            timestamp=timestamp(now_ns),
            frame_id=str(msg.header.frame_id) or f"{agent}/{kind}_optical",
            data=data,
            format="jpeg",
        )
        return [Output(agent, image.encode())]


SALIENCY_CONFIRMED = (0.1, 0.85, 0.2)


def _map_locations(text: str) -> list[tuple[Location, bool]] | None:
    """Locations of a GeoJSON saliency map with their ``confirmed`` flags, None if malformed."""
    try:
        data = json.loads(text)
        locations = locations_from_geojson(data)
    except (ValueError, RecursionError, MapError):
        return None
    params = MapParams()
    flags = [
        props.get("confirmed") if isinstance(props := feature["properties"], dict) else None
        for feature in data["features"]
    ]
    return [
        (loc, flag if isinstance(flag, bool) else loc.confirmed(params))
        for loc, flag in zip(locations, flags, strict=True)
    ]


class SaliencyConverter(ConverterBase):
    """``saliency/map`` (GeoJSON) -> the agent's salient locations in the world frame.

    One entity per agent (``saliency/<agent>``, replaced by each map): a sphere per location,
    green when confirmed as a person, else red to orange with the certainty p_body (opacity too),
    and a label ``p_body (T_body/T_frame)``. Positions are the map's ``east``/``north``/``up``:
    the local ENU frame of the world origin, the live view's ``world`` frame.
    """

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The agent's map entity, or its deletion for an empty map."""
        located = _map_locations(str(msg.data))
        if located is None:
            return self._skip(SkipReason.MALFORMED_MAP)
        entity_id = f"saliency/{agent}"
        if not located:
            gone = SceneEntityDeletion(
                timestamp=timestamp(now_ns), type=SceneEntityDeletionType.MatchingId, id=entity_id
            )
            return [Output(agent, SceneUpdate(deletions=[gone]).encode())]
        spheres, texts = [], []
        for loc, confirmed in located:
            p = min(1.0, max(0.0, loc.p_body))
            rgb = SALIENCY_CONFIRMED if confirmed else (1.0, 0.6 * p, 0.1)
            spheres.append(
                SpherePrimitive(
                    pose=pose(loc.east, loc.north, loc.up + 1.0),
                    size=Vector3(x=2.0, y=2.0, z=2.0),
                    color=color(*rgb, max(0.35, p)),
                )
            )
            texts.append(
                TextPrimitive(
                    pose=pose(loc.east, loc.north, loc.up + 3.0),
                    billboard=True,
                    font_size=12.0,
                    scale_invariant=True,
                    color=color(*rgb),
                    text=f"{p:.2f} ({loc.t_body}/{loc.t_frame})",
                )
            )
        entity = SceneEntity(
            timestamp=timestamp(now_ns),
            frame_id=WORLD_FRAME,
            id=entity_id,
            spheres=spheres,
            texts=texts,
        )
        return [Output(agent, SceneUpdate(entities=[entity]).encode())]
