import signal
import sys
import time

import pytest

from hdrc3.supervisor import ProcessSpec, ProcessState, RestartPolicy, Supervisor
from hdrc3_base.errors import ConfigError


def _python(code: str, name: str = "p") -> ProcessSpec:
    return ProcessSpec(name, (sys.executable, "-c", code))


def _poll_until(sup: Supervisor, now: float, predicate, limit_s: float = 10.0):
    """Poll with a fixed fake time until the predicate holds on the snapshot (bounded)."""
    deadline = time.monotonic() + limit_s
    events = []
    while time.monotonic() < deadline:
        events += sup.poll(now)
        if predicate(sup.snapshot()):
            return events
        time.sleep(0.01)
    raise AssertionError(f"condition not reached: {sup.snapshot()}")


@pytest.mark.parametrize(
    ("restarts", "expected"), [(0, 0.5), (1, 1.0), (3, 4.0), (4, 8.0), (10, 8.0)]
)
def test_backoff_doubles_up_to_the_cap(restarts: int, expected: float) -> None:
    assert RestartPolicy(initial_backoff_s=0.5, max_backoff_s=8.0).delay(restarts) == expected


def test_duplicate_names_are_rejected() -> None:
    with pytest.raises(ConfigError, match="duplicate process names: a"):
        Supervisor([_python("pass", "a"), _python("pass", "a")])


def test_crashed_process_is_restarted_after_backoff_then_given_up() -> None:
    sup = Supervisor([_python("raise SystemExit(3)")], RestartPolicy(max_restarts=1))
    sup.start_all()
    events = _poll_until(sup, 0.0, lambda s: s[0].state is ProcessState.BACKOFF)
    assert events[-1].message == "exited with code 3; restarting in 0.5 s"
    assert sup.poll(0.4) == []  # back-off not over yet
    assert sup.poll(0.5)[0].message == "restarted (restart 1)"
    events = _poll_until(sup, 1.0, lambda s: s[0].state is ProcessState.FAILED)
    assert "gave up after 1 restarts" in events[-1].message
    assert sup.snapshot()[0].last_exit_code == 3


def test_running_process_is_reported_and_stopped_by_sigint() -> None:
    sup = Supervisor([_python("import time\nwhile True: time.sleep(0.05)")])
    sup.start_all()
    sup.mark_running("p")
    status = sup.snapshot()[0]
    assert status.state is ProcessState.RUNNING and status.pid > 0
    codes = sup.stop_all(timeout_s=3.0)
    assert codes["p"] != 0
    assert sup.snapshot()[0].state is ProcessState.STOPPED


def test_stubborn_process_is_escalated_within_the_timeout() -> None:
    ignore = (
        "import signal, sys, time\n"
        "signal.signal(signal.SIGINT, signal.SIG_IGN)\n"
        "signal.signal(signal.SIGTERM, signal.SIG_IGN)\n"
        "print('armed', flush=True)\n"
        "while True: time.sleep(0.05)"
    )
    import subprocess

    started: list[subprocess.Popen[bytes]] = []

    def spawn(spec: ProcessSpec) -> subprocess.Popen[bytes]:
        proc = subprocess.Popen(spec.argv, stdout=subprocess.PIPE)
        assert proc.stdout is not None
        proc.stdout.readline()  # handlers installed
        started.append(proc)
        return proc

    sup = Supervisor([_python(ignore)], spawn=spawn)
    sup.start_all()
    begin = time.monotonic()
    codes = sup.stop_all(timeout_s=1.0)
    assert time.monotonic() - begin < 2.0
    assert codes["p"] == -signal.SIGKILL
    started[0].wait(timeout=5)


def test_order_stops_named_processes_last() -> None:
    stopped: list[str] = []

    class Fake:
        def __init__(self, name: str) -> None:
            self.name, self.pid, self.code = name, 1, None

        def poll(self):
            return self.code

        def send_signal(self, sig: int) -> None:
            stopped.append(self.name)
            self.code = 0

        def kill(self) -> None:
            raise AssertionError("not needed")

    specs = [_python("", "recorder"), _python("", "a"), _python("", "b")]
    sup = Supervisor(specs, spawn=lambda spec: Fake(spec.name))
    sup.start_all()
    sup.stop_all(timeout_s=1.0, order=("recorder",))
    assert stopped == ["a", "b", "recorder"]
