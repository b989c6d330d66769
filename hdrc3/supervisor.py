"""Process supervision for the launcher: start, watch, restart with back-off, stop cleanly.

Pure core (no rclpy): time is passed in explicitly and processes are created through a spawn
function, so the behaviour is testable with real short-lived processes and a fake clock.
"""

from __future__ import annotations

import ctypes
import enum
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Protocol

from hdrc3_base.errors import ConfigError

_PR_SET_PDEATHSIG = 1  # from <linux/prctl.h>


class ProcessState(enum.IntEnum):
    """Lifecycle of a supervised process (values match SupervisedProcess.STATE_*)."""

    STARTING = 0
    RUNNING = 1
    BACKOFF = 2
    FAILED = 3
    STOPPED = 4


class ProcessLike(Protocol):
    """What the supervisor needs of a child process (subprocess.Popen satisfies it)."""

    pid: int

    def poll(self) -> int | None:
        """Return the exit code, or None while running."""

    def send_signal(self, sig: int) -> None:
        """Deliver a signal."""

    def kill(self) -> None:
        """Kill the process."""


@dataclass(frozen=True, slots=True)
class ProcessSpec:
    """How to start one supervised process."""

    name: str
    argv: tuple[str, ...]
    node_name: str = ""
    """Fully qualified ROS node name the process is expected to create ("" if none)."""
    env: Mapping[str, str] = field(default_factory=dict)
    """Variables added to the inherited environment."""
    entry: str = ""
    """``module:function`` of the console script in ``argv[0]`` ("" if unknown): lets the
    launcher's warm spare (:mod:`hdrc3.warm_spare`) restart it in a pre-imported interpreter."""


@dataclass(frozen=True, slots=True)
class SupervisorEvent:
    """Something the operator should hear about (a crash, a restart, giving up)."""

    name: str
    message: str


@dataclass(frozen=True, slots=True)
class ProcessStatus:
    """Snapshot of one supervised process."""

    name: str
    node_name: str
    pid: int
    state: ProcessState
    restarts: int
    last_exit_code: int


@dataclass(frozen=True, slots=True)
class RestartPolicy:
    """Exponential back-off between restarts, and how many restarts before giving up."""

    max_restarts: int = 3
    initial_backoff_s: float = 0.5
    max_backoff_s: float = 8.0

    def delay(self, restarts: int) -> float:
        """Back-off before restart number ``restarts + 1``."""
        return float(min(self.max_backoff_s, self.initial_backoff_s * 2**restarts))


