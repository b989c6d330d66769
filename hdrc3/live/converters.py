"""Converters: one per live channel, from ROS messages (or the world file) to encoded messages.

Pure: a converter gets the decoded ROS message, the agent whose namespace it came from and the
receive time (wall-clock ns, injected by the caller) and returns :class:`Output` values. Time
stamps in visual messages are that receive time, so that transforms and scene entities of all
channels share one clock with the log times; sim time stays in the JSON payloads.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from foxglove.messages import (
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
from hdrc3.live.scene import ZONE, outline, prism, world_scene
from hdrc3.live.wire import encode_json
from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.stamps import stamp_s
from hdrc3_hcsm.trace import TraceRecord
from hdrc3_navigation.messages import segment_from_msg
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


class Converter(Protocol):
    """Turns the messages of a channel's sources into that channel's messages."""

    def start(self, now_ns: int) -> list[Output]:
        """Messages known before any source message (the world), usually none."""

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """Messages for one ROS message from ``/<agent>/<source>``."""


def agent_color(agent: str, alpha: float = 1.0) -> Any:
    """A stable colour per agent name."""
    r, g, b = AGENT_COLORS[sum(agent.encode()) % len(AGENT_COLORS)]
    return color(r, g, b, alpha)


class _NoStart:
    def start(self, now_ns: int) -> list[Output]:
        return []


class WorldConverter:
    """The world file as one scene update, once (channel without sources)."""

    def __init__(self, world: World) -> None:
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

    def due(self, key: str, now_ns: int) -> bool:
        """True if ``key`` may send at ``now_ns``; schedules its next slot."""
        due = self._due.get(key)
        if due is not None and now_ns < due:
            return False
        # keep the average period exact (a late message does not delay the next slot), but
        # never catch up a long pause in a burst: the next slot is at least half a period away
        nxt = now_ns + self.period_ns if due is None else due + self.period_ns
        self._due[key] = max(nxt, now_ns + self.period_ns // 2)
        return True


class TransformConverter(_NoStart):
    """Ground truth -> ``world -> <agent>`` frame transforms at 25 Hz per agent."""

    def __init__(self, world: World, period_ns: int = POSE_PERIOD_NS) -> None:
        self._limit = RateLimiter(period_ns)

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """One FrameTransforms message when the agent's slot is due."""
        if not self._limit.due(agent, now_ns):
            return []
        x, y, z = (float(v) for v in msg.position_enu)
        q = attitude_quaternion(float(msg.roll), float(msg.pitch), float(msg.heading))
        if not all(math.isfinite(v) for v in (x, y, z, *q)):
            return []
        tf = FrameTransform(
            timestamp=timestamp(now_ns),
            parent_frame_id=WORLD_FRAME,
            child_frame_id=agent,
            translation=Vector3(x=x, y=y, z=z),
            rotation=quaternion(q),
        )
        return [Output(agent, FrameTransforms(transforms=[tf]).encode())]


class AircraftConverter(_NoStart):
    """The aircraft model (fuselage, rotor disc, name) in its own frame, once per agent."""

    def __init__(self, world: World) -> None:
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


class TrackConverter(_NoStart):
    """Ground truth -> each agent's flown track as a line, refreshed twice a second."""

    def __init__(self, world: World, period_ns: int = TRACK_PERIOD_NS) -> None:
        self._limit = RateLimiter(period_ns)
        self._tracks: dict[str, list[tuple[float, float, float]]] = {}

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """Add the position to the track; the whole track when the agent's slot is due."""
        x, y, z = (float(v) for v in msg.position_enu)
        if not all(math.isfinite(v) for v in (x, y, z)):
            return []
        track = self._tracks.setdefault(agent, [])
        if not track or math.dist(track[-1], (x, y, z)) >= TRACK_STEP_M:
            track.append((x, y, z))
            if len(track) > TRACK_MAX_POINTS:
                del track[1::2]  # halve the resolution, keep the whole flight
        if len(track) < 2 or not self._limit.due(agent, now_ns):
            return []
        entity = _line_entity(f"track/{agent}", agent, track, now_ns, 2.0, 0.8)
        return [Output(agent, SceneUpdate(entities=[entity]).encode())]


class PlannedPathConverter(_NoStart):
    """``planned_path`` -> the agent's planned path as a sampled curve (empty path: removed)."""

    def __init__(self, world: World) -> None:
        pass

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The path's curve, or a deletion of the agent's path entity."""
        entity_id = f"planned_path/{agent}"
        pts: list[tuple[float, ...]] = []
        for i, seg_msg in enumerate(msg.segments):
            try:
                segment = segment_from_msg(seg_msg, i)
            except Hdrc3Error:
                return []  # a malformed path is not drawn (the planner validates its own)
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


class GisConverter(_NoStart):
    """``path_planner/gis_state`` -> runtime no-fly zones and obstacles of every agent's GIS."""

    def __init__(self, world: World) -> None:
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


class TstConverter(_NoStart):
    """``tst_status`` -> the latest state of every TST node of every agent, as one JSON table."""

    def __init__(self, world: World) -> None:
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


class HcsmConverter(_NoStart):
    """``hcsm/trace`` (JSON trace records) -> each agent's active HCSM states."""

    def __init__(self, world: World) -> None:
        pass

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """The configuration after the record's micro step (a bad record is skipped)."""
        try:
            record = TraceRecord.from_json(str(msg.data))
        except Hdrc3Error:
            return []
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
EVENT_KINDS = {0: "finished", 1: "failed", 2: "cancelled", 3: "segment request", 4: "info"}


class EventConverter(_NoStart):
    """Platform events and TST execution flags -> Foxglove log lines."""

    def __init__(self, world: World) -> None:
        pass

    def convert(self, source: str, agent: str, msg: Any, now_ns: int) -> list[Output]:
        """One log line."""
        if source == "platform_events":
            kind = int(msg.kind)
            text = f"{msg.command} #{msg.command_id} {EVENT_KINDS.get(kind, f'kind {kind}')}"
            level = EVENT_LEVELS.get(kind, LogLevel.Info)
            name = f"{agent}/platform_server"
        else:  # execution_flags
            state = "executing" if msg.executing else "done"
            text = f"{msg.mission}: {msg.agent or agent}/{msg.node_id} {msg.action} {state}"
            level = LogLevel.Info
            name = f"{agent}/tst_manager"
        if getattr(msg, "reason", ""):
            text += f": {msg.reason}"
        line = Log(
            timestamp=timestamp(now_ns),
            level=level,
            message=f"[t={stamp_s(msg.header.stamp):.2f}] {text}",
            name=name,
        )
        return [Output(agent, line.encode())]
