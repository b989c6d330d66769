"""ROS 2 adapter: the ``pad_pose`` node (one per agent namespace), the landing pad's pose (§5.4).

The PPC engages it (``ppcl_ip_state_estimation``, stopped by ``ppcl_ip_abort``; see
:mod:`hdrc3_perception.image_gate`). While engaged it subscribes ``camera/color/image_raw``
(``rgb8``) with its ``camera_info`` and hands every image, in grey, to
:func:`hdrc3_perception.pad_pose.estimate`.

Publishes ``~/engaged`` (latched ``std_msgs/Bool``), ``~/pose``
(``geometry_msgs/PoseStamped``: the pad in the colour camera's optical frame, x right, y down, z
forward, stamped with the image) for every image with a pose, and ``~/result``
(``std_msgs/String``, JSON: stamp, status, reason, triplets, RMS reprojection error, circles seen,
and the camera's position on the pad, and the helicopter fix) for every image, and ``~/fix``
(``geometry_msgs/PoseWithCovarianceStamped``, frame ``world_enu``, stamped with the image): the
helicopter's centre of gravity in the world's ENU frame and its attitude (body FRD -> ENU), from
the pose, the PTU read-out at the image's time (``sensors/ptu``) and the pad's place in the world
file (:mod:`hdrc3_perception.pad_fix`); the position covariance is ``sigma^2`` per axis. The
control kernel fuses these fixes in its Kalman filter.

Parameters: ``gated`` (default true), ``world`` (default ``revinge``), ``pad`` (the patterned pad
of the world; "" = its only one).
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Sequence
from typing import Any

import cv2
import numpy as np
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from rclpy.subscription import Subscription
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import String

from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults
from hdrc3_base.ros_runtime import run_node
from hdrc3_base.stamps import stamp_s
from hdrc3_control.ppc_modes import ImageProcessing
from hdrc3_interfaces.msg import PtuState
from hdrc3_perception.camera import Intrinsics, body_to_enu
from hdrc3_perception.history import PtuHistory
from hdrc3_perception.image_gate import ImageGate
from hdrc3_perception.node import PTU_QOS, RESULT_QOS, image_array
from hdrc3_perception.pad_fix import FixStatus, PadPlacement, helicopter_fix
from hdrc3_perception.pad_pose import PoseStatus, estimate
from sim.world_loader import load_world

OPTICAL_FRAME = "camera_color_optical"
WORLD_FRAME = "world_enu"


class PadPoseNode(Node):
    """The pad's pose from each colour image while the PPC engages state estimation."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("pad_pose", **kwargs)
        gated = bool(self.declare_parameter("gated", True).value)
        world_name = str(self.declare_parameter("world", "revinge").value)
        pad_name = str(self.declare_parameter("pad", "").value)
        self.placement = PadPlacement.of_world(load_world(world_name), pad_name)
        self._ptu = PtuHistory()
        self.fixes = 0
        self._intrinsics: Intrinsics | None = None
        self.results: dict[str, int] = {}
        self._pose_pub = self.create_publisher(PoseStamped, "~/pose", RESULT_QOS)
        self._result_pub = self.create_publisher(String, "~/result", RESULT_QOS)
        self._fix_pub = self.create_publisher(PoseWithCovarianceStamped, "~/fix", RESULT_QOS)
        self.gate = ImageGate(
            self, ImageProcessing.STATE_ESTIMATION, self._subscribe, lambda: None, gated
        )

    def _subscribe(self) -> list[Subscription]:
        return [
            self.create_subscription(
                CameraInfo, "camera/color/camera_info", self._on_info, qos_profile_sensor_data
            ),
            self.create_subscription(
                Image, "camera/color/image_raw", self._on_image, qos_profile_sensor_data
            ),
            self.create_subscription(PtuState, "sensors/ptu", self._on_ptu, PTU_QOS),
        ]

    def _on_ptu(self, msg: PtuState) -> None:
        self._ptu.add(stamp_s(msg.header.stamp), float(msg.pan), float(msg.tilt))

    def _on_info(self, msg: CameraInfo) -> None:
        self._intrinsics = Intrinsics.from_k(int(msg.width), int(msg.height), list(msg.k))

    def _on_image(self, msg: Image) -> None:
        if not self.gate.engaged:  # taken by the executor before the stop
            return
        report: dict[str, Any] = {"time": stamp_s(msg.header.stamp)}
        pixels = image_array(msg) if msg.encoding == "rgb8" else f"encoding {msg.encoding!r}: rgb8"
        if isinstance(pixels, str):
            report |= {"status": PoseStatus.BAD_IMAGE.value, "reason": pixels}
        else:
            gray = cv2.cvtColor(np.ascontiguousarray(pixels, dtype=np.uint8), cv2.COLOR_RGB2GRAY)
            pose = estimate(gray, self._intrinsics)
            report |= {
                "status": pose.status.value,
                "reason": pose.reason,
                "triplets": list(pose.triplets),
                "rms_px": None if pose.status is not PoseStatus.OK else round(pose.rms_px, 3),
                "circles": pose.blobs,
            }
            if pose.status is PoseStatus.OK and pose.rotation is not None:
                assert pose.translation is not None
                report["camera_in_pad"] = [round(float(v), 4) for v in pose.camera_in_pad]
                out = PoseStamped()
                out.header.stamp = msg.header.stamp
                out.header.frame_id = OPTICAL_FRAME
                p = out.pose.position
                p.x, p.y, p.z = (float(v) for v in pose.translation)
                q = Rotation.from_matrix(pose.rotation).as_quat()  # x, y, z, w
                o = out.pose.orientation
                o.x, o.y, o.z, o.w = (float(v) for v in q)
                self._pose_pub.publish(out)
                report["fix"] = self._publish_fix(msg, pose.rotation, pose.translation)
        self.results[report["status"]] = self.results.get(report["status"], 0) + 1
        self._result_pub.publish(String(data=json.dumps(report)))

    def _publish_fix(self, image: Image, rotation: Any, translation: Any) -> dict[str, Any]:
        """The helicopter fix of this image on ``~/fix``; its summary for the result."""
        time = stamp_s(image.header.stamp)
        fix = helicopter_fix(time, rotation, translation, self._ptu.at(time), self.placement)
        if fix.status is not FixStatus.OK:
            return {"status": fix.status.value, "reason": fix.reason}
        out = PoseWithCovarianceStamped()
        out.header.stamp = image.header.stamp
        out.header.frame_id = WORLD_FRAME
        p = out.pose.pose.position
        p.x, p.y, p.z = fix.position
        o = out.pose.pose.orientation
        body = Rotation.from_matrix(body_to_enu(fix.roll, fix.pitch, fix.heading))
        o.x, o.y, o.z, o.w = (float(v) for v in body.as_quat())
        cov = [0.0] * 36
        for i in range(3):
            cov[7 * i] = fix.sigma**2
        out.pose.covariance = cov
        self._fix_pub.publish(out)
        self.fixes += 1
        return {
            "status": fix.status.value,
            "position": [round(v, 4) for v in fix.position],
            "heading_deg": round(math.degrees(fix.heading), 2),
            "range_m": round(fix.range_m, 3),
            "sigma_m": round(fix.sigma, 4),
            "pad": self.placement.name,
        }


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``hdrc3-pad-pose``; accepts ``--ros-args`` (e.g. ``-r __ns:=/uav0``)."""
    apply_dds_defaults()
    try:
        return run_node(
            lambda context: PadPoseNode(context=context), sys.argv if argv is None else argv
        )
    except Hdrc3Error as exc:
        print(f"hdrc3-pad-pose: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
