"""A stand-in for the control and perception kernels over real DDS (tests and the benchmark).

Runs :class:`~hdrc3_platform_server.fakes.FakePfc` and :class:`FakePpc` on the real-time channel
(``hcsm/events/*``), publishes ``/clock``, ``pfc/state`` and ``ppc/camera_state`` at 50 Hz of
sim time, advancing ``speed`` times faster than the wall clock. Not a simulator: it lets the
Platform Server be exercised end to end when the real kernels are not wanted.
Run: ``python -m hdrc3_platform_server.fake_node --ros-args -r __ns:=/uav0 -p speed:=10.0``.
"""

from __future__ import annotations

import sys

from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.context import Context
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock as ClockMsg

from hdrc3_base.ros_runtime import run_node
from hdrc3_base.stamps import set_stamp_s
from hdrc3_hcsm.ros_transport import RosTransport
from hdrc3_interfaces.msg import CameraState, PfcState
from hdrc3_platform_server.fakes import FakePfc, FakePfcTiming, FakePpc
from hdrc3_platform_server.node import STATE_QOS

TICK_S = 0.02
CLOCK_QOS = QoSProfile(  # type: ignore[no-untyped-call]  # rclpy is partly annotated
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)


class FakeKernelsNode(Node):
    """FakePfc + FakePpc behind the real transports and topics of one agent."""

    def __init__(self, context: Context | None = None) -> None:
        super().__init__("fake_kernels", context=context)
        speed = float(self.declare_parameter("speed", 1.0).value)
        on_ground = bool(self.declare_parameter("on_ground", True).value)
        duration = float(self.declare_parameter("duration", 0.0).value)
        timing = FakePfcTiming()
        if duration > 0.0:
            timing = FakePfcTiming(
                duration, duration, duration, duration, duration, duration, duration
            )
        self.pfc = FakePfc(RosTransport(self, "PFC"), timing, on_ground=on_ground)
        self.ppc = FakePpc(RosTransport(self, "PPC"))
        self.t = 0.0
        self.clock_pub = self.create_publisher(ClockMsg, "/clock", CLOCK_QOS)
        self.state_pub = self.create_publisher(PfcState, "pfc/state", STATE_QOS)
        self.camera_pub = self.create_publisher(CameraState, "ppc/camera_state", STATE_QOS)
        self.create_timer(
            TICK_S / max(speed, 1e-3), self._tick, clock=Clock(clock_type=ClockType.STEADY_TIME)
        )

    def _tick(self) -> None:
        self.t = round(self.t + TICK_S, 9)
        clock = ClockMsg()
        set_stamp_s(clock.clock, self.t)
        self.clock_pub.publish(clock)
        s = self.pfc.step(self.t)
        msg = PfcState()
        set_stamp_s(msg.header.stamp, self.t)
        set_stamp_s(msg.pfc_time, self.t)
        msg.position_enu = list(s.position_enu)
        msg.velocity_enu = list(s.velocity_enu)
        msg.heading, msg.rpm = s.heading, s.rpm
        msg.on_ground, msg.auto_flag, msg.mode = s.on_ground, s.auto_flag, int(s.mode)
        msg.command_id = s.command_id
        self.state_pub.publish(msg)
        cameras = self.ppc.step(self.t)
        if round(self.t / TICK_S) % 2:
            return  # the PPC reports the cameras at 25 Hz
        for cam in cameras:
            c = CameraState()
            set_stamp_s(c.header.stamp, self.t)
            c.id, c.pan, c.tilt, c.zoom = cam.camera_id, cam.pan, cam.tilt, cam.zoom
            set_stamp_s(c.ipc_time, cam.ipc_time)
            self.camera_pub.publish(c)


def main() -> int:
    """Entry point (``python -m hdrc3_platform_server.fake_node``)."""
    return run_node(FakeKernelsNode, args=sys.argv)


if __name__ == "__main__":
    sys.exit(main())
