"""Navigation values <-> ``hdrc3_interfaces`` messages: one converter per layout.

The path planner node, the TST's navigation port and the demo mission all convert through
here, so a segment, a runtime world model or an elevation map crosses the wire in exactly one
way.
"""

from __future__ import annotations

import array
import math
from typing import Any

import numpy as np
from geometry_msgs.msg import Point, Vector3

from hdrc3_base.errors import Hdrc3Error
from hdrc3_control.path_segment import PathSegment
from hdrc3_interfaces.msg import ElevationMap as ElevationMapMsg
from hdrc3_interfaces.msg import GisState, GisZone
from hdrc3_interfaces.msg import PathSegment as PathSegmentMsg
from hdrc3_navigation.elevation_map import MAX_CELLS, ElevationMap
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
        elevation_maps=list(world.elevation_maps),
    )


def world_from_msg(msg: Any) -> RuntimeWorld:
    """``hdrc3_interfaces/GisState`` as the runtime world model (bad regions are dropped)."""
    margin = float(msg.margin)
    return RuntimeWorld(
        int(msg.revision),
        margin if math.isfinite(margin) and margin >= 0.0 else 0.0,
        tuple(_zone(z) for z in msg.no_fly_zones if len(z.polygon_east) >= 3),
        tuple(_zone(z) for z in msg.obstacles if len(z.polygon_east) >= 3),
        tuple(str(name) for name in msg.elevation_maps),
    )


def elevation_map_to_msg(elevation_map: ElevationMap) -> ElevationMapMsg:
    """An elevation map as ``hdrc3_interfaces/ElevationMap`` (heights as float32, row-major)."""
    m = elevation_map
    returns = m.returns.astype(np.uint32) if m.returns.size else np.zeros(0, dtype=np.uint32)
    return ElevationMapMsg(
        name=m.name,
        east0=float(m.east0),
        north0=float(m.north0),
        resolution=float(m.resolution),
        columns=m.columns,
        rows=m.rows,
        heights=array.array("f", m.heights.astype(np.float32).tobytes()),
        returns=array.array("I", returns.tobytes()),
    )


def elevation_map_from_msg(msg: Any) -> ElevationMap | str:
    """``hdrc3_interfaces/ElevationMap`` as an elevation map, or the reason it is malformed.

    Never raises: a wrong number of heights or returns, an empty or oversized grid, a bad
    resolution, origin or name, infinite heights are answered with a readable reason.
    """
    name = "?"
    try:
        name = str(msg.name)
        rows, columns = int(msg.rows), int(msg.columns)
        if rows <= 0 or columns <= 0:
            return f"elevation map {name!r}: {rows} rows x {columns} columns, both must be > 0"
        cells = rows * columns
        if cells > MAX_CELLS:
            return f"elevation map {name!r}: {cells} cells, more than {MAX_CELLS}"
        if len(msg.heights) != cells:
            return (
                f"elevation map {name!r}: {len(msg.heights)} heights for {rows} rows x "
                f"{columns} columns ({cells} expected)"
            )
        if len(msg.returns) not in (0, cells):
            return f"elevation map {name!r}: {len(msg.returns)} returns, expected 0 or {cells}"
        heights = np.asarray(msg.heights, dtype=np.float64).reshape(rows, columns)
        returns = np.asarray(msg.returns, dtype=np.int64)
        if returns.size:
            returns = returns.reshape(rows, columns)
        else:
            returns = np.zeros((0, 0), dtype=np.int64)
        return ElevationMap(
            name,
            float(msg.east0),
            float(msg.north0),
            float(msg.resolution),
            heights,
            returns,
        )
    except (Hdrc3Error, ValueError, TypeError, OverflowError, AttributeError) as exc:
        return f"elevation map {name!r}: {exc}"
