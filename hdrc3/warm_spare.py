"""Warm spare: a crashed node is restarted by an interpreter that has already done its imports.

A node started with ``Popen`` spends 3-4.5 s of wall time (2 loaded cores) importing rclpy,
numpy, the HCSM parser and its own code before it can say anything; the terminal event of the
command it was running (issue 21: within 2 s of the restart) waits for it. So the launcher keeps
one spare interpreter that has imported the entry-point modules of every node of the launch and
then waits, with no rclpy context, no DDS participant and no thread of its own. A restart hands
the node to the spare: the spare takes the node's environment (``ROS_DOMAIN_ID`` and the other
ROS variables are read by ``rclpy.init``, which has not run yet) and argv, and runs the console
script's entry point as the script does, ``sys.exit(main())`` at the top level. The spare *is*
the node from then on: the launcher supervises the process it started, and starts a new spare
a few seconds later (:data:`RESPAWN_DELAY_S`, so the restarted node has the CPU while it comes up).

Why not fork from a pre-imported server (this module's predecessor, ``hdrc3/zygote.py``): after
``import rclpy`` the process holds rmw_fastrtps's LTTng-UST listener threads, and a process with
threads is not safe to fork; in one fresh-clone test run of four, a forked control kernel started
but nothing it published ever arrived. A spare is an ordinary interpreter started with ``Popen``
(own session, SIGTERM when the launcher dies, the launcher's stdout and stderr), only earlier.
Why not one spare per node: each costs a whole import and its memory; one covers any node.
Two restarts closer together than a spare's import: the second starts a new interpreter.

Protocol, one JSON object per line over a Unix socket pair: the spare says
``{"ready": [modules], "threads": N}`` once its imports are done; the launcher asks
``{"entry": "module:function", "argv": [...], "env": {...}}``; the spare answers
``{"running": pid}`` and closes the socket. The spare ends when the socket closes before a
request, or when the launcher dies. Linux only (parent-death signal); elsewhere the launcher
always uses ``Popen``.
"""

from __future__ import annotations

import importlib
import json
import os
import selectors
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from types import TracebackType
from typing import Any

from hdrc3.supervisor import ProcessLike, ProcessSpec, die_with_parent, popen_spawn

REPLY_TIMEOUT_S = 5.0
"""How long the launcher waits for the spare to take a node before it gives the spare up."""
RESPAWN_DELAY_S = 5.0
"""After a handover, the next spare starts this much later (its imports would slow the node)."""
CLOSE_TIMEOUT_S = 3.0
SUPPORTED = sys.platform == "linux"


def _send(sock: socket.socket, message: Mapping[str, Any]) -> None:
    sock.sendall(json.dumps(message).encode() + b"\n")


