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
from hdrc3.warm_spare import SUPPORTED, WarmSpare

pytestmark = pytest.mark.skipif(not SUPPORTED, reason="the warm spare needs Linux")

FAKE = "hdrc3.fake_spare_child"
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


def _until_ready(spare: WarmSpare) -> None:
    deadline = time.monotonic() + LIMIT_S
    while not spare.ready and time.monotonic() < deadline:
        spare.collect(0.2)
    assert spare.ready


@pytest.fixture
def lines() -> list[str]:
    return []


@pytest.fixture
def spare(lines: list[str]) -> Iterator[WarmSpare]:
    with WarmSpare([FAKE], lines.append, respawn_delay_s=0.0) as server:
        server.start()
        _until_ready(server)
        assert "warm spare ready: 1 node modules" in lines[0]
        yield server


def _spare_pid(server: WarmSpare) -> int:
    assert server._process is not None
    return server._process.pid


@pytest.mark.parametrize("code", [0, 3])
def test_the_spare_becomes_the_node_with_its_argv_env_and_session(
    spare: WarmSpare, tmp_path: Path, code: int
) -> None:
    pid = _spare_pid(spare)
    spec = _spec(tmp_path, str(code))
    node = spare.spawn(spec)
    assert node.pid == pid and not spare.alive
    assert _code(node) == code
    assert _seen(spec) == {
        "argv": list(spec.argv),
        "probe": "node",
        "leader": True,
        "parent": os.getpid(),
    }


@pytest.mark.parametrize(("stop", "code"), [("send_signal", 0), ("kill", -signal.SIGKILL)])
def test_signals_reach_the_node_in_the_spare(
    spare: WarmSpare, tmp_path: Path, stop: str, code: int
) -> None:
    spec = _spec(tmp_path, "wait")
    node = spare.spawn(spec)
    _seen(spec)
    assert node.poll() is None
    if stop == "send_signal":
        node.send_signal(signal.SIGINT)
    else:
        node.kill()
    assert _code(node) == code


def test_a_new_spare_follows_each_handover(spare: WarmSpare, tmp_path: Path) -> None:
    first = spare.spawn(_spec(tmp_path, "0", "a"))
    spare.collect()  # the respawn delay (0 here) is over: the next spare starts
    assert spare.alive
    _until_ready(spare)
    second = spare.spawn(_spec(tmp_path, "0", "b"))
    assert second.pid != first.pid
    assert (_code(first), _code(second)) == (0, 0)
    assert [_seen(_spec(tmp_path, "0", n))["probe"] for n in "ab"] == ["a", "b"]


def test_a_restart_before_the_next_spare_is_ready_starts_an_interpreter(
    lines: list[str], tmp_path: Path
) -> None:
    with WarmSpare([FAKE], lines.append, respawn_delay_s=3600.0) as server:
        server.start()
        _until_ready(server)
        first = server.spawn(_spec(tmp_path, "wait", "a"))
        server.collect()  # no replacement for an hour
        assert not server.alive
        spec = ProcessSpec("p", (sys.executable, "-c", "raise SystemExit(4)"), entry=f"{FAKE}:main")
        fallback = server.spawn(spec)
        assert isinstance(fallback, subprocess.Popen) and fallback.wait(LIMIT_S) == 4
        first.kill()
        assert _code(first) == -signal.SIGKILL


def test_the_supervisor_restarts_through_spares(spare: WarmSpare, tmp_path: Path) -> None:
    spec = _spec(tmp_path, "5")
    sup = Supervisor([spec], RestartPolicy(max_restarts=2, initial_backoff_s=0.0), spare.spawn)
    sup.start_all()
    pids: set[int] = set()

    def failed() -> bool:
        pids.add(sup.snapshot()[0].pid)
        if spare.ready:  # each restart waits for the next spare: the fake node has no script
            sup.poll(time.monotonic())
        return sup.snapshot()[0].state is ProcessState.FAILED

    _until(failed, "given up after 2 restarts")
    status = sup.snapshot()[0]
    assert (status.restarts, status.last_exit_code) == (2, 5)
    assert len(pids - {0}) == 3  # the first start and two restarts, each its own process


def test_a_spare_that_died_is_replaced_and_meanwhile_popen_starts_nodes(
    spare: WarmSpare, lines: list[str], tmp_path: Path
) -> None:
    os.kill(_spare_pid(spare), signal.SIGKILL)
    spec = ProcessSpec("p", (sys.executable, "-c", "pass"), entry=f"{FAKE}:main")
    fallback = spare.spawn(spec)
    assert isinstance(fallback, subprocess.Popen)
    assert fallback.wait(LIMIT_S) == 0
    assert any("warm spare exited" in line for line in lines)
    spare.collect()  # respawn delay 0: a new spare
    _until_ready(spare)


def test_without_an_entry_point_or_before_ready_a_process_is_popened(tmp_path: Path) -> None:
    argv = (sys.executable, "-c", "raise SystemExit(4)")
    with WarmSpare([FAKE], lambda _line: None) as server:  # never started
        for spec in (ProcessSpec("p", argv), ProcessSpec("q", argv, entry=f"{FAKE}:main")):
            process = server.spawn(spec)
            assert isinstance(process, subprocess.Popen)
            assert process.wait(LIMIT_S) == 4


def test_closing_ends_the_unused_spare_and_keeps_the_nodes(tmp_path: Path) -> None:
    server = WarmSpare([FAKE], lambda _line: None, respawn_delay_s=0.0)
    server.start()
    _until_ready(server)
    spec = _spec(tmp_path, "wait")
    node = server.spawn(spec)
    _seen(spec)
    server.collect()
    process = server._process
    assert process is not None
    server.close()
    assert process.poll() is not None and not server.alive
    assert node.poll() is None  # the node is the supervisor's, not the spare's
    node.send_signal(signal.SIGINT)
    assert _code(node) == 0
