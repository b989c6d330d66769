"""A trivial attitude-holding controller process for the world_sim lockstep benchmark.

Each agent: engine on and autonomous through the RC service, then on every /clock tick it
answers a YACS command stamped with that tick (level attitude, climb 1 m/s for the first 25 s,
then hold height). It subscribes to the attitude sensor (``--sensors attitude``) or to every
sensor a control kernel reads (``--sensors all``: 200 Hz IMU, attitude, GPS, barometer, rpm,
ground contact, YACS status), so that world_sim publishes them as in a real run; it only counts
them. With ``--observe`` it sends nothing and only measures how fast /clock advances.

Prints one JSON line: sim seconds, wall seconds, ticks answered.

Run (world_sim must be running on the same ROS_DOMAIN_ID):
    .venv/bin/python bench/lockstep_controller.py --agents uav0 --seconds 60
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import rclpy
from geometry_msgs.msg import TwistStamped
from rclpy.experimental.events_executor import EventsExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, NavSatFix

from hdrc3_base.stamps import stamp_s
from hdrc3_interfaces.msg import (
    Attitude,
    Barometer,
    GroundContact,
    RotorRpm,
    YacsCommand,
    YacsStatus,
)
from hdrc3_interfaces.srv import SimSetRc

CLOCK_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
COMMAND_QOS = QoSProfile(depth=20, reliability=ReliabilityPolicy.RELIABLE)


class Controller(Node):
    """Answers every /clock tick of world_sim with a level-attitude YACS command per agent."""

    def __init__(self, agents: list[str], seconds: float, observe: bool, all_sensors: bool) -> None:
        super().__init__("bench_lockstep_controller")
        self.agents = agents
        self.seconds = seconds
        self.observe = observe
        self.first: tuple[float, float] | None = None  # (sim s, wall s) at the first tick
        self.last: tuple[float, float] | None = None
        self.ticks = 0
        self.samples = 0
        self.done = False
        self.pubs = {
            a: self.create_publisher(YacsCommand, f"/{a}/yacs/command", COMMAND_QOS)
            for a in ([] if observe else agents)
        }
        sensors = (
            (Imu, "sensors/imu"),
            (Attitude, "sensors/attitude"),
            (NavSatFix, "sensors/gps/fix"),
            (TwistStamped, "sensors/gps/velocity"),
            (Barometer, "sensors/barometer"),
            (RotorRpm, "sensors/rpm"),
            (GroundContact, "sensors/ground_contact"),
            (YacsStatus, "yacs/status"),
        )
        for a in agents:
            for msg_type, topic in sensors if all_sensors else sensors[1:2]:
                self.create_subscription(msg_type, f"/{a}/{topic}", self._on_sample, 50)
        self.create_subscription(Clock, "/clock", self._on_clock, CLOCK_QOS)
        self.msg = YacsCommand()
        self.armed = observe
        """Answer ticks only once RC is set and world_sim has matched every command publisher."""
        self.pending: Clock | None = None

    def _on_sample(self, msg: object) -> None:
        self.samples += 1

    def _on_clock(self, msg: Clock) -> None:
        self.pending = msg
        if self.armed:
            self.answer(msg)

    def answer(self, msg: Clock) -> None:
        """Answer one tick (and start the measurement at the first one)."""
        sim = stamp_s(msg.clock)
        wall = time.perf_counter()
        if self.first is None:
            self.first = (sim, wall)
        self.last = (sim, wall)
        if sim - self.first[0] >= self.seconds:
            self.done = True
            return
        m = self.msg
        m.header.stamp = msg.clock
        m.vertical = 1.0 if sim < 25.0 else 0.0
        for pub in self.pubs.values():
            pub.publish(m)
        self.ticks += 1


def set_rc(node: Node, executor: EventsExecutor, agent: str) -> None:
    client = node.create_client(SimSetRc, f"/{agent}/rc/set")
    if not client.wait_for_service(timeout_sec=30.0):
        raise SystemExit(f"no RC service for {agent}")
    request = SimSetRc.Request(
        mode=SimSetRc.Request.MODE_AUTONOMOUS, engine=SimSetRc.Request.ENGINE_ON
    )
    future = client.call_async(request)
    deadline = time.monotonic() + 30.0
    while not future.done() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    if not future.done() or future.result().result.code != 0:
        raise SystemExit(f"RC request for {agent} failed")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--agents", default="uav0")
    parser.add_argument("--seconds", type=float, default=60.0, help="sim seconds to run")
    parser.add_argument("--observe", action="store_true", help="send nothing, measure /clock")
    parser.add_argument("--sensors", choices=("attitude", "all"), default="attitude")
    parser.add_argument("--timeout", type=float, default=300.0, help="wall-clock bound, s")
    args = parser.parse_args()
    rclpy.init()
    node = Controller(args.agents.split(","), args.seconds, args.observe, args.sensors == "all")
    executor = EventsExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + 30.0
    if not args.observe:
        for agent in node.agents:
            set_rc(node, executor, agent)
        # an answer written before world_sim's subscription matched would be lost
        while not all(p.get_subscription_count() for p in node.pubs.values()):
            if time.monotonic() > deadline:
                raise SystemExit("world_sim does not subscribe to the commands")
            executor.spin_once(timeout_sec=0.05)
        node.armed = True
        if node.pending is not None:
            node.answer(node.pending)
    deadline = time.monotonic() + args.timeout
    while not node.done and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    if node.first is None or node.last is None or not node.done:
        print(json.dumps({"error": "timed out", "ticks": node.ticks}), flush=True)
        return 1
    sim = node.last[0] - node.first[0]
    wall = node.last[1] - node.first[1]
    print(json.dumps({"sim": sim, "wall": wall, "ticks": node.ticks, "samples": node.samples}))
    executor.shutdown()
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
