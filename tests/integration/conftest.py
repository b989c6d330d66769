"""Fixtures for multi-process tests: hdrc3 commands as child processes, always cleaned up."""

from __future__ import annotations

import os
import selectors
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path

import pytest

from hdrc3.launched_system import STOP_TIMEOUT_S

HDRC3 = str(Path(sys.executable).parent / "hdrc3")


class Child:
    """A running `hdrc3 ...` process whose output is read with bounded waits."""

    def __init__(
        self,
        args: list[str],
        prefix: Sequence[str] = (),
        env: Mapping[str, str] | None = None,
        program: str = HDRC3,
    ) -> None:
        """Start ``[*prefix, program, *args]`` (``prefix``: e.g. ``ip netns exec NS``)."""
        self.args = args
        self.proc = subprocess.Popen(
            [*prefix, program, *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            start_new_session=True,
            env=dict(os.environ, PYTHONUNBUFFERED="1", **(env or {})),
        )
        self.lines: list[str] = []
        self._selector = selectors.DefaultSelector()
        assert self.proc.stdout is not None
        os.set_blocking(self.proc.stdout.fileno(), False)
        self._selector.register(self.proc.stdout, selectors.EVENT_READ)
        self._buffer = b""

    def _read_available(self, timeout: float) -> bool:
        assert self.proc.stdout is not None
        if not self._selector.select(timeout):
            return True
        chunk = self.proc.stdout.read()
        if not chunk:
            return False
        self._buffer += chunk
        *complete, self._buffer = self._buffer.split(b"\n")
        self.lines += [line.decode(errors="replace") for line in complete]
        return True

    def poll_output(self, timeout: float) -> None:
        """Collect whatever output arrives within ``timeout`` seconds."""
        self._read_available(timeout)

    def wait_for_line(self, needle: str, timeout: float = 60.0) -> str:
        """Return the first output line containing ``needle``; fail after ``timeout``."""
        deadline = time.monotonic() + timeout
        seen = 0
        while True:
            for line in self.lines[seen:]:
                if needle in line:
                    return line
            seen = len(self.lines)
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"{needle!r} not printed in {timeout} s: {self.lines}")
            if not self._read_available(min(remaining, 0.5)) and self.proc.poll() is not None:
                raise AssertionError(
                    f"exited {self.proc.returncode} before {needle!r}: {self.lines}"
                )

    def interrupt(self, timeout: float = STOP_TIMEOUT_S) -> int:
        """Send SIGINT and wait for the exit code, collecting remaining output.

        The default is the wait `hdrc3 demo` and `tst run` give their launch: a launch of 20
        processes on a loaded machine took more than 30 s to stop.
        """
        self.proc.send_signal(signal.SIGINT)
        return self.finish(timeout)

    def finish(self, timeout: float = 60.0) -> int:
        """Wait for the process to exit on its own and collect all output."""
        deadline = time.monotonic() + timeout
        while self.proc.poll() is None or self._read_available(0):
            if time.monotonic() > deadline:
                raise AssertionError(f"{self.args} did not exit within {timeout} s: {self.lines}")
            if not self._read_available(0.1) and self.proc.poll() is not None:
                break
        if self._buffer:
            self.lines.append(self._buffer.decode(errors="replace"))
            self._buffer = b""
        return self.proc.returncode

    def kill(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(timeout=10)


@pytest.fixture
def hdrc3_cli(ros_domain: int) -> Iterator[Callable[..., Child]]:
    """Start `hdrc3 ...` commands on the test's domain; kill leftovers at teardown."""
    children: list[Child] = []

    def start(*args: str) -> Child:
        child = Child(list(args))
        children.append(child)
        return child

    yield start
    for child in children:
        child.kill()
