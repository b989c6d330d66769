"""The `system_monitor` node: publishes /diagnostics about every supervised node, once a second."""

from __future__ import annotations

import sys

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rclpy.context import Context
from rclpy.node import Node

from hdrc3.supervisor import ProcessState, ProcessStatus
from hdrc3.system_health import HealthLevel, ResourceProbe, assess
from hdrc3_base.ros_runtime import STATUS_QOS, STATUS_TOPIC, node_names, run_node
from hdrc3_interfaces.msg import LaunchStatus

PUBLISH_PERIOD_S = 1.0
HARDWARE_ID = "hdrc3"


class SystemMonitorNode(Node):
    """Turns the launcher's status and the ROS graph into diagnostics."""

    def __init__(self, context: Context) -> None:
        """Subscribe to the launcher status and start the 1 Hz diagnostics timer."""
        super().__init__("system_monitor", context=context)
        self._latest: LaunchStatus | None = None
        self._probe = ResourceProbe()
        self._publisher = self.create_publisher(DiagnosticArray, "/diagnostics", 10)
        self.create_subscription(LaunchStatus, STATUS_TOPIC, self._on_status, STATUS_QOS)
        self.create_timer(PUBLISH_PERIOD_S, self.publish_diagnostics)

    def _on_status(self, msg: LaunchStatus) -> None:
        self._latest = msg

    def publish_diagnostics(self) -> None:
        """Publish one DiagnosticArray with an entry per supervised process."""
        array = DiagnosticArray()
        array.header.stamp = self.get_clock().now().to_msg()
        if self._latest is None:
            array.status.append(
                DiagnosticStatus(
                    level=bytes([int(HealthLevel.STALE)]),
                    name="hdrc3/launcher",
                    message="no status from an hdrc3 launcher yet",
                    hardware_id=HARDWARE_ID,
                )
            )
        else:
            visible = node_names(self)
            pids = {p.pid for p in self._latest.processes}
            self._probe.forget_except(pids)
            for proc in self._latest.processes:
                report = assess(
                    ProcessStatus(
                        proc.name,
                        proc.node_name,
                        proc.pid,
                        ProcessState(proc.state),
                        proc.restarts,
                        proc.last_exit_code,
                    ),
                    node_visible=proc.node_name in visible,
                    resources=self._probe.sample(proc.pid),
                )
                array.status.append(
                    DiagnosticStatus(
                        level=bytes([int(report.level)]),
                        name=f"hdrc3/{report.name}",
                        message=report.message,
                        hardware_id=HARDWARE_ID,
                        values=[KeyValue(key=k, value=v) for k, v in report.values],
                    )
                )
        self._publisher.publish(array)


def main() -> int:
    """Console script `hdrc3-system-monitor`."""
    return run_node(SystemMonitorNode, args=sys.argv)


if __name__ == "__main__":
    sys.exit(main())
