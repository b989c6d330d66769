"""ROS 2 adapter: the ``laser_mapper`` node (one per agent namespace), elevation maps (§11.2).

The chapter integrates map building "as a perception functionality of the Control Kernel" and
saves the maps "in the GIS Service database". The node follows the PPC's latched
``laser/command`` (``LaserCommand``): when its ``collect`` flag rises (PPCL
``laser_start_data_collection``) a new map begins and ``sensors/laser`` (``RotatingLaserScan``)
is subscribed; the Data Interface's ``helicopter_state`` registers each scan. When the flag
falls (``laser_stop_data_collection``) the scans are unsubscribed (the simulator casts no rays
for nobody) and the map is finished:

- ``~/elevation_map`` (``ElevationMap``, latched): the grid, cropped to the mapped cells;
- ``~/changes`` (``std_msgs/String``, latched, JSON): the overlay with the world model the stack
  holds (its ``world`` file): regions higher (``new``) or lower (``removed``) than the model;
- the map is stored in the GIS of the agent's path planner (``path_planner/gis_elevation_map``),
  which from then on plans around it with its margin; ``~/status`` (``std_msgs/String``,
  latched, JSON) says what happened (``collecting``, ``stored``, ``not_stored`` with a reason).

While collecting, ``~/points`` (``sensor_msgs/PointCloud2``, ``x y z`` float32 in the ``map``
frame, local ENU) carries the registered returns when someone subscribes.

Parameters: ``world`` (shipped name or .toml path: origin, model and area mapped), ``agents``
and ``speed`` (taken from the launcher, unused), ``resolution`` (m, default 1.0),
``max_range_used`` (m, default 60), ``align_search`` (m, default 6; 0: off): the finished map
is moved onto the model by the horizontal shift within this distance, and the height offset,
that fit it best (:meth:`~hdrc3_navigation.elevation_map.ElevationMap.aligned_to`: the GPS
offset of metres that every return carries), before it is compared and stored.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.subscription import Subscription
from sensor_msgs.msg import PointCloud2, PointField
from std_msgs.msg import String

from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults
from hdrc3_base.ros_runtime import run_node
from hdrc3_base.stamps import set_stamp_s, stamp_s
from hdrc3_control.perception_kernel_node import LATCHED
from hdrc3_interfaces.msg import ElevationMap as ElevationMapMsg
from hdrc3_interfaces.msg import HelicopterState, LaserCommand, RotatingLaserScan
from hdrc3_interfaces.srv import GisElevationMap
from hdrc3_navigation.elevation_map import ElevationMap
from hdrc3_navigation.messages import elevation_map_to_msg
from hdrc3_perception.camera import NavPose
from hdrc3_perception.laser_mapping import LaserMapper, MapperConfig, ScanLine
from hdrc3_platform_server.geo_frame import WorldFrame
from sim.world_loader import load_world

SCAN_QOS = QoSProfile(depth=200, reliability=ReliabilityPolicy.RELIABLE)
STATE_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
GIS_SERVICE = "path_planner/gis_elevation_map"
_XYZ = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1) for i, n in
        enumerate("xyz")]  # fmt: skip


def cropped(m: ElevationMap) -> ElevationMap:
    """The map cut down to the bounding box of its mapped cells (one cell at least)."""
    rows, cols = np.nonzero(m.mapped)
    if not len(rows):
        return m
    r0, r1, c0, c1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    returns = m.returns[r0:r1, c0:c1] if m.returns.size else m.returns
    return ElevationMap(
        m.name,
        m.east0 + float(c0) * m.resolution,
        m.north0 + float(r0) * m.resolution,
        m.resolution,
        m.heights[r0:r1, c0:c1],
        returns,
    )


def cloud_msg(points: NDArray[np.float64], time: float) -> PointCloud2:
    """Points (N x 3, ENU) as a ``PointCloud2`` in the ``map`` frame."""
    msg = PointCloud2()
    set_stamp_s(msg.header.stamp, time)
    msg.header.frame_id = "map"
    msg.height, msg.width = 1, len(points)
    msg.fields, msg.is_bigendian, msg.point_step = _XYZ, sys.byteorder == "big", 12
    msg.row_step, msg.is_dense = 12 * len(points), True
    msg.data = np.ascontiguousarray(points, dtype=np.float32).tobytes()
    return msg


class LaserMapperNode(Node):
    """Builds an elevation map while the PPC collects laser data; stores it in the GIS."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("laser_mapper", **kwargs)
        world_name = str(self.declare_parameter("world", "revinge").value)
        self.declare_parameter("agents", [""])
        self.declare_parameter("speed", 1.0)
        config = MapperConfig(
            resolution=float(self.declare_parameter("resolution", 1.0).value),
            max_range_used=float(self.declare_parameter("max_range_used", 60.0).value),
        )
        self._search = float(self.declare_parameter("align_search", 6.0).value)
        self._world = load_world(world_name)
        origin = self._world.origin
        self._frame = WorldFrame(origin.latitude, origin.longitude, origin.altitude)
        self.mapper = LaserMapper(self._world.bounds, config)
        self.collecting = False
        self.maps = 0
        """Maps finished so far (the next one's number)."""
        self._scans: Subscription | None = None
        self._map_pub = self.create_publisher(ElevationMapMsg, "~/elevation_map", LATCHED)
        self._changes_pub = self.create_publisher(String, "~/changes", LATCHED)
        self._status_pub = self.create_publisher(String, "~/status", LATCHED)
        self._points_pub = self.create_publisher(PointCloud2, "~/points", SCAN_QOS)
        self._gis = self.create_client(GisElevationMap, GIS_SERVICE)
        self.create_subscription(LaserCommand, "laser/command", self._on_command, LATCHED)
        self.create_subscription(HelicopterState, "helicopter_state", self._on_state, STATE_QOS)

    def _status(self, status: str, **fields: Any) -> None:
        self._status_pub.publish(String(data=json.dumps({"status": status, **fields})))

    def _on_command(self, msg: LaserCommand) -> None:
        if msg.collect and not self.collecting:
            self.collecting = True
            self.mapper.reset()
            self._scans = self.create_subscription(
                RotatingLaserScan, "sensors/laser", self._on_scan, SCAN_QOS
            )
            self._status("collecting", map=self._name())
        elif not msg.collect and self.collecting:
            self.collecting = False
            if self._scans is not None:
                self.destroy_subscription(self._scans)
                self._scans = None
            self._finish()

    def _name(self) -> str:
        return f"lrf-{self.get_namespace().strip('/') or 'map'}-{self.maps + 1}"

    def _on_scan(self, msg: RotatingLaserScan) -> None:
        if self.collecting:
            self.mapper.add_scan(
                ScanLine(
                    stamp_s(msg.header.stamp),
                    float(msg.rotation_angle),
                    float(msg.angle_min),
                    float(msg.angle_increment),
                    np.asarray(msg.ranges, dtype=np.float64),
                )
            )

    def _on_state(self, msg: HelicopterState) -> None:
        pose = NavPose.of_state(self._frame, msg)
        if not (self.collecting and pose.is_finite()):
            return
        time = stamp_s(msg.header.stamp)
        clouds = self.mapper.add_state(time, pose)
        if clouds and self._points_pub.get_subscription_count():
            self._points_pub.publish(cloud_msg(np.vstack(clouds), time))

    def _finish(self) -> None:
        name = self._name()
        self.maps += 1
        if not self.mapper.mapped_cells:
            self._status("not_stored", map=name, reason="no cell of the map got a return")
            return
        m = cropped(self.mapper.snapshot(name))
        summary: dict[str, Any] = {"map": name, "points": self.mapper.points}
        if self._search > 0.0:
            m, shift = m.aligned_to(self._world.surface_heights, self._search)
            summary["aligned"] = {"east": shift.east, "north": shift.north, "up": shift.up}
        summary["cells"] = int(m.mapped.sum())
        msg = elevation_map_to_msg(m)
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = "map"
        self._map_pub.publish(msg)
        changes = [
            {
                "kind": c.kind.value,
                "area_m2": c.area,
                "centre": list(c.centre),
                "bounds": list(c.bounds),
                "height_m": round(c.height, 2),
            }
            for c in m.compare(self._world.surface_heights)
        ]
        self._changes_pub.publish(String(data=json.dumps({"map": name, "changes": changes})))
        if not self._gis.service_is_ready():
            self._status("not_stored", **summary, reason=f"no GIS service {GIS_SERVICE}")
            return
        future = self._gis.call_async(GisElevationMap.Request(map=msg))
        future.add_done_callback(lambda f: self._stored(f, summary))

    def _stored(self, future: Any, summary: dict[str, Any]) -> None:
        result = future.result()
        if result is None or not result.success:
            reason = "no answer" if result is None else result.reason
            self._status("not_stored", **summary, reason=reason)
        else:
            self._status("stored", **summary, triangles=result.triangles, revision=result.revision)


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``hdrc3-laser-mapper``; accepts ``--ros-args`` (e.g. ``-r __ns:=/uav0``)."""
    apply_dds_defaults()
    try:
        return run_node(
            lambda context: LaserMapperNode(context=context), sys.argv if argv is None else argv
        )
    except Hdrc3Error as exc:
        print(f"hdrc3-laser-mapper: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
