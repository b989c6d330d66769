"""The ``pad_pose`` node: engaged by the PPC's state estimation, the pad's pose per colour image."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Bool, String, UInt8

from hdrc3_control.perception_kernel_node import IMAGE_PROCESSING_TOPIC, LATCHED
from hdrc3_control.ppc_modes import ImageProcessing
from hdrc3_interfaces.msg import PtuState
from hdrc3_perception.camera import MOUNT_OFFSET
from hdrc3_perception.node import RESULT_QOS
from hdrc3_perception.pad_node import OPTICAL_FRAME, WORLD_FRAME, PadPoseNode
from hdrc3_perception.pad_view import look_at, render
from hdrc3_perception.synthetic import COLOR_K
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros
EYE = (1.0, 2.0, 5.0)


@dataclass
class Rig:
    executor: SingleThreadedExecutor
    node: PadPoseNode
    pubs: dict[str, Any]
    poses: list[PoseStamped]
    fixes: list[PoseWithCovarianceStamped]
    results: list[dict[str, Any]]
    engaged: list[bool]

    def mode(self, mode: ImageProcessing) -> None:
        self.pubs["mode"].publish(UInt8(data=int(mode)))
        on = mode is ImageProcessing.STATE_ESTIMATION
        assert spin_until(self.executor, lambda: self.engaged[-1:] == [on], 10.0), self.engaged

    def ptu(self, t: int, pan: float, tilt: float) -> None:
        """Publish one PTU read-out stamped ``t`` s (reliable: taken before the next image)."""
        msg = PtuState(pan=pan, tilt=tilt)
        msg.header.stamp.sec = t
        self.pubs["ptu"].publish(msg)

    def image(self, t: int, encoding: str = "rgb8") -> dict[str, Any]:
        """Publish calibration and one view of the pad stamped ``t`` s; the node's result."""
        info = CameraInfo(width=COLOR_K.width, height=COLOR_K.height, k=list(COLOR_K.k()))
        self.pubs["info"].publish(info)
        gray = render(COLOR_K, *look_at(EYE, roll=0.4))
        msg = Image(height=COLOR_K.height, width=COLOR_K.width, encoding=encoding)
        msg.header.stamp.sec = t
        msg.step = 3 * COLOR_K.width
        msg.data = np.repeat(gray[:, :, None], 3, axis=2).tobytes()
        for _ in range(5):  # sensor-data QoS is best effort: publish until one is taken
            self.pubs["image"].publish(msg)
            if spin_until(self.executor, lambda: self._result(t) is not None, 2.0):
                break
        result = self._result(t)
        assert result is not None, self.results
        return result

    def _result(self, t: int) -> dict[str, Any] | None:
        return next((r for r in self.results if r["time"] == t), None)


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    node = PadPoseNode(context=ros_context, namespace="/uav0")
    tester = Node("pad_tester", context=ros_context)
    poses: list[PoseStamped] = []
    fixes: list[PoseWithCovarianceStamped] = []
    results: list[dict[str, Any]] = []
    engaged: list[bool] = []
    tester.create_subscription(PoseStamped, "/uav0/pad_pose/pose", poses.append, RESULT_QOS)
    tester.create_subscription(
        PoseWithCovarianceStamped, "/uav0/pad_pose/fix", fixes.append, RESULT_QOS
    )
    tester.create_subscription(
        String, "/uav0/pad_pose/result", lambda m: results.append(json.loads(m.data)), RESULT_QOS
    )
    tester.create_subscription(
        Bool, "/uav0/pad_pose/engaged", lambda m: engaged.append(m.data), LATCHED
    )
    pubs = {
        "mode": tester.create_publisher(UInt8, f"/uav0/{IMAGE_PROCESSING_TOPIC}", LATCHED),
        "ptu": tester.create_publisher(PtuState, "/uav0/sensors/ptu", 10),
        "info": tester.create_publisher(
            CameraInfo, "/uav0/camera/color/camera_info", qos_profile_sensor_data
        ),
        "image": tester.create_publisher(
            Image, "/uav0/camera/color/image_raw", qos_profile_sensor_data
        ),
    }
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    executor.add_node(tester)
    try:
        yield Rig(executor, node, pubs, poses, fixes, results, engaged)
    finally:
        executor.shutdown()
        tester.destroy_node()
        node.destroy_node()


def test_the_pose_of_an_engaged_node(rig: Rig) -> None:
    rig.mode(ImageProcessing.STATE_ESTIMATION)
    result = rig.image(7)
    assert result["status"] == "ok", result
    assert np.linalg.norm(np.array(result["camera_in_pad"]) - EYE) < 0.05
    assert spin_until(rig.executor, lambda: bool(rig.poses), 5.0)
    pose = rig.poses[-1]
    assert pose.header.frame_id == OPTICAL_FRAME and pose.header.stamp.sec == 7
    _, truth = look_at(EYE, roll=0.4)
    got = np.array([pose.pose.position.x, pose.pose.position.y, pose.pose.position.z])
    assert np.linalg.norm(got - truth) < 0.03


def test_a_bad_image_gets_a_status(rig: Rig) -> None:
    rig.mode(ImageProcessing.STATE_ESTIMATION)
    result = rig.image(8, encoding="bgr8")
    assert result["status"] == "bad_image" and "rgb8" in result["reason"]


def test_the_node_follows_the_ppc(rig: Rig) -> None:
    assert spin_until(rig.executor, lambda: rig.engaged[-1:] == [False], 10.0)
    rig.mode(ImageProcessing.SALIENCY)  # another function: still not engaged
    assert not rig.node.gate.engaged
    rig.mode(ImageProcessing.STATE_ESTIMATION)
    assert rig.image(9)["status"] == "ok"
    rig.mode(ImageProcessing.IDLE)
    assert not rig.node.gate.engaged


def test_a_fix_of_the_helicopter_on_the_world_s_pad(rig: Rig) -> None:
    rig.mode(ImageProcessing.STATE_ESTIMATION)
    first = rig.image(10)
    assert first["fix"]["status"] == "no_ptu", first  # no PTU read-out yet
    for t in (10, 11):  # the node interpolates between two read-outs
        rig.ptu(t, 0.3, 1.2)
    assert spin_until(rig.executor, lambda: rig.node._ptu.at(11.0) is not None, 5.0)
    result = rig.image(11)
    assert result["fix"]["status"] == "ok" and result["fix"]["pad"] == "L1", result
    assert spin_until(rig.executor, lambda: bool(rig.fixes), 5.0)
    fix = rig.fixes[-1]
    assert fix.header.frame_id == WORLD_FRAME and fix.header.stamp.sec == 11
    q = fix.pose.pose.orientation
    body = Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix()
    p = fix.pose.pose.position
    camera = np.array([p.x, p.y, p.z]) + body @ np.asarray(MOUNT_OFFSET)
    place = rig.node.placement
    assert np.linalg.norm(camera - (place.origin + place.axes @ np.asarray(EYE))) < 0.05
    sigma = result["fix"]["sigma_m"]
    assert fix.pose.covariance[0] == pytest.approx(sigma**2, rel=0.01)
