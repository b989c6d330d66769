"""The execution monitor node reads the hook's carrying sensor (HookState) over real DDS.

An ``execution_monitor`` of uav0 (world revinge: a ``carrying(uav0, L)`` stream per box and
carrier) runs in-process on the test's own domain with the packaged ``default.monitors``. The
test is the rest of the system: it publishes ``/clock``, the carrying sensor
(``/uav0/sensors/carrying`` at 10 Hz, ``HookState``) and the pick-up step's execution flag, in
sim time it steps itself. While box1 is held after the pick-up nothing is violated; when the
sensor stops reporting it, ``box_held`` (Example 9.4) is violated at that reading's state,
naming the ``box-lost`` recovery operator and the emergency brake.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

pytestmark = pytest.mark.ros

WAIT_S = 30.0
PICK_ON_MS, PICK_OFF_MS, LOST_MS, END_MS = 500, 2000, 4000, 5000
STEP_MS = 50


@pytest.fixture
def monitor_context(ros_domain: int) -> Iterator[Any]:
    import rclpy
    from rclpy.context import Context

    context = Context()
    args = ["--ros-args", "-r", "__ns:=/uav0", "-p", "world:=revinge"]
    rclpy.init(args=args, context=context, domain_id=ros_domain)
    try:
        yield context
    finally:
        context.try_shutdown()


def test_a_box_lost_after_its_pick_up_violates_box_held(monitor_context: Any) -> None:
    from builtin_interfaces.msg import Time
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from rosgraph_msgs.msg import Clock

    from hdrc3_deliberative.execution_monitor_node import ExecutionMonitorNode
    from hdrc3_interfaces.msg import ExecutionFlag, HookState, MonitorViolation
    from tests.integration.ros_wait import spin_until

    monitor = ExecutionMonitorNode(monitor_context)
    test = Node("carrying_test", context=monitor_context, use_global_arguments=False)
    executor = SingleThreadedExecutor(context=monitor_context)
    executor.add_node(monitor)
    executor.add_node(test)
    latched = QoSProfile(
        depth=100,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )
    violations: list[Any] = []

    def on_violation(msg: Any) -> None:
        if msg.kind == MonitorViolation.KIND_VIOLATION:  # not the stale Data Interface
            violations.append(msg)

    test.create_subscription(MonitorViolation, "/uav0/monitor_violations", on_violation, latched)
    clock = test.create_publisher(Clock, "/clock", latched)
    hook = test.create_publisher(HookState, "/uav0/sensors/carrying", 10)
    flags = test.create_publisher(ExecutionFlag, "/uav0/execution_flags", latched)
    try:
        assert spin_until(executor, lambda: hook.get_subscription_count() > 0, WAIT_S), (
            "the monitor does not subscribe the carrying sensor"
        )
        samples = monitor.streams.host.generator("uav0/hook/box1")

        def stamp(ms: int) -> Time:
            return Time(sec=ms // 1000, nanosec=(ms % 1000) * 1_000_000)

        for now in range(STEP_MS, END_MS + 1, STEP_MS):
            clock.publish(Clock(clock=stamp(now)))
            if now in (PICK_ON_MS, PICK_OFF_MS):
                flag = ExecutionFlag(
                    agent="uav0",
                    node_id="d/2",
                    action="pick-up-box",
                    executing=now == PICK_ON_MS,
                    argument_names=["box"],
                    argument_values=["box1"],
                )
                flag.header.stamp = stamp(now)
                flags.publish(flag)
            if now % 100 == 0:
                held = "box1" if 1500 <= now < LOST_MS else ""
                reading = HookState(carrying=bool(held), object_id=held, magnet=bool(held))
                reading.header.stamp = stamp(now)
                seen = samples.status().stats.samples_in
                hook.publish(reading)
                assert spin_until(
                    executor, lambda s=seen: samples.status().stats.samples_in > s, WAIT_S
                ), f"reading at {now} ms not received"
            assert spin_until(
                executor,
                lambda n=now: monitor.get_clock().now().nanoseconds >= n * 1_000_000,
                WAIT_S,
            ), f"clock {now} ms not received"
            if now < LOST_MS:
                assert violations == [], f"violated at {now} ms while box1 was held"
        assert spin_until(executor, lambda: bool(violations), WAIT_S), "no violation"
    finally:
        executor.shutdown()
        test.destroy_node()
        monitor.destroy_node()

    (violation,) = violations
    assert violation.kind == MonitorViolation.KIND_VIOLATION
    assert violation.monitor_id.startswith("box_held@")
    assert (violation.action, violation.node_id) == ("pick-up-box", "d/2")
    assert (violation.recovery, violation.emergency_brake) == ("box-lost", True)
    assert dict(zip(violation.argument_names, violation.argument_values, strict=True)) == {
        "box": "box1"
    }
    decided = violation.header.stamp.sec * 1000 + violation.header.stamp.nanosec // 1_000_000
    assert LOST_MS <= decided <= LOST_MS + 100  # the state of the first reading without box1