def die_with_parent() -> None:
    """In the child: ask Linux to SIGTERM us if the launcher dies, even by SIGKILL."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)


def popen_spawn(spec: ProcessSpec) -> ProcessLike:
    """Start a process in its own session so that terminal signals reach only the launcher."""
    env = dict(os.environ)
    env.update(spec.env)
    try:
        return subprocess.Popen(
            spec.argv,
            env=env,
            start_new_session=True,
            preexec_fn=die_with_parent if sys.platform == "linux" else None,
        )
    except OSError as exc:
        raise ConfigError(f"cannot start {spec.name} ({spec.argv[0]}): {exc.strerror}") from exc


@dataclass
class _Child:
    spec: ProcessSpec
    process: ProcessLike | None = None
    state: ProcessState = ProcessState.STARTING
    restarts: int = 0
    last_exit_code: int = 0
    restart_at: float = 0.0


class Supervisor:
    """Starts a set of processes, restarts crashed ones with back-off, and stops them all."""

    def __init__(
        self,
        specs: Sequence[ProcessSpec],
        policy: RestartPolicy | None = None,
        spawn: Callable[[ProcessSpec], ProcessLike] = popen_spawn,
    ) -> None:
        """Prepare (but do not start) the processes in ``specs``; names must be unique."""
        names = [spec.name for spec in specs]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise ConfigError(f"duplicate process names: {', '.join(duplicates)}")
        self._policy = policy or RestartPolicy()
        self._spawn = spawn
        self._children = {spec.name: _Child(spec) for spec in specs}

    def start_all(self) -> None:
        """Start every process (in the order given)."""
        for child in self._children.values():
            self._start(child)

    def poll(self, now: float) -> list[SupervisorEvent]:
        """Notice exits, schedule restarts and perform the restarts that are due.

        Args:
            now: Current monotonic time, s.

        """
        events: list[SupervisorEvent] = []
        for child in self._children.values():
            if child.state in (ProcessState.STARTING, ProcessState.RUNNING):
                assert child.process is not None
                code = child.process.poll()
                if code is None:
                    continue
                child.last_exit_code = code
                child.process = None
                if child.restarts >= self._policy.max_restarts:
                    child.state = ProcessState.FAILED
                    events.append(
                        SupervisorEvent(
                            child.spec.name,
                            f"exited with code {code}; gave up after {child.restarts} restarts",
                        )
                    )
                    continue
                delay = self._policy.delay(child.restarts)
                child.state = ProcessState.BACKOFF
                child.restart_at = now + delay
                events.append(
                    SupervisorEvent(
                        child.spec.name, f"exited with code {code}; restarting in {delay:.1f} s"
                    )
                )
            elif child.state is ProcessState.BACKOFF and now >= child.restart_at:
                child.restarts += 1
                self._start(child)
                events.append(
                    SupervisorEvent(child.spec.name, f"restarted (restart {child.restarts})")
                )
        return events

    def mark_running(self, name: str) -> None:
        """Record that a process finished starting (e.g. its node appeared in the graph)."""
        child = self._children[name]
        if child.state is ProcessState.STARTING:
            child.state = ProcessState.RUNNING

    def snapshot(self) -> list[ProcessStatus]:
        """Status of every supervised process."""
        return [
            ProcessStatus(
                name=c.spec.name,
                node_name=c.spec.node_name,
                pid=c.process.pid if c.process is not None else 0,
                state=c.state,
                restarts=c.restarts,
                last_exit_code=c.last_exit_code,
            )
            for c in self._children.values()
        ]

    def _start(self, child: _Child) -> None:
        child.process = self._spawn(child.spec)
        child.state = ProcessState.STARTING

    def stop_all(self, timeout_s: float = 4.5, order: Sequence[str] = ()) -> dict[str, int]:
        """Stop every process: SIGINT, then SIGTERM, then SIGKILL, within ``timeout_s``.

        Args:
            timeout_s: Wall-clock budget for the whole shutdown.
            order: Names to stop last, in this order (e.g. the recorder, so it sees the end).

        Returns:
            Exit code of each process that was running.

        """
        last = [n for n in order if n in self._children]
        first = [n for n in self._children if n not in last]
        deadline = time.monotonic() + timeout_s
        codes: dict[str, int] = {}
        groups = [first, last] if last else [first]
        for index, group in enumerate(groups):
            share = (deadline - time.monotonic()) / (len(groups) - index)
            codes.update(self._stop_group(group, time.monotonic() + share))
        return codes

    def _stop_group(self, names: Sequence[str], deadline: float) -> dict[str, int]:
        running = {n: self._children[n] for n in names if self._children[n].process is not None}
        for child in self._children.values():
            if child.spec.name in names and child.process is None:
                child.state = ProcessState.STOPPED
        codes: dict[str, int] = {}
        term_at = time.monotonic() + 0.7 * max(0.0, deadline - time.monotonic())
        for sig in (signal.SIGINT, signal.SIGTERM):
            for child in running.values():
                assert child.process is not None
                if child.process.poll() is None:
                    child.process.send_signal(sig)
            limit = term_at if sig is signal.SIGINT else deadline
            codes.update(_wait_all(running, limit))
            running = {n: c for n, c in running.items() if n not in codes}
            if not running:
                break
        for name, child in running.items():
            assert child.process is not None
            child.process.kill()
            codes[name] = -signal.SIGKILL
        for name in names:
            child = self._children[name]
            child.process = None
            child.state = ProcessState.STOPPED
            if name in codes:
                child.last_exit_code = codes[name]
        return codes


def _wait_all(children: Mapping[str, _Child], deadline: float) -> dict[str, int]:
    """Poll until every child exited or the deadline passed; return the exit codes seen."""
    codes: dict[str, int] = {}
    while True:
        for name, child in children.items():
            if name not in codes and child.process is not None:
                code = child.process.poll()
                if code is not None:
                    codes[name] = code
        if len(codes) == len(children) or time.monotonic() >= deadline:
            return codes
        time.sleep(0.02)  # polling child exit status; no notification exists for several pids
