"""The `world_render` node: colour and thermal images of every agent's cameras.

A separate process beside world_sim (started by ``hdrc3 launch --cameras``): rendering costs
milliseconds per image, so in world_sim's process it would stall the lockstep physics. It reads
world_sim's per-exposure metadata (``sensors/<camera>_camera``: pan, tilt, zoom) and the pose of
the exposure (``ground_truth/<camera>_camera_pose``), renders with :class:`Renderer`, and
publishes ``sensor_msgs/Image`` + ``CameraInfo`` stamped with the exposure's sim time:

- ``/<agent>/camera/color/image_raw`` (``rgb8``), ``/<agent>/camera/color/camera_info``,
  frame ``<agent>/color_optical``;
- ``/<agent>/camera/thermal/image_raw`` (``mono16``, value = temperature in centi-kelvin, i.e.
  value / 100 = K), ``/<agent>/camera/thermal/camera_info``, frame ``<agent>/thermal_optical``.

A camera is rendered only while one of its two topics has a subscriber. After each exposure's
pose it publishes ``/world_render/progress`` (``std_msgs/Header``: that stamp, ``frame_id`` =
agent), and world_sim holds its ticks while the exposures run more than ``render_lag`` ahead of
it (:mod:`sim.render_gate`), so images follow sim time at any speed; a renderer that falls
behind anyway still renders the newest exposure and skips older ones.
While both cameras of an agent have subscribers, the two images of one exposure are rendered
together and a half whose partner was skipped is not rendered (:class:`ExposurePairs`): the
saliency pipeline needs pairs. See ``sim/WORLD_SIM.md`` ("Camera images").
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseStamped
from rcl_interfaces.msg import ParameterDescriptor, ParameterType
from rclpy.context import Context
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Header

from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import run_events_node
from hdrc3_base.stamps import set_stamp_ns
from hdrc3_interfaces.msg import CameraState, SimRun, WorldObjects
from sim.node import LATCHED_QOS, RENDER_PROGRESS_QOS, RENDER_PROGRESS_TOPIC
from sim.render.camera_feed import (
    CameraFeed,
    CameraMeta,
    ExposurePairs,
    FrameAction,
    FrameRequest,
    pose_from_ros,
    projection_rows,
)
from sim.render.objects import objects_from_message
from sim.render.renderer import Renderer, RenderError
from sim.sensors.camera import CameraId
from sim.world_loader import WorldError, load_world, shipped_worlds

NODE_NAME = "world_render"
INPUT_QOS = QoSProfile(depth=4, reliability=ReliabilityPolicy.RELIABLE)
"""Short queues: a renderer that falls behind skips to the newest exposures."""
IMAGE_QOS = QoSProfile(depth=4, reliability=ReliabilityPolicy.RELIABLE)
_NAMES = {CameraId.COLOR: "color", CameraId.THERMAL: "thermal"}


def _ns(stamp: Any) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


class _CameraTopics:
    """Feed, publishers and the last published image of one agent's camera."""

    def __init__(self, node: Node, agent: str, camera: CameraId) -> None:
        name = _NAMES[camera]
        self.agent = agent
        self.feed = CameraFeed(camera)
        self.image_pub = node.create_publisher(
            Image, f"/{agent}/camera/{name}/image_raw", IMAGE_QOS
        )
        self.info_pub = node.create_publisher(
            CameraInfo, f"/{agent}/camera/{name}/camera_info", IMAGE_QOS
        )
        self.image = Image()
        self.image.header.frame_id = f"{agent}/{name}_optical"
        self.image.encoding = "rgb8" if camera is CameraId.COLOR else "mono16"
        self.info = CameraInfo()
        self.info.header.frame_id = self.image.header.frame_id
        self.info.distortion_model = "plumb_bob"
        self.info.d = [0.0] * 5
        self.info.r = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        self.has_image = False

    def wanted(self) -> bool:
        return self.image_pub.get_subscription_count() + self.info_pub.get_subscription_count() > 0


