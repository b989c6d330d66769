"""The `perception_kernel` node (the PPC): payload control modes behind PPCL (chapter 5.2).

A thin adapter around :class:`~hdrc3_control.ppc_kernel.PpcKernel`. It runs one kernel
iteration per PTU angle report (``sensors/ptu``, 25 Hz of sim time), takes the aircraft pose
from the PFC (``pfc/state``) and the camera states from ``sensors/color_camera`` /
``sensors/thermal_camera``, commands the devices on ``ptu/command`` (PtuCommand),
``camera/command`` (CameraCommand) and ``laser/command`` (LaserCommand), republishes the camera
state stamped with the PPC clock on ``ppc/camera_state``, publishes the engaged image
processing function on ``ppc/image_processing`` (latched ``std_msgs/UInt8``,
:class:`~hdrc3_control.ppc_modes.ImageProcessing`) and the colour tracker's seed of each
``ppcl_ip_color_tracker(x, y)`` on ``ppc/color_tracker_seed`` (latched ``PointStamped``: point.x
the pixel column, point.y the row, stamp the PPC time of the command), and talks to the DRC over
``hcsm/events/*``. While state estimation is engaged the PTU follows the landing pad's pose
(``pad_pose/pose``), while colour tracking is engaged the tracked object (``color_tracker/track``,
``ColorTrack`` results with status TRACKING) (:mod:`hdrc3_control.visual_servoing`).

It reports on ``ppc/pad_vision`` (latched ``UInt8``, :class:`~hdrc3_control.ppc_modes.PadVision`)
what it can do for a vision landing: from the ROS graph, whether a colour camera publishes
(``camera/color/image_raw`` has a publisher) and the pad pose pipeline is up (``pad_pose/result``
has one), checked once a second of sim time; from the pipeline's ``pad_pose/result`` (one per
processed image), whether images are actually processed. The control kernel's landing plans on it.
"""

from __future__ import annotations

import sys
from typing import Any

from geometry_msgs.msg import PointStamped, PoseStamped
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String, UInt8

from hdrc3_base.ros_runtime import run_events_node
from hdrc3_base.stamps import set_stamp_ns, set_stamp_s, stamp_s
from hdrc3_control.ppc_kernel import ColorSeed, PpcKernel, PpcOutputs
from hdrc3_control.ppc_modes import ImageProcessing, PadVision, Pose
from hdrc3_control.visual_servoing import Sighting
from hdrc3_hcsm.ros_transport import RosTransport
from hdrc3_interfaces.msg import (
    CameraCommand,
    CameraState,
    ColorTrack,
    LaserCommand,
    PfcState,
    PtuCommand,
    PtuState,
)

NODE_NAME = "perception_kernel"
QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
IMAGE_PROCESSING_TOPIC = "ppc/image_processing"
"""The engaged :class:`ImageProcessing` function (relative to the agent's namespace)."""
COLOR_TRACKER_SEED_TOPIC = "ppc/color_tracker_seed"
"""The colour tracker's seed (latched ``PointStamped``; a new one restarts the tracking)."""
COLOR_TRACK_TOPIC = "color_tracker/track"
"""The colour tracker's ``ColorTrack`` of every image while colour tracking is engaged."""
PAD_VISION_TOPIC = "ppc/pad_vision"
"""The PPC's :class:`PadVision` report (latched ``UInt8``)."""
PAD_RESULT_TOPIC = "pad_pose/result"
"""The pad pose pipeline's result of every image it processed (``std_msgs/String`` JSON)."""
COLOR_IMAGE_TOPIC = "camera/color/image_raw"
"""The colour camera's images (only their publisher is looked at: subscribing would render)."""
DEVICE_CHECK_PERIOD_NS = 1_000_000_000
"""How often the graph is asked for the camera and the pipeline, ns of sim time."""
LATCHED = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)


