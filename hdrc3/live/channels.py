"""The registry of live channels: one source of truth for names, schemas, sources, converters.

The live view node, the recorder and the saved Foxglove layout (``foxglove/hdrc3.json``, checked
by a test) all read this table. Names start with ``/live/``: in a recording they sit beside the
ROS topics (``/hdrc3/launch_status`` is one) and must not be taken for them. A new channel
(camera images, the saliency map) is one more :class:`LiveChannel` here with its converter;
nothing else changes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from foxglove.messages import FrameTransforms, Log, SceneUpdate

from hdrc3.live.converters import (
    AircraftConverter,
    Converter,
    EventConverter,
    GisConverter,
    HcsmConverter,
    PlannedPathConverter,
    TrackConverter,
    TransformConverter,
    TstConverter,
    WorldConverter,
)
from hdrc3.live.wire import WireSchema
from sim.world import World


@dataclass(frozen=True, slots=True)
class Source:
    """A ROS topic in every agent's namespace: ``/<agent>/<suffix>`` of type ``type_name``."""

    suffix: str
    type_name: str


@dataclass(frozen=True, slots=True)
class LiveChannel:
    """One Foxglove channel of the live view."""

    topic: str
    schema: WireSchema
    sources: tuple[Source, ...]
    make: Callable[[World], Converter]
    latched: bool
    """A subscribing client gets the latest message of every key again (static or slow data)."""
    description: str


TRUTH = Source("ground_truth/state", "hdrc3_interfaces/msg/TruthState")
TST_ROW = {
    "type": "object",
    "properties": {
        k: {"type": "number"} if k in ("start", "end", "time") else {"type": "string"}
        for k in ("mission", "agent", "node_id", "parent", "kind", "state", "start", "end",
                  "reason", "time")
    },
}  # fmt: skip

CHANNELS: tuple[LiveChannel, ...] = (
    LiveChannel(
        "/live/world",
        WireSchema.well_known(SceneUpdate),
        (),
        WorldConverter,
        True,
        "terrain, buildings, no-fly zones and roads of the world file",
    ),
    LiveChannel(
        "/live/tf",
        WireSchema.well_known(FrameTransforms),
        (TRUTH,),
        TransformConverter,
        False,
        "world -> <agent> pose of every aircraft, 25 Hz",
    ),
    LiveChannel(
        "/live/aircraft",
        WireSchema.well_known(SceneUpdate),
        (TRUTH,),
        AircraftConverter,
        True,
        "aircraft models, in their own frames",
    ),
    LiveChannel(
        "/live/tracks",
        WireSchema.well_known(SceneUpdate),
        (TRUTH,),
        TrackConverter,
        True,
        "flown tracks, 2 Hz",
    ),
    LiveChannel(
        "/live/planned_paths",
        WireSchema.well_known(SceneUpdate),
        (Source("planned_path", "hdrc3_interfaces/msg/Path"),),
        PlannedPathConverter,
        True,
        "the path each agent follows (cubic segments)",
    ),
    LiveChannel(
        "/live/gis",
        WireSchema.well_known(SceneUpdate),
        (Source("path_planner/gis_state", "hdrc3_interfaces/msg/GisState"),),
        GisConverter,
        True,
        "the path planners' runtime no-fly zones and obstacles",
    ),
    LiveChannel(
        "/live/tst",
        WireSchema.json_schema(
            "hdrc3.TstTable", {"changed": TST_ROW, "nodes": {"type": "array", "items": TST_ROW}}
        ),
        (Source("tst_status", "hdrc3_interfaces/msg/TstNodeStatus"),),
        TstConverter,
        True,
        "latest state of every TST node (JSON)",
    ),
    LiveChannel(
        "/live/hcsm",
        WireSchema.json_schema(
            "hdrc3.HcsmActiveStates",
            {
                "agent": {"type": "string"},
                "computer": {"type": "string"},
                "time": {"type": "number"},
                "event": {"type": "string"},
                "transitions": {"type": "array", "items": {"type": "string"}},
                "active_states": {"type": "array", "items": {"type": "string"}},
            },
        ),
        (Source("hcsm/trace", "std_msgs/msg/String"),),
        HcsmConverter,
        True,
        "active HCSM states of each agent's control kernel (JSON)",
    ),
    LiveChannel(
        "/live/events",
        WireSchema.well_known(Log),
        (
            Source("platform_events", "hdrc3_interfaces/msg/PlatformEvent"),
            Source("execution_flags", "hdrc3_interfaces/msg/ExecutionFlag"),
        ),
        EventConverter,
        False,
        "platform events and TST execution flags (log lines)",
    ),
)
CHANNEL_NAMES = tuple(c.topic for c in CHANNELS)