class WorldRenderNode(Node):
    """ROS face of the renderer."""

    def __init__(self, context: Context) -> None:
        """Read parameters (ConfigError), load the world, create the GL context and topics."""
        super().__init__(NODE_NAME, context=context)
        strings = ParameterDescriptor(type=ParameterType.PARAMETER_STRING_ARRAY)
        agents = [str(a) for a in self.declare_parameter("agents", ["uav0"], strings).value]
        world_name = str(self.declare_parameter("world", "revinge").value)
        seed = int(self.declare_parameter("seed", 0).value)
        if world_name not in shipped_worlds() and not world_name.endswith(".toml"):
            raise ConfigError(f"unknown world {world_name!r}")
        if seed < 0:
            raise ConfigError(f"parameter seed: expected an integer >= 0, got {seed}")
        try:
            self.world = load_world(world_name)
            self.renderer = Renderer(self.world, seed=seed)
        except (WorldError, RenderError) as exc:
            raise ConfigError(str(exc)) from exc
        self.get_logger().info(f"rendering with {self.renderer.renderer_name}")
        self.cameras: dict[tuple[str, CameraId], _CameraTopics] = {}
        self.pairs = {agent: ExposurePairs() for agent in agents}
        for agent in agents:
            for camera in CameraId:
                topics = _CameraTopics(self, agent, camera)
                self.cameras[(agent, camera)] = topics
                name = _NAMES[camera]
                self.create_subscription(
                    CameraState,
                    f"/{agent}/sensors/{name}_camera",
                    self._on_meta(topics),
                    INPUT_QOS,
                )
                self.create_subscription(
                    PoseStamped,
                    f"/{agent}/ground_truth/{name}_camera_pose",
                    self._on_pose(topics),
                    INPUT_QOS,
                )
        self._progress_pub = self.create_publisher(
            Header, RENDER_PROGRESS_TOPIC, RENDER_PROGRESS_QOS
        )
        self._progress = Header()
        self.create_subscription(WorldObjects, "/world_sim/objects", self._on_objects, LATCHED_QOS)
        self.create_subscription(SimRun, "/world_sim/run", self._on_run, LATCHED_QOS)

    def _on_meta(self, topics: _CameraTopics) -> Callable[[Any], None]:
        def callback(msg: Any) -> None:
            if topics.wanted():
                meta = CameraMeta(msg.pan, msg.tilt, msg.zoom)
                self._offer(topics, topics.feed.on_meta(_ns(msg.header.stamp), meta))

        return callback

    def _on_pose(self, topics: _CameraTopics) -> Callable[[Any], None]:
        def callback(msg: Any) -> None:
            if topics.wanted():
                p, q = msg.pose.position, msg.pose.orientation
                pose = pose_from_ros((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
                if pose is None:
                    self.get_logger().warning(
                        "camera pose with non-finite values or a non-unit quaternion ignored",
                        throttle_duration_sec=5.0,
                    )
                else:
                    self._offer(topics, topics.feed.on_pose(_ns(msg.header.stamp), pose))
            # handled (rendered and published, or not wanted): world_sim may go on (RenderGate)
            self._progress.stamp = msg.header.stamp
            self._progress.frame_id = topics.agent
            self._progress_pub.publish(self._progress)

        return callback

    def _on_objects(self, msg: Any) -> None:
        self.renderer.set_objects(objects_from_message(self.world, msg.objects))

    def _on_run(self, msg: Any) -> None:
        for topics in self.cameras.values():  # stamps restart (reset) or jump (resume)
            topics.feed.reset()
        for pairs in self.pairs.values():
            pairs.reset()

    def _offer(self, topics: _CameraTopics, request: FrameRequest | None) -> None:
        """Render what the agent's pairing releases (both cameras wanted: pairs only)."""
        if request is None:
            return
        agent = topics.agent
        paired = all(self.cameras[(agent, camera)].wanted() for camera in CameraId)
        for ready in self.pairs[agent].offer(request, paired):
            self._publish(self.cameras[(agent, ready.camera)], ready)

    def _publish(self, topics: _CameraTopics, request: FrameRequest) -> None:
        image, info = topics.image, topics.info
        if request.action is FrameAction.RENDER or not topics.has_image:
            k = request.intrinsics
            if request.camera is CameraId.COLOR:
                data = self.renderer.render_color(request.pose, k, request.stamp_ns).tobytes()
                image.step = k.width * 3
            else:
                data = self.renderer.render_thermal(request.pose, k, request.stamp_ns).tobytes()
                image.step = k.width * 2
            image.height, image.width = k.height, k.width
            image.is_bigendian = int(sys.byteorder == "big")
            image.data = data
            info.height, info.width = k.height, k.width
            info.k, info.p = projection_rows(k)
            topics.has_image = True
        set_stamp_ns(image.header.stamp, request.stamp_ns)
        info.header.stamp = image.header.stamp
        topics.info_pub.publish(info)
        topics.image_pub.publish(image)


def main() -> int:
    """Console script `hdrc3-world-render`: exit 0 on SIGINT/SIGTERM, 2 on bad parameters."""
    return run_events_node(WorldRenderNode, "world_render")


if __name__ == "__main__":
    sys.exit(main())
