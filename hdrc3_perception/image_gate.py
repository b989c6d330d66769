"""The PPC's gate on a perception node's images: subscribed only while its function is engaged.

The perception kernel publishes the image processing function it engaged, latched, on
``ppc/image_processing`` (``ImageProcessing``). A pipeline node hands the gate its function and
a hook that creates its image subscriptions; the gate creates them when the PPC engages that
function and destroys them when it engages another one or none, so the renderer draws nothing
for an idle pipeline. The node's latched ``~/engaged`` (``std_msgs/Bool``) follows; once it reads
false, no further image reaches the node (an image the executor took before is dropped by the
node's :attr:`ImageGate.engaged` check). Without ``gated`` the images are subscribed at once.
"""

from __future__ import annotations

from collections.abc import Callable

from rclpy.node import Node
from rclpy.subscription import Subscription
from std_msgs.msg import Bool, UInt8

from hdrc3_control.perception_kernel_node import IMAGE_PROCESSING_TOPIC, LATCHED
from hdrc3_control.ppc_modes import ImageProcessing

__all__ = ["LATCHED", "ImageGate"]


class ImageGate:
    """Creates and destroys one node's image subscriptions as the PPC engages its function."""

    def __init__(
        self,
        node: Node,
        function: ImageProcessing,
        subscribe: Callable[[], list[Subscription]],
        on_stop: Callable[[], None],
        gated: bool = True,
    ) -> None:
        """Follow ``ppc/image_processing`` (or subscribe at once if not ``gated``).

        Args:
            node: The pipeline's node.
            function: The PPC function that engages it.
            subscribe: Creates the image subscriptions (called on each engagement).
            on_stop: Called after the subscriptions are gone (e.g. publish a final result).
            gated: Whether to wait for the PPC.
        """
        self._node = node
        self._function = function
        self._subscribe = subscribe
        self._on_stop = on_stop
        self._images: list[Subscription] = []
        self._pub = node.create_publisher(Bool, "~/engaged", LATCHED)
        if gated:
            self._pub.publish(Bool(data=False))
            node.create_subscription(UInt8, IMAGE_PROCESSING_TOPIC, self._on_mode, LATCHED)
        else:
            self._engage(True)

    @property
    def engaged(self) -> bool:
        """Whether the images are subscribed."""
        return bool(self._images)

    def _on_mode(self, msg: UInt8) -> None:
        self._engage(msg.data == self._function)

    def _engage(self, on: bool) -> None:
        if on == self.engaged:
            return
        if on:
            self._images = self._subscribe()
            self._pub.publish(Bool(data=True))
            return
        for sub in self._images:
            self._node.destroy_subscription(sub)
        self._images = []
        self._pub.publish(Bool(data=False))
        self._on_stop()
