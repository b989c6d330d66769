"""ROS 2 adapter: the ``color_tracker`` node (one per agent namespace), §6.1 / §6.2.3.

The PPC engages it on ``ppcl_ip_color_tracker(x, y)`` (``ImageProcessing.COLOR_TRACKER`` on the
latched ``ppc/image_processing``; see :mod:`hdrc3_perception.image_gate`) and publishes the seed
on :data:`SEED_TOPIC` (latched ``geometry_msgs/PointStamped``: point.x = column, point.y = row,
stamp = when the command was given). A new seed restarts tracking on the first colour image taken
at or after the seed's stamp; the tracker forgets its target when the PPC engages another
function.

While engaged it subscribes ``camera/color/image_raw`` (``rgb8``) with its ``camera_info``, the
Data Interface's ``helicopter_state`` (the aircraft's own navigation solution, WGS84 -> ENU of
the world's origin) and the PTU read-out ``sensors/ptu``, and publishes one
``hdrc3_interfaces/ColorTrack`` per image on ``~/track`` (:data:`TRACK_TOPIC` under the agent's
namespace; reliable, depth 50): status, reason, the target's pixel, area, direction in the optical
frame, and its ground point (ENU) from the navigation state nearest the image's time and the PTU
angles interpolated to it (:func:`hdrc3_perception.colour_tracking.locate`). A bad image or seed
gives a status and a reason, never an exception. Also ``~/engaged`` (latched ``Bool``).

Parameters: ``gated`` (default true), ``world`` (default ``revinge``: origin and terrain).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np
from geometry_msgs.msg import PointStamped
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from rclpy.subscription import Subscription
from sensor_msgs.msg import CameraInfo, Image

from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults
from hdrc3_base.ros_runtime import run_node
from hdrc3_base.stamps import stamp_ns, stamp_s
from hdrc3_control.perception_kernel_node import COLOR_TRACK_TOPIC, COLOR_TRACKER_SEED_TOPIC
from hdrc3_control.ppc_modes import ImageProcessing
from hdrc3_interfaces.msg import ColorTrack, HelicopterState, PtuState
from hdrc3_perception.camera import Intrinsics, NavPose
from hdrc3_perception.colour_tracking import (
    CameraView,
    ColourTracker,
    TrackResult,
    TrackStatus,
    locate,
)
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.history import NavHistory, PtuHistory
from hdrc3_perception.image_gate import LATCHED, ImageGate
from hdrc3_perception.node import PTU_QOS, RESULT_QOS, STATE_QOS, image_array
from hdrc3_platform_server.geo_frame import WorldFrame
from sim.world_loader import load_world

SEED_TOPIC = COLOR_TRACKER_SEED_TOPIC
"""The PPC's seed (latched ``PointStamped``), relative to the agent's namespace."""
TRACK_TOPIC = COLOR_TRACK_TOPIC
"""The node's ``~/track`` relative to the agent's namespace (``/uav0/color_tracker/track``)."""
SEED_QOS = LATCHED
TRACK_QOS = RESULT_QOS
OPTICAL_FRAME = "camera_color_optical"


class ColorTrackerNode(Node):
    """Tracks the PPC's seeded object in each colour image while the PPC engages it."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("color_tracker", **kwargs)
        gated = bool(self.declare_parameter("gated", True).value)
        world = load_world(str(self.declare_parameter("world", "revinge").value))
        origin = world.origin
        self._frame = WorldFrame(origin.latitude, origin.longitude, origin.altitude)
        self._ground = Ground(height=world.terrain.height, max_slope=1.0)
        self.tracker = ColourTracker()
        self._nav = NavHistory()
        self._ptu = PtuHistory()
        self._intrinsics: Intrinsics | None = None
        self._pending: PointStamped | None = None
        self._last_seed: tuple[int, float, float] | None = None
        self.results: dict[TrackStatus, int] = {}
        self._pub = self.create_publisher(ColorTrack, "~/track", TRACK_QOS)
        self.create_subscription(PointStamped, SEED_TOPIC, self._on_seed, SEED_QOS)
        self.gate = ImageGate(
            self, ImageProcessing.COLOR_TRACKER, self._subscribe, self._stopped, gated
        )

    def _subscribe(self) -> list[Subscription]:
        return [
            self.create_subscription(
                CameraInfo, "camera/color/camera_info", self._on_info, qos_profile_sensor_data
            ),
            self.create_subscription(
                Image, "camera/color/image_raw", self._on_image, qos_profile_sensor_data
            ),
            self.create_subscription(
                HelicopterState, "helicopter_state", self._on_state, STATE_QOS
            ),
            self.create_subscription(PtuState, "sensors/ptu", self._on_ptu, PTU_QOS),
        ]

    def _stopped(self) -> None:
        self.tracker.reset()
        self._pending = None

    def _on_seed(self, msg: PointStamped) -> None:
        key = (stamp_ns(msg.header.stamp), float(msg.point.x), float(msg.point.y))
        if key != self._last_seed:  # a latched seed delivered again is no new seed
            self._last_seed = key
            self._pending = msg

    def _on_info(self, msg: CameraInfo) -> None:
        self._intrinsics = Intrinsics.from_k(int(msg.width), int(msg.height), list(msg.k))

    def _on_state(self, msg: HelicopterState) -> None:
        self._nav.add(stamp_s(msg.header.stamp), NavPose.of_state(self._frame, msg))

    def _on_ptu(self, msg: PtuState) -> None:
        self._ptu.add(stamp_s(msg.header.stamp), float(msg.pan), float(msg.tilt))

    def _on_image(self, msg: Image) -> None:
        if not self.gate.engaged:  # taken by the executor before the stop
            return
        time = stamp_s(msg.header.stamp)
        view = self._view(time)
        decoded = image_array(msg) if msg.encoding == "rgb8" else f"encoding {msg.encoding!r}: rgb8"
        if isinstance(decoded, str):
            result = TrackResult(TrackStatus.LOST, f"bad image: {decoded}")
        else:
            pixels = np.asarray(decoded, dtype=np.uint8)  # rgb8 decodes to uint8
            known = view if isinstance(view, CameraView) else None
            pending = self._pending
            # the seed's pixel is in the image the operator saw when commanding: an image taken
            # before the command (queued on a loaded machine) may show the scene elsewhere
            if pending is not None and stamp_ns(msg.header.stamp) >= stamp_ns(pending.header.stamp):
                self._pending = None
                x, y = float(pending.point.x), float(pending.point.y)
                result = self.tracker.seed(x, y, pixels, time, known)
            else:
                result = self.tracker.update(pixels, time, known)
        self.results[result.status] = self.results.get(result.status, 0) + 1
        self._pub.publish(self._message(msg, result, view))

    def _view(self, time: float) -> CameraView | str:
        """The colour camera at an image's time, or why it is unknown (predictions, locating)."""
        if self._intrinsics is None:
            return "no usable camera_info"
        return CameraView.at(self._intrinsics, self._nav.at(time), self._ptu.at(time))

    def _message(self, image: Image, result: TrackResult, view: CameraView | str) -> ColorTrack:
        out = ColorTrack()
        out.header.stamp = image.header.stamp
        out.header.frame_id = image.header.frame_id or OPTICAL_FRAME
        out.status = int(result.status)
        out.x, out.y, out.area = result.x, result.y, result.area
        reason = result.reason
        nan = math.nan
        out.direction.x = out.direction.y = out.direction.z = nan
        out.position.x = out.position.y = out.position.z = nan
        if result.status is TrackStatus.TRACKING:
            if self._intrinsics is None:  # then ``view`` says so
                reason += f"; not located: {view}"
            else:
                fix = locate(self._intrinsics, result.x, result.y, view, self._ground)
                out.direction.x, out.direction.y, out.direction.z = (
                    float(v) for v in fix.direction
                )
                if fix.position is None:
                    reason += f"; not located: {fix.reason}"
                else:
                    out.located = True
                    out.position.x, out.position.y, out.position.z = (
                        float(v) for v in fix.position
                    )
        out.reason = reason
        return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``hdrc3-color-tracker``; accepts ``--ros-args`` (e.g. ``-r __ns:=/uav0``)."""
    apply_dds_defaults()
    try:
        return run_node(
            lambda context: ColorTrackerNode(context=context), sys.argv if argv is None else argv
        )
    except Hdrc3Error as exc:
        print(f"hdrc3-color-tracker: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
