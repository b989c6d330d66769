"""The registry of live channels: one source of truth for names, schemas, sources, converters.

The live view node, the recorder and the saved Foxglove layout (``foxglove/hdrc3.json``, checked
by a test) all read this table. Names start with ``/live/``: in a recording they sit beside the
ROS topics (``/hdrc3/launch_status`` is one) and must not be taken for them. A new channel is one
more :class:`LiveChannel` here with its converter; nothing else changes.

Camera images are per agent (``/live/camera/color/uav0``): Foxglove's Image panel shows one
topic, and images of several agents on one channel would alternate in it (an image's frame id
does not select). They are also on demand: the renderer draws a camera only while its topic has
a subscriber, so the live view subscribes to the images only while a client subscribes to the
agent's image channel.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from foxglove.messages import CompressedImage, FrameTransforms, Log, SceneUpdate

from hdrc3.live.converters import (
    AircraftConverter,
    Converter,
    EventConverter,
    GisConverter,
    HcsmConverter,
    ImageConverter,
    PlannedPathConverter,
    SaliencyConverter,
    TrackConverter,
    TransformConverter,
    TstConverter,
    WorldConverter,
)
from hdrc3.live.wire import WireSchema
from hdrc3_base.agents import AGENT_NAME
from sim.world import World


@dataclass(frozen=True, slots=True)
class Source:
    """A ROS topic in every agent's namespace: ``/<agent>/<suffix>`` of type ``type_name``."""

    suffix: str
    type_name: str
    newest_only: bool = False
    """Subscribe best effort with a queue of one (sensor data): a slow live view never holds
    up the publisher (world_render's images are reliable, and world_sim waits for the renderer)
    and only the newest message is taken; otherwise the QoS follows the publishers'."""


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
    per_agent: bool = False
    """One channel per agent, ``<topic>/<agent>``, advertised when the agent's source appears."""
    on_demand: bool = False
    """The sources are subscribed only while a client subscribes to the channel."""

    def instance(self, agent: str) -> str:
        """The channel name that carries ``agent``'s messages."""
        return f"{self.topic}/{agent}" if self.per_agent else self.topic


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
            Source("monitor_violations", "hdrc3_interfaces/msg/MonitorViolation"),
            Source("recovery_events", "hdrc3_interfaces/msg/RecoveryEvent"),
        ),
        EventConverter,
        False,
        "platform events, TST execution flags, monitor violations, recovery steps (log lines)",
    ),
    LiveChannel(
        "/live/saliency",
        WireSchema.well_known(SceneUpdate),
        (Source("saliency/map", "std_msgs/msg/String"),),
        SaliencyConverter,
        True,
        "salient locations (people) of each agent's saliency map, by certainty",
    ),
    LiveChannel(
        "/live/camera/color",
        WireSchema.well_known(CompressedImage),
        (Source("camera/color/image_raw", "sensor_msgs/msg/Image", newest_only=True),),
        ImageConverter,
        False,
        "colour camera, JPEG, 5 Hz, one channel per agent",
        per_agent=True,
        on_demand=True,
    ),
    LiveChannel(
        "/live/camera/thermal",
        WireSchema.well_known(CompressedImage),
        (Source("camera/thermal/image_raw", "sensor_msgs/msg/Image", newest_only=True),),
        ImageConverter,
        False,
        "thermal camera (white hot), JPEG, 5 Hz, one channel per agent",
        per_agent=True,
        on_demand=True,
    ),
)
CHANNEL_NAMES = tuple(c.topic for c in CHANNELS)
"""Registry names; a per-agent channel is advertised as ``<name>/<agent>``."""
STATIC_CHANNEL_NAMES = tuple(c.topic for c in CHANNELS if not c.per_agent)
"""Channels advertised from the start."""


def registered(topic: str, channels: tuple[LiveChannel, ...] = CHANNELS) -> LiveChannel | None:
    """The registry entry of an advertised channel name (a per-agent one too), or None."""
    parent, _, agent = topic.rpartition("/")
    for c in channels:
        if topic == c.topic and not c.per_agent:
            return c
        if c.per_agent and parent == c.topic and AGENT_NAME.match(agent):
            return c
    return None
