"""The launcher node: supervises node processes and publishes their status.

It watches the ROS graph to tell when each supervised node is up, restarts crashed processes
through :class:`~hdrc3.supervisor.Supervisor`, and publishes a :class:`LaunchStatus` snapshot
(latched) that the system monitor turns into diagnostics.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from rclpy.context import Context
from rclpy.node import Node

from hdrc3.launch_plan import RECORDER
from hdrc3.supervisor import ProcessSpec, ProcessState, Supervisor
from hdrc3_base.ros_runtime import STATUS_QOS, STATUS_TOPIC, node_name_counts, node_names
from hdrc3_interfaces.msg import LaunchStatus, SupervisedProcess

STATUS_PERIOD_S = 0.5
LAUNCHER_PREFIX = "hdrc3_launcher_"


class LauncherNode(Node):
    """Owns the supervisor of one launch and reports on it."""

    def __init__(
        self,
        context: Context,
        specs: Sequence[ProcessSpec],
        report: Callable[[str], None] = print,
        supervisor: Supervisor | None = None,
    ) -> None:
        """Prepare to supervise ``specs``; ``report`` receives one line per notable event."""
        # The start time in the name orders launches: on a clash the younger one yields.
        self.started_ns = time.time_ns()
        super().__init__(f"{LAUNCHER_PREFIX}{self.started_ns}", context=context)
        self.specs = list(specs)
        self.supervisor = supervisor or Supervisor(self.specs)
        self._report = report
        self._publisher = self.create_publisher(LaunchStatus, STATUS_TOPIC, STATUS_QOS)
        self.create_timer(STATUS_PERIOD_S, self.publish_status)

    def expected_nodes(self) -> dict[str, str]:
        """Process name -> ROS node name, for processes that create a node."""
        return {s.name: s.node_name for s in self.specs if s.node_name}

    def conflicts(self, started: bool = False) -> list[str]:
        """Node names of this launch that another launch also runs in this domain.

        Args:
            started: Whether this launch's processes are running; then a name counts as a
                conflict only when it appears twice.
        """
        counts = node_name_counts(self)
        least = 2 if started else 1
        return sorted(n for n in self.expected_nodes().values() if counts[n] >= least)

    def older_launch_present(self) -> bool:
        """True if a launcher that started before this one is in the graph."""
        for name, _ in self.get_node_names_and_namespaces():
            suffix = name.removeprefix(LAUNCHER_PREFIX)
            if suffix != name and suffix.isdigit() and int(suffix) < self.started_ns:
                return True
        return False

    def missing(self) -> list[str]:
        """Node names of this launch not (yet) visible in the graph."""
        present = node_names(self)
        return sorted(n for n in self.expected_nodes().values() if n not in present)

    def tick(self) -> None:
        """Supervise: report exits/restarts, mark processes whose node is visible as running."""
        events = self.supervisor.poll(time.monotonic())
        for event in events:
            self._report(f"[launch] {event.name}: {event.message}")
        if events:  # a crash is news at once (platform servers end the lost commands)
            self.publish_status()
        present = node_names(self)
        for status in self.supervisor.snapshot():
            if status.state is ProcessState.STARTING and (
                not status.node_name or status.node_name in present
            ):
                self.supervisor.mark_running(status.name)

    def failed(self) -> list[str]:
        """Processes the supervisor gave up on."""
        return [s.name for s in self.supervisor.snapshot() if s.state is ProcessState.FAILED]

    def publish_status(self) -> None:
        """Publish the current snapshot on the status topic."""
        msg = LaunchStatus()
        msg.header.stamp = self.get_clock().now().to_msg()
        for status in self.supervisor.snapshot():
            msg.processes.append(
                SupervisedProcess(
                    name=status.name,
                    node_name=status.node_name,
                    pid=status.pid,
                    state=int(status.state),
                    restarts=status.restarts,
                    last_exit_code=status.last_exit_code,
                )
            )
        self._publisher.publish(msg)

    def stop(self, timeout_s: float = 4.5) -> dict[str, int]:
        """Stop every process, the recorder last so that it records the shutdown."""
        codes = self.supervisor.stop_all(timeout_s, order=(RECORDER,))
        self.publish_status()
        return codes
