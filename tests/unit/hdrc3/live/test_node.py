"""The ``live_view`` node: camera images subscribed only while a client watches them, bad images
skipped and counted."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from foxglove.messages import CompressedImage
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import qos_profile_sensor_data
from sensor_msgs.msg import Image

from hdrc3.live.converters import SkipReason
from hdrc3.live.node import LiveViewNode
from hdrc3.live.probe import FoxgloveProbe, Frame
from hdrc3.live.wire import WireSchema, decode
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros
COLOR = "/live/camera/color/uav0"


@pytest.fixture
def graph(ros_context: Any) -> Iterator[tuple[SingleThreadedExecutor, LiveViewNode, Node]]:
    node = LiveViewNode(ros_context, parameter_overrides=[Parameter("port", value=0)])
    camera = Node("camera", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    executor.add_node(camera)
    try:
        yield executor, node, camera
    finally:
        executor.shutdown()
        node.destroy_node()
        camera.destroy_node()


def rgb(encoding: str = "rgb8") -> Image:
    return Image(width=4, height=2, encoding=encoding, step=12, data=bytes(24))


def test_images_are_subscribed_while_a_client_watches_them(graph):
    executor, node, camera = graph
    pub = camera.create_publisher(Image, "/uav0/camera/color/image_raw", qos_profile_sensor_data)
    client = FoxgloveProbe(f"ws://127.0.0.1:{node.server.port}")
    try:
        assert spin_until(executor, lambda: client.wait_for_channels({COLOR}, 0.05), 20)
        assert pub.get_subscription_count() == 0  # advertised, not subscribed: nobody watches
        client.subscribe([COLOR])
        assert spin_until(executor, lambda: pub.get_subscription_count() == 1, 20)
        frames: list[Frame] = []

        def received() -> bool:
            pub.publish(rgb())
            frame = client.receive(0.02)
            frames.extend([frame] if frame is not None else [])
            return bool(frames)

        assert spin_until(executor, received, 20)
        image = decode(WireSchema.well_known(CompressedImage), frames[0].data)
        assert image.format == "jpeg" and image.frame_id == "uav0/color_optical"

        def skipped() -> bool:
            pub.publish(rgb("yuv422"))
            return "/live/camera/color" in node.view.skipped()

        assert spin_until(executor, skipped, 20)
        assert set(node.view.skipped()["/live/camera/color"]) == {SkipReason.UNKNOWN_ENCODING}
    finally:
        client.close()
    assert spin_until(executor, lambda: pub.get_subscription_count() == 0, 20)
