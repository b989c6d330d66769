import os

import pytest

from hdrc3.supervisor import ProcessState, ProcessStatus
from hdrc3.system_health import HealthLevel, ResourceProbe, ResourceSample, assess


def _report(state: ProcessState, restarts: int = 0, node: str = "/n") -> ProcessStatus:
    return ProcessStatus("n", node, 42, state, restarts, 7)


@pytest.mark.parametrize(
    ("state", "restarts", "visible", "level", "message"),
    [
        (ProcessState.RUNNING, 0, True, HealthLevel.OK, "running"),
        (ProcessState.RUNNING, 2, True, HealthLevel.WARN, "running; restarted 2 times"),
        (ProcessState.RUNNING, 0, False, HealthLevel.WARN, "node is not in the graph"),
        (ProcessState.STARTING, 0, False, HealthLevel.WARN, "starting"),
        (ProcessState.BACKOFF, 1, False, HealthLevel.ERROR, "crashed (exit code 7)"),
        (ProcessState.FAILED, 3, False, HealthLevel.ERROR, "gave up after 3 restarts"),
        (ProcessState.STOPPED, 0, False, HealthLevel.STALE, "stopped"),
    ],
)
def test_assess(state, restarts, visible, level, message) -> None:
    report = assess(_report(state, restarts), visible, ResourceSample(12.5, 3 * 2**20))
    assert report.level is level
    assert message in report.message
    assert dict(report.values)["rss_mb"] == "3.0"


def test_process_without_node_needs_no_graph_presence() -> None:
    assert assess(_report(ProcessState.RUNNING, node=""), False, None).level is HealthLevel.OK


def test_probe_measures_live_processes_only() -> None:
    probe = ResourceProbe()
    sample = probe.sample(os.getpid())
    assert sample is not None and sample.rss_bytes > 10 * 2**20
    assert probe.sample(0) is None
    assert probe.sample(2**22 + 12345) is None