class PerceptionKernelNode(Node):
    """ROS adapter of the PPC kernel."""

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(NODE_NAME, context=context)
        self.declare_parameter("sim_time", True)
        self.declare_parameter("world", "revinge")
        self.declare_parameter("agents", [""])
        self.declare_parameter("speed", 1.0)
        if self.get_parameter("sim_time").value:
            self.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        self.kernel = PpcKernel(RosTransport(self, "PPC"))
        self.pose: Pose | None = None
        self.zooms: dict[int, float] = {}
        self.ptu_pub = self.create_publisher(PtuCommand, "ptu/command", QOS)
        self.camera_pub = self.create_publisher(CameraCommand, "camera/command", QOS)
        self.laser_pub = self.create_publisher(LaserCommand, "laser/command", LATCHED)
        self.state_pub = self.create_publisher(CameraState, "ppc/camera_state", QOS)
        self.ip_pub = self.create_publisher(UInt8, IMAGE_PROCESSING_TOPIC, LATCHED)
        self.seed_pub = self.create_publisher(PointStamped, COLOR_TRACKER_SEED_TOPIC, LATCHED)
        self.pad_vision_pub = self.create_publisher(UInt8, PAD_VISION_TOPIC, LATCHED)
        self._publish_ip(self.kernel.image_processing)
        self._publish_pad_vision(self.kernel.pad_vision)
        self._devices_checked_ns: int | None = None
        self.create_subscription(PfcState, "pfc/state", self._on_pfc, QOS)
        self.create_subscription(PtuState, "sensors/ptu", self._on_ptu, QOS)
        self.create_subscription(PoseStamped, "pad_pose/pose", self._on_pad, QOS)
        self.create_subscription(ColorTrack, COLOR_TRACK_TOPIC, self._on_color_track, QOS)
        self.create_subscription(String, PAD_RESULT_TOPIC, self._on_pad_result, QOS)
        for topic in ("sensors/color_camera", "sensors/thermal_camera"):
            self.create_subscription(CameraState, topic, self._on_camera, QOS)

    def _now_ns(self) -> int:
        return int(self.get_clock().now().nanoseconds)

    def _on_pfc(self, msg: Any) -> None:
        p = msg.position_enu
        self.pose = Pose(
            (float(p[0]), float(p[1]), float(p[2])),
            float(msg.roll),
            float(msg.pitch),
            float(msg.heading),
        )

    def _on_pad(self, msg: Any) -> None:
        p, stamp = msg.pose.position, msg.header.stamp
        sighting = Sighting(stamp_s(stamp), (float(p.x), float(p.y), float(p.z)))
        self.kernel.see(ImageProcessing.STATE_ESTIMATION, sighting)

    def _on_pad_result(self, _msg: Any) -> None:
        self.kernel.pad_image(self._now_ns() * 1e-9)

    def _check_devices(self, now_ns: int) -> None:
        """Ask the graph (once a second of sim time) for the colour camera and the pipeline."""
        last = self._devices_checked_ns
        if last is not None and 0 <= now_ns - last < DEVICE_CHECK_PERIOD_NS:
            return
        self._devices_checked_ns = now_ns
        camera = self.count_publishers(COLOR_IMAGE_TOPIC) > 0
        self.kernel.devices(camera, self.count_publishers(PAD_RESULT_TOPIC) > 0)

    def _on_color_track(self, msg: Any) -> None:
        if msg.status != ColorTrack.STATUS_TRACKING:
            return
        d = msg.direction
        sighting = Sighting(stamp_s(msg.header.stamp), (float(d.x), float(d.y), float(d.z)))
        self.kernel.see(ImageProcessing.COLOR_TRACKER, sighting)

    def _on_camera(self, msg: Any) -> None:
        self.zooms[int(msg.id)] = float(msg.zoom)
        out = CameraState()
        out.header = msg.header
        out.id, out.pan, out.tilt, out.zoom = msg.id, msg.pan, msg.tilt, msg.zoom
        set_stamp_ns(out.ipc_time, self._now_ns())
        self.state_pub.publish(out)

    def _on_ptu(self, msg: Any) -> None:
        now_ns = self._now_ns()
        stamp = msg.header.stamp
        time = stamp_s(stamp)
        self.kernel.ptu_reading(time, float(msg.pan), float(msg.tilt))
        self._check_devices(now_ns)
        try:
            out = self.kernel.step(
                now_ns * 1e-9, self.pose, (float(msg.pan), float(msg.tilt)), dict(self.zooms)
            )
        except Exception as exc:  # keep the node alive: a bad iteration is logged, not fatal
            self.get_logger().error(f"PPC iteration failed: {exc}")
            return
        self._publish(out, now_ns)

    def _publish(self, out: PpcOutputs, now_ns: int) -> None:
        if out.ptu is not None:
            m = PtuCommand()
            set_stamp_ns(m.header.stamp, now_ns)
            m.pan, m.tilt = out.ptu
            self.ptu_pub.publish(m)
        for c in out.cameras:
            cm = CameraCommand()
            set_stamp_ns(cm.header.stamp, now_ns)
            cm.camera_id, cm.zoom, cm.auto_exposure = c.camera_id, c.zoom, c.auto_exposure
            cm.iris, cm.shutter = c.iris, c.shutter
            self.camera_pub.publish(cm)
        if out.laser is not None:
            lm = LaserCommand()
            set_stamp_ns(lm.header.stamp, now_ns)
            la = out.laser
            lm.angular_resolution, lm.distance_resolution = (
                la.angular_resolution,
                la.distance_resolution,
            )
            lm.rotation_speed, lm.hold_angle = la.rotation_speed, la.hold_angle
            lm.rotation_angle, lm.collect = la.rotation_angle, la.collect
            self.laser_pub.publish(lm)
        if out.color_seed is not None:  # before the function: the tracker starts on this seed
            self._publish_seed(out.color_seed)
        if out.image_processing is not None:
            self._publish_ip(out.image_processing)
        if out.pad_vision is not None:
            self._publish_pad_vision(out.pad_vision)

    def _publish_seed(self, seed: ColorSeed) -> None:
        m = PointStamped()
        set_stamp_s(m.header.stamp, seed.time)
        m.point.x, m.point.y = seed.x, seed.y
        self.seed_pub.publish(m)

    def _publish_ip(self, mode: ImageProcessing) -> None:
        self.ip_pub.publish(UInt8(data=int(mode)))

    def _publish_pad_vision(self, state: PadVision) -> None:
        self.get_logger().info(f"pad vision: {state.name.lower()} ({state.describe()})")
        self.pad_vision_pub.publish(UInt8(data=int(state)))


def main() -> int:
    """Console script `hdrc3-perception-kernel`."""
    # the events executor: ~200 callbacks per sim second (PFC state, PTU, cameras, /clock)
    return run_events_node(PerceptionKernelNode, "hdrc3-perception-kernel")


if __name__ == "__main__":
    sys.exit(main())
