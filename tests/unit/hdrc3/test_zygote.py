import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from hdrc3.supervisor import ProcessSpec, ProcessState, RestartPolicy, Supervisor
from hdrc3.zygote import SUPPORTED, ForkedProcess, ForkServer

pytestmark = pytest.mark.skipif(not SUPPORTED, reason="the fork server needs Linux pidfds")

FAKE = "hdrc3.fake_zygote_child"
LIMIT_S = 30.0


def _until(done: Callable[[], object], what: str) -> None:
    deadline = time.monotonic() + LIMIT_S
    while not done():
        assert time.monotonic() < deadline, f"not within {LIMIT_S} s: {what}"
        time.sleep(0.01)


def _spec(tmp_path: Path, what: str, name: str = "node") -> ProcessSpec:
    out = str(tmp_path / f"{name}.json")
    argv = ("/usr/bin/fake-node", what, out)
    return ProcessSpec(name, argv, entry=f"{FAKE}:main", env={"HDRC3_PROBE": name})


def _seen(spec: ProcessSpec) -> dict[str, object]:
    out = Path(spec.argv[2])
    _until(out.exists, f"{spec.name} started")
    return dict(json.loads(out.read_text()))


def _code(process: object) -> int:
    _until(lambda: process.poll() is not None, "exit")  # type: ignore[attr-defined]
    return int(process.poll())  # type: ignore[attr-defined]


@pytest.fixture
def zygote() -> Iterator[ForkServer]:
    lines: list[str] = []
    with ForkServer([FAKE], lines.append) as server:
        server.start()
        deadline = time.monotonic() + LIMIT_S
        while not server.ready and time.monotonic() < deadline:
            server.collect(0.2)
        assert server.ready, lines
        assert "fork server ready: 1 node modules" in lines[0]
        yield server


def _zygote_pid(server: ForkServer) -> int:
    assert server._process is not None
    return server._process.pid


@pytest.mark.parametrize("code", [0, 3])
def test_a_forked_child_runs_the_entry_point_with_its_argv_env_and_session(
    zygote: ForkServer, tmp_path: Path, code: int
) -> None:
    spec = _spec(tmp_path, str(code))
    child = zygote.spawn(spec)
    assert isinstance(child, ForkedProcess)
    assert _code(child) == code
    assert _seen(spec) == {
        "argv": list(spec.argv),
        "probe": "node",
        "leader": True,
        "parent": _zygote_pid(zygote),
    }


@pytest.mark.parametrize(("stop", "code"), [("send_signal", 0), ("kill", -signal.SIGKILL)])
def test_signals_reach_the_forked_child(
    zygote: ForkServer, tmp_path: Path, stop: str, code: int
) -> None:
    spec = _spec(tmp_path, "wait")
    child = zygote.spawn(spec)
    _seen(spec)
    assert child.poll() is None
    if stop == "send_signal":
        child.send_signal(signal.SIGINT)
    else:
        child.kill()
    assert _code(child) == code
    child.kill()  # ended: a no-op, never a signal to a reused pid


def test_the_supervisor_restarts_through_the_zygote(zygote: ForkServer, tmp_path: Path) -> None:
    spec = _spec(tmp_path, "5")
    sup = Supervisor([spec], RestartPolicy(max_restarts=2, initial_backoff_s=0.0), zygote.spawn)
    sup.start_all()
    pids: set[int] = set()

    def failed() -> bool:
        pids.add(sup.snapshot()[0].pid)
        sup.poll(time.monotonic())
        return sup.snapshot()[0].state is ProcessState.FAILED

    _until(failed, "given up after 2 restarts")
    status = sup.snapshot()[0]
    assert (status.restarts, status.last_exit_code) == (2, 5)
    assert len(pids - {0}) == 3  # the first start and two restarts, each forked


def test_children_end_with_the_zygote_and_later_starts_use_popen(
    zygote: ForkServer, tmp_path: Path
) -> None:
    children = [zygote.spawn(_spec(tmp_path, "wait", f"n{i}")) for i in range(2)]
    for i in range(2):
        _seen(_spec(tmp_path, "wait", f"n{i}"))
    os.kill(_zygote_pid(zygote), signal.SIGKILL)
    # the zygote's death sends them SIGTERM (PR_SET_PDEATHSIG): none is left behind
    assert [_code(c) for c in children] == [-signal.SIGTERM] * 2
    assert not zygote.alive
    spec = ProcessSpec("p", (sys.executable, "-c", "pass"), entry=f"{FAKE}:main")
    fallback = zygote.spawn(spec)
    assert isinstance(fallback, subprocess.Popen)
    assert fallback.wait(LIMIT_S) == 0


def test_without_an_entry_point_or_before_ready_a_process_is_popened(tmp_path: Path) -> None:
    argv = (sys.executable, "-c", "raise SystemExit(4)")
    with ForkServer([FAKE], lambda _line: None) as server:  # never started
        for spec in (ProcessSpec("p", argv), ProcessSpec("q", argv, entry=f"{FAKE}:main")):
            process = server.spawn(spec)
            assert isinstance(process, subprocess.Popen)
            assert process.wait(LIMIT_S) == 4


def test_closing_the_server_ends_the_zygote(tmp_path: Path) -> None:
    server = ForkServer([FAKE], lambda _line: None)
    server.start()
    process = server._process
    assert process is not None
    server.close()
    assert process.poll() is not None and not server.alive
