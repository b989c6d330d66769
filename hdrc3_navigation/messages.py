"""Navigation values <-> ``hdrc3_interfaces`` messages: one converter per layout.

The path planner node, the TST's navigation port and the demo mission all convert through
here, so a segment or a runtime world model crosses the wire in exactly one way.
"""

from __future__ import annotations

import math
from typing import Any

from geometry_msgs.msg import Point, Vector3

from hdrc3_control.path_segment import PathSegment
from hdrc3_interfaces.msg import GisState, GisZone
from hdrc3_interfaces.msg import PathSegment as PathSegmentMsg
from hdrc3_navigation.gis import Zone
from hdrc3_navigation.runtime_world import RuntimeWorld

Vec3 = tuple[float, float, float]


def point_msg(p: Vec3) -> Point:
    """``geometry_msgs/Point`` of an (e, n, u) triple."""
    return Point(x=float(p[0]), y=float(p[1]), z=float(p[2]))


def vector_msg(v: Vec3) -> Vector3:
    """``geometry_msgs/Vector3`` of an (e, n, u) triple."""
    return Vector3(x=float(v[0]), y=float(v[1]), z=float(v[2]))


def triple(msg: Any) -> Vec3:
    """(x, y, z) of a Point or Vector3."""
    return (float(msg.x), float(msg.y), float(msg.z))


def segment_to_msg(segment: PathSegment) -> PathSegmentMsg:
    """A cubic segment as ``hdrc3_interfaces/PathSegment``."""
    return PathSegmentMsg(
        start_point=point_msg(segment.start),
        end_point=point_msg(segment.end),
        start_direction=vector_msg(segment.start_direction),
        end_direction=vector_msg(segment.end_direction),
        target_velocity=float(segment.target_velocity),
        end_velocity=float(segment.end_velocity),
    )


def segment_from_msg(msg: Any, segment_id: int = 0) -> PathSegment:
    """``hdrc3_interfaces/PathSegment`` as a segment (ConfigError if it is not one)."""
    return PathSegment(
        triple(msg.start_point),
        triple(msg.end_point),
        triple(msg.start_direction),
        triple(msg.end_direction),
        float(msg.target_velocity),
        float(msg.end_velocity),
        segment_id,
    )


def _zone_msg(zone: Zone) -> GisZone:
    return GisZone(
        name=zone.name,
        polygon_east=[float(p[0]) for p in zone.polygon],
        polygon_north=[float(p[1]) for p in zone.polygon],
        floor=float(zone.floor),
        ceiling=float(zone.ceiling),
    )


def _zone(msg: Any) -> Zone:
    polygon = tuple(zip(map(float, msg.polygon_east), map(float, msg.polygon_north), strict=False))
    return Zone(str(msg.name), polygon, float(msg.floor), float(msg.ceiling))


def world_to_msg(world: RuntimeWorld) -> GisState:
    """The runtime world model as ``hdrc3_interfaces/GisState``."""
    return GisState(
        revision=world.revision,
        margin=world.margin,
        no_fly_zones=[_zone_msg(z) for z in world.no_fly_zones],
        obstacles=[_zone_msg(z) for z in world.obstacles],
    )


def world_from_msg(msg: Any) -> RuntimeWorld:
    """``hdrc3_interfaces/GisState`` as the runtime world model (bad regions are dropped)."""
    margin = float(msg.margin)
    return RuntimeWorld(
        int(msg.revision),
        margin if math.isfinite(margin) and margin >= 0.0 else 0.0,
        tuple(_zone(z) for z in msg.no_fly_zones if len(z.polygon_east) >= 3),
        tuple(_zone(z) for z in msg.obstacles if len(z.polygon_east) >= 3),
    )