class WarmSpare:
    """The launcher's side of the spare; a context manager (leaving it stops an unused spare)."""

    def __init__(
        self,
        modules: Sequence[str],
        report: Callable[[str], None] = print,
        respawn_delay_s: float = RESPAWN_DELAY_S,
    ) -> None:
        """Prepare a spare that imports ``modules`` (started by :meth:`start`)."""
        self.modules = tuple(dict.fromkeys(modules))
        self.respawn_delay_s = respawn_delay_s
        self._report = report
        self._process: subprocess.Popen[bytes] | None = None
        self._sock: socket.socket | None = None
        self._buffer = b""
        self._ready = False
        self._running: int | None = None
        self._started_at = 0.0
        self._respawn_at: float | None = None

    @property
    def alive(self) -> bool:
        """A spare runs and its socket is open."""
        return self._sock is not None

    @property
    def ready(self) -> bool:
        """The spare finished its imports and can take a node."""
        self.collect()
        return self._ready and self.alive

    def start(self) -> None:
        """Start a spare (its imports run in the background); a no-op while one runs."""
        if not SUPPORTED or self._process is not None or not self.modules:
            return
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        command = [sys.executable, "-m", "hdrc3.warm_spare", str(theirs.fileno()), *self.modules]
        self._process = subprocess.Popen(
            command, pass_fds=(theirs.fileno(),), start_new_session=True, preexec_fn=die_with_parent
        )
        theirs.close()
        ours.setblocking(False)
        self._sock, self._buffer, self._ready, self._running = ours, b"", False, None
        self._started_at = time.monotonic()
        self._respawn_at = None

    def spawn(self, spec: ProcessSpec) -> ProcessLike:
        """Hand ``spec`` to the spare when it is ready and knows the entry, else Popen it."""
        if spec.entry and spec.entry.partition(":")[0] in self.modules and self.ready:
            process = self._hand_over(spec)
            if process is not None:
                return process
        return popen_spawn(spec)

    def collect(self, timeout: float = 0.0) -> None:
        """Read what the spare said (waiting up to ``timeout``); start a due replacement."""
        if self._respawn_at is not None and time.monotonic() >= self._respawn_at:
            self.start()
        sock = self._sock
        if sock is None:
            return
        selector = selectors.DefaultSelector()
        selector.register(sock, selectors.EVENT_READ)
        try:
            ready = selector.select(timeout)
        finally:
            selector.close()
        if not ready:
            return
        try:
            chunk = sock.recv(1 << 16)
        except BlockingIOError:
            return
        except OSError:
            chunk = b""
        self._buffer += chunk
        *lines, self._buffer = self._buffer.split(b"\n")
        for line in lines:
            self._handle(json.loads(line))
        if not chunk and self._running is None:
            self._lost("exited")

    def _handle(self, message: Mapping[str, Any]) -> None:
        if "ready" in message:
            self._ready = True
            elapsed = time.monotonic() - self._started_at
            self._report(
                f"[launch] warm spare ready: {len(message['ready'])} node modules imported in "
                f"{elapsed:.1f} s ({message['threads']} thread(s)); a restart runs in it"
            )
        elif "running" in message:
            self._running = int(message["running"])

    def _hand_over(self, spec: ProcessSpec) -> ProcessLike | None:
        process = self._process
        assert self._sock is not None and process is not None
        env = dict(os.environ)
        env.update(spec.env)
        try:
            _send(self._sock, {"entry": spec.entry, "argv": list(spec.argv), "env": env})
        except OSError:
            self._lost("unreachable")
            return None
        deadline = time.monotonic() + REPLY_TIMEOUT_S
        while self._running is None and self.alive and time.monotonic() < deadline:
            self.collect(deadline - time.monotonic())
        if self._sock is None or self._running != process.pid:
            self._lost(f"did not take {spec.name} within {REPLY_TIMEOUT_S:g} s")
            return None
        self._sock.close()
        self._sock, self._process = None, None
        self._respawn_at = time.monotonic() + self.respawn_delay_s
        self._report(f"[launch] {spec.name}: runs in the warm spare (pid {process.pid})")
        return process

    def _lost(self, why: str) -> None:
        """The spare is gone or broken: stop it; a new one starts after the respawn delay."""
        if self._sock is None:
            return
        self._sock.close()
        self._sock = None
        self._report(f"[launch] warm spare {why}; restarts start new interpreters for now")
        self._stop_process()
        self._respawn_at = time.monotonic() + self.respawn_delay_s

    def _stop_process(self) -> None:
        """End the spare at once (SIGTERM; it may still be importing and not read the socket)."""
        process, self._process = self._process, None
        if process is None:
            return
        if process.poll() is None:
            process.terminate()
        try:
            process.wait(CLOSE_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()

    def close(self) -> None:
        """Stop the unused spare, if any; no replacement starts after this."""
        self._respawn_at = None
        if self._sock is not None:
            self._sock.close()
            self._sock = None
        self._stop_process()

    def __enter__(self) -> WarmSpare:
        """Return self (:meth:`start` is separate: the launch starts it with its nodes)."""
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        """Stop the unused spare."""
        self.close()


# --- the spare process -----------------------------------------------------------------------


def _import_all(modules: Sequence[str]) -> list[str]:
    """Import what can be imported; a module that fails is imported again by its node."""
    loaded: list[str] = []
    for name in modules:
        try:
            importlib.import_module(name)
        except Exception as exc:  # reported; the node's own start shows the full error
            print(f"hdrc3 warm spare: cannot pre-import {name}: {exc}", file=sys.stderr, flush=True)
        else:
            loaded.append(name)
    return loaded


def serve(sock: socket.socket, modules: Sequence[str]) -> Mapping[str, Any] | None:
    """Import, say so, and wait for a node to run.

    Returns:
        The request (entry, argv, env) once the launcher handed a node over, with the
        environment and argv already applied; None when the socket closed first.
    """
    loaded = _import_all(modules)
    _send(sock, {"ready": loaded, "threads": len(os.listdir("/proc/self/task"))})
    buffer = b""
    while b"\n" not in buffer:
        chunk = sock.recv(1 << 16)
        if not chunk:
            return None
        buffer += chunk
    request: dict[str, Any] = json.loads(buffer.partition(b"\n")[0])
    os.environ.clear()
    os.environ.update(request["env"])
    sys.argv = list(request["argv"])
    _send(sock, {"running": os.getpid()})
    sock.close()
    return request


def main() -> int:
    """``python -m hdrc3.warm_spare FD MODULE...``; once handed a node, runs its entry point."""
    sock = socket.socket(fileno=int(sys.argv[1]))
    try:
        request = serve(sock, sys.argv[2:])
    except (BrokenPipeError, ConnectionResetError):
        return 0  # the launcher closed the socket while a message was on its way
    if request is None:
        return 0
    module, _, function = str(request["entry"]).partition(":")
    entry: Callable[[], int | None] = getattr(importlib.import_module(module), function)
    return entry() or 0


if __name__ == "__main__":
    sys.exit(main())
