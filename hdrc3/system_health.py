"""Health of supervised processes: liveness, restarts, CPU and memory -> diagnostic levels.

Pure core of the system monitor; levels match ``diagnostic_msgs/DiagnosticStatus``.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import psutil

from hdrc3.supervisor import ProcessState, ProcessStatus


class HealthLevel(enum.IntEnum):
    """Diagnostic level (values of DiagnosticStatus.OK/WARN/ERROR/STALE)."""

    OK = 0
    WARN = 1
    ERROR = 2
    STALE = 3


@dataclass(frozen=True, slots=True)
class ResourceSample:
    """CPU and memory use of one process."""

    cpu_percent: float
    rss_bytes: int


@dataclass(frozen=True, slots=True)
class HealthReport:
    """One diagnostic entry."""

    name: str
    level: HealthLevel
    message: str
    values: tuple[tuple[str, str], ...]


def assess(
    process: ProcessStatus, node_visible: bool, resources: ResourceSample | None
) -> HealthReport:
    """Judge one process from its supervision state, graph presence and resource use."""
    if process.state is ProcessState.FAILED:
        level, message = (
            HealthLevel.ERROR,
            f"gave up after {process.restarts} restarts (exit code {process.last_exit_code})",
        )
    elif process.state is ProcessState.BACKOFF:
        level, message = (
            HealthLevel.ERROR,
            f"crashed (exit code {process.last_exit_code}); restart pending",
        )
    elif process.state is ProcessState.STOPPED:
        level, message = HealthLevel.STALE, "stopped"
    elif process.state is ProcessState.STARTING:
        level, message = HealthLevel.WARN, "starting"
    elif process.node_name and not node_visible:
        level, message = HealthLevel.WARN, "process runs but its node is not in the graph"
    elif process.restarts:
        level, message = HealthLevel.WARN, f"running; restarted {process.restarts} times"
    else:
        level, message = HealthLevel.OK, "running"
    values: list[tuple[str, str]] = [
        ("pid", str(process.pid)),
        ("state", process.state.name),
        ("restarts", str(process.restarts)),
        ("node_visible", str(node_visible).lower()),
    ]
    if resources is not None:
        values += [
            ("cpu_percent", f"{resources.cpu_percent:.1f}"),
            ("rss_mb", f"{resources.rss_bytes / 2**20:.1f}"),
        ]
    return HealthReport(process.name, level, message, tuple(values))


class ResourceProbe:
    """Measures processes by pid; CPU percent is over the interval since the previous call."""

    def __init__(self) -> None:
        """Start with no process known."""
        self._processes: dict[int, psutil.Process] = {}

    def sample(self, pid: int) -> ResourceSample | None:
        """Measure ``pid``; None if it does not exist (any more)."""
        if pid <= 0:
            return None
        try:
            proc = self._processes.get(pid)
            if proc is None:
                proc = psutil.Process(pid)
                self._processes[pid] = proc
                proc.cpu_percent(None)  # first call only primes the counter
            with proc.oneshot():
                return ResourceSample(proc.cpu_percent(None), proc.memory_info().rss)
        except (psutil.NoSuchProcess, psutil.AccessDenied, psutil.ZombieProcess):
            self._processes.pop(pid, None)
            return None

    def forget_except(self, pids: set[int]) -> None:
        """Drop cached handles of processes no longer supervised."""
        for pid in set(self._processes) - pids:
            del self._processes[pid]
