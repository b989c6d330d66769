"""ROS 2 adapter: external HCSM events over DDS (hdrc3_interfaces/Event) and trace publishing.

Each computer subscribes to ``<prefix>/<COMPUTER>`` and publishes to the topics of the computers
it sends to. QoS is reliable and ordered (keep-last with a deep queue); on top of that every event
carries a per-channel sequence number and a CRC-32 checked by the same
:class:`~hdrc3_hcsm.transport.ChannelIntegrity` the loopback transport uses. The subscription
callback only appends to a queue; :meth:`RosTransport.receive` drains it in the main loop's
Communicate, so the interpreter never runs inside an executor callback.

Each transport draws a random incarnation when it is created (see :mod:`hdrc3_hcsm.transport`):
a restarted node is heard again at once and its peers learn of the restart from
:meth:`RosTransport.restarts`. Events for a computer whose topic has no matched subscription yet
(a node that just started, or whose peer is restarting) are held, up to :data:`HELD_PER_TARGET`
per target, and published as soon as the subscription is matched: a volatile reliable publisher
would otherwise drop them, and the first events of a restarted node are its resynchronisation.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Mapping

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String

from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.trace import TraceRecord
from hdrc3_hcsm.transport import ChannelIntegrity, ChannelStats, SendStatus, Verdict
from hdrc3_interfaces.msg import Event

# Computer names of the RMAX and their codes in Event.msg.
RMAX_COMPUTERS: Mapping[str, int] = {
    "PFC": Event.COMPUTER_PFC,
    "PPC": Event.COMPUTER_PPC,
    "DRC": Event.COMPUTER_DRC,
}
DEFAULT_PREFIX = "hcsm/events"
HELD_PER_TARGET = 64
"""Events kept for a target with no matched subscription (the oldest are dropped beyond)."""

EVENT_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=256,
    durability=DurabilityPolicy.VOLATILE,
)


def to_msg(event: WireEvent, codes: Mapping[str, int] = RMAX_COMPUTERS) -> Event:
    """Convert a sealed wire event to a ROS message."""
    msg = Event()
    msg.id = event.event_id
    msg.name = event.name
    msg.data = event.data
    msg.source_computer = codes[event.source]
    msg.target_computer = codes[event.target]
    msg.sequence = event.sequence
    msg.crc32 = event.crc32
    msg.incarnation = event.incarnation
    return msg


def from_msg(msg: Event, codes: Mapping[str, int] = RMAX_COMPUTERS) -> WireEvent | None:
    """Convert a ROS message to a wire event; None if a computer code is unknown."""
    names = {code: name for name, code in codes.items()}
    source = names.get(int(msg.source_computer))
    target = names.get(int(msg.target_computer))
    if source is None or target is None:
        return None
    return WireEvent(
        int(msg.id),
        str(msg.name),
        bytes(msg.data),
        source,
        target,
        int(msg.sequence),
        int(msg.crc32),
        int(msg.incarnation),
    )


class RosTransport:
    """The :class:`~hdrc3_hcsm.transport.Transport` of one computer on ROS 2."""

    def __init__(
        self,
        node: Node,
        computer: str,
        *,
        prefix: str = DEFAULT_PREFIX,
        codes: Mapping[str, int] = RMAX_COMPUTERS,
    ) -> None:
        if computer not in codes:
            raise ValueError(f"computer {computer!r} has no code in {sorted(codes)}")
        self.computer = computer
        self.stats = ChannelStats()
        self.malformed = 0
        self._node = node
        self._prefix = prefix
        self._codes = dict(codes)
        self._integrity = ChannelIntegrity(self.stats)
        self._held: dict[str, deque[Event]] = {
            name: deque(maxlen=HELD_PER_TARGET) for name in self._codes if name != computer
        }
        self._inbox: deque[Event] = deque()
        self._lock = threading.Lock()
        self._publishers = {
            name: node.create_publisher(Event, f"{prefix}/{name}", EVENT_QOS)
            for name in self._codes
            if name != computer
        }
        self._subscription = node.create_subscription(
            Event, f"{prefix}/{computer}", self._on_event, EVENT_QOS
        )

    def _on_event(self, msg: Event) -> None:
        with self._lock:
            self._inbox.append(msg)

    @property
    def incarnation(self) -> int:
        """The incarnation of this transport (stamped on every event it sends)."""
        return self._integrity.incarnation

    def send(self, event: WireEvent) -> SendStatus:
        """Seal and publish one event on its target's topic (held while nobody subscribes)."""
        if event.target not in self._publishers:
            self.stats.no_route += 1
            return SendStatus.NO_ROUTE
        self._held[event.target].append(to_msg(self._integrity.seal(event), self._codes))
        self.stats.sent += 1
        self._release(event.target)
        return SendStatus.SENT

    def _release(self, target: str) -> None:
        """Publish the events held for ``target`` once its subscription is matched."""
        held = self._held[target]
        publisher = self._publishers[target]
        if held and publisher.get_subscription_count() > 0:
            while held:
                publisher.publish(held.popleft())

    def held(self, target: str) -> int:
        """Events waiting for ``target``'s subscription to match."""
        return len(self._held.get(target, ()))

    def restarts(self) -> list[str]:
        """Computers heard with a new incarnation (restarted) since the last call."""
        return self._integrity.restarts()

    def receive(self) -> list[WireEvent]:
        """Events received since the last call that passed the integrity check, in order.

        Also publishes the events held for targets whose subscription has matched meanwhile.
        """
        for target in self._held:
            self._release(target)
        with self._lock:
            messages = list(self._inbox)
            self._inbox.clear()
        out: list[WireEvent] = []
        for msg in messages:
            event = from_msg(msg, self._codes)
            if event is None:
                self.malformed += 1
            elif self._integrity.accept(event) is Verdict.ACCEPTED:
                out.append(event)
        return out

    def subscribers(self, target: str) -> int:
        """Count the subscriptions matched on ``target``'s topic (discovery check)."""
        publisher = self._publishers.get(target)
        return 0 if publisher is None else int(publisher.get_subscription_count())

    def destroy(self) -> None:
        """Remove publishers and the subscription from the node."""
        for publisher in self._publishers.values():
            self._node.destroy_publisher(publisher)
        self._node.destroy_subscription(self._subscription)


class TracePublisher:
    """A :class:`~hdrc3_hcsm.trace.TraceSink` publishing records as JSON on a String topic."""

    def __init__(self, node: Node, topic: str = "hcsm/trace") -> None:
        self._publisher = node.create_publisher(String, topic, EVENT_QOS)

    def record(self, record: TraceRecord) -> None:
        """Publish one trace record."""
        self._publisher.publish(String(data=record.to_json()))
