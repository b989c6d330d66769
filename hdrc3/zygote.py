"""Fork server ("zygote"): a crashed node is restarted in a fraction of a second.

A node started with ``Popen`` spends 3-4.5 s of wall time (2 loaded cores) importing rclpy,
numpy, the HCSM parser and its own code before it can say anything; the terminal event of the
command it was running (issue 21: within 2 s of the restart) waits for it. So the launcher keeps
one helper process that has imported the entry-point modules of every node of the launch, has
not initialised rclpy (no context, no DDS participant) and runs no thread of its own. A restart
asks it to ``fork``; the child takes the node's argv and environment (``ROS_DOMAIN_ID`` and the
other ROS variables are read by ``rclpy.init``, which has not run yet), starts its own session,
asks Linux to SIGTERM it when its parent dies (as :func:`~hdrc3.supervisor.popen_spawn` does), and
runs the console script's entry point as the script does: ``sys.exit(main())`` at the top level,
so atexit handlers and non-daemon threads end as in a fresh process. Its output goes where the
launcher's goes, like any supervised process.

Why not ``multiprocessing``'s forkserver: it runs a pickled callable under its own bootstrap
(stdin replaced, the parent's ``__main__`` re-run, ``os._exit`` at the end) with no per-child
argv, environment or session, and a node must run exactly as its console script does. Why not a
warm standby interpreter per node: one idle process per node of every agent, each paying the
whole import and memory, where one forking process shares the imported pages copy-on-write.

Protocol, one JSON object per line over a Unix socket pair: the zygote says
``{"ready": [modules], "threads": N}`` once its imports are done; the launcher asks
``{"entry": "module:function", "argv": [...], "env": {...}}`` and gets ``{"pid": N}`` (or
``{"error": "..."}``), later ``{"exit": N, "code": C}`` when that child ends (C negative for a
signal, as subprocess reports it). Until the zygote is ready, or once it died, the launcher
starts processes with ``Popen`` as before. The zygote ends when the socket closes or its parent
dies; the children it forked then get SIGTERM, as supervised processes of a dead launcher do.
Linux only (``pidfd_open``, ``prctl``); elsewhere the launcher always uses ``Popen``.
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib
import json
import os
import selectors
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from types import TracebackType
from typing import Any

from hdrc3.supervisor import ProcessLike, ProcessSpec, die_with_parent, popen_spawn

REPLY_TIMEOUT_S = 5.0
"""How long the launcher waits for the pid of a fork before it gives the zygote up."""
CLOSE_TIMEOUT_S = 3.0
SUPPORTED = sys.platform == "linux" and hasattr(os, "pidfd_open")


def _send(sock: socket.socket, message: Mapping[str, Any]) -> None:
    sock.sendall(json.dumps(message).encode() + b"\n")


class ForkedProcess:
    """A node forked by the zygote (satisfies :class:`~hdrc3.supervisor.ProcessLike`).

    Signals go through a pidfd, so a pid reused after the child was reaped is never hit.
    """

    def __init__(self, server: ForkServer, pid: int) -> None:
        """Track child ``pid`` of ``server``'s zygote."""
        self.pid = pid
        self._server = server
        try:
            self._pidfd = os.pidfd_open(pid)
        except ProcessLookupError:  # ended and reaped already: the zygote reports its code
            self._pidfd = -1

    def poll(self) -> int | None:
        """Exit code reported by the zygote; -SIGTERM if the zygote died before reporting."""
        code = self._server.exit_code(self.pid)
        if code is None and not self._server.alive and self._exited():
            code = -signal.SIGTERM  # the zygote's death sends it SIGTERM (PR_SET_PDEATHSIG)
        if code is not None and self._pidfd >= 0:
            os.close(self._pidfd)
            self._pidfd = -1
        return code

    def _exited(self) -> bool:
        if self._pidfd < 0:
            return True
        selector = selectors.DefaultSelector()
        try:
            selector.register(self._pidfd, selectors.EVENT_READ)
            return bool(selector.select(0))
        finally:
            selector.close()

    def send_signal(self, sig: int) -> None:
        """Deliver ``sig`` unless the process has ended."""
        if self.poll() is None and self._pidfd >= 0:
            # ProcessLookupError: exited since the poll; its exit code comes from the zygote
            with contextlib.suppress(ProcessLookupError):
                signal.pidfd_send_signal(self._pidfd, sig)

    def kill(self) -> None:
        """SIGKILL."""
        self.send_signal(signal.SIGKILL)


class ForkServer:
    """The launcher's side of the zygote; a context manager (leaving it stops the zygote)."""

    def __init__(self, modules: Sequence[str], report: Callable[[str], None] = print) -> None:
        """Prepare a zygote that imports ``modules`` (started by :meth:`start`)."""
        self.modules = tuple(dict.fromkeys(modules))
        self._report = report
        self._process: subprocess.Popen[bytes] | None = None
        self._sock: socket.socket | None = None
        self._buffer = b""
        self._ready = False
        self._started_at = 0.0
        self._pids: list[int] = []
        self._exits: dict[int, int] = {}

    @property
    def alive(self) -> bool:
        """The zygote runs and its socket is open."""
        return self._sock is not None

    @property
    def ready(self) -> bool:
        """The zygote finished its imports and takes fork requests."""
        self.collect()
        return self._ready and self.alive

    def start(self) -> None:
        """Start the zygote process (its imports run in the background)."""
        if not SUPPORTED or self._process is not None or not self.modules:
            return
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_STREAM)
        command = [sys.executable, "-m", "hdrc3.zygote", str(theirs.fileno()), *self.modules]
        self._process = subprocess.Popen(
            command, pass_fds=(theirs.fileno(),), start_new_session=True, preexec_fn=die_with_parent
        )
        theirs.close()
        ours.setblocking(False)
        self._sock = ours
        self._started_at = time.monotonic()

    def spawn(self, spec: ProcessSpec) -> ProcessLike:
        """Fork ``spec`` from the zygote when it is ready and knows the entry, else Popen it."""
        if spec.entry and spec.entry.partition(":")[0] in self.modules and self.ready:
            forked = self._fork(spec)
            if forked is not None:
                return forked
        return popen_spawn(spec)

    def exit_code(self, pid: int) -> int | None:
        """Exit code of a forked child once the zygote reported it."""
        self.collect()
        return self._exits.get(pid)

    def collect(self, timeout: float = 0.0) -> None:
        """Read what the zygote said (waiting up to ``timeout`` for something)."""
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
        if not chunk:
            self._lost("exited")
            return
        self._buffer += chunk
        *lines, self._buffer = self._buffer.split(b"\n")
        for line in lines:
            self._handle(json.loads(line))

    def _handle(self, message: Mapping[str, Any]) -> None:
        if "ready" in message:
            self._ready = True
            elapsed = time.monotonic() - self._started_at
            self._report(
                f"[launch] fork server ready: {len(message['ready'])} node modules imported in "
                f"{elapsed:.1f} s ({message['threads']} thread(s)); restarts fork from it"
            )
        elif "pid" in message:
            self._pids.append(int(message["pid"]))
        elif "exit" in message:
            self._exits[int(message["exit"])] = int(message["code"])
        elif "error" in message:
            self._report(f"[launch] fork server: {message['error']}")
            self._pids.append(0)

    def _fork(self, spec: ProcessSpec) -> ForkedProcess | None:
        assert self._sock is not None
        env = dict(os.environ)
        env.update(spec.env)
        request = {"entry": spec.entry, "argv": list(spec.argv), "env": env}
        try:
            _send(self._sock, request)
        except OSError:
            self._lost("unreachable")
            return None
        deadline = time.monotonic() + REPLY_TIMEOUT_S
        while not self._pids and self.alive and time.monotonic() < deadline:
            self.collect(deadline - time.monotonic())
        if not self._pids:
            self._lost(f"no answer within {REPLY_TIMEOUT_S:g} s")
            return None
        pid = self._pids.pop(0)
        return ForkedProcess(self, pid) if pid else None

    def _lost(self, why: str) -> None:
        """The zygote is gone or broken: stop using it (Popen from now on)."""
        if self._sock is None:
            return
        self._sock.close()
        self._sock = None
        self._report(f"[launch] fork server {why}; restarts start new interpreters")
        self._stop_process()

    def _stop_process(self) -> None:
        """End the zygote at once (SIGTERM; it may still be importing and not read the socket)."""
        process = self._process
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
        """Stop the zygote (its children, if any, get SIGTERM from their parent's death)."""
        if self._sock is not None:
            self._sock.close()
            self._sock = None
        self._stop_process()

    def __enter__(self) -> ForkServer:
        """Return self (:meth:`start` is separate: the launch starts it with its nodes)."""
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        """Stop the zygote."""
        self.close()


# --- the zygote process ----------------------------------------------------------------------


def _import_all(modules: Sequence[str]) -> list[str]:
    """Import what can be imported; a module that fails is imported again by its child."""
    loaded: list[str] = []
    for name in modules:
        try:
            importlib.import_module(name)
        except Exception as exc:  # reported; the node's own start shows the full error
            print(f"hdrc3 zygote: cannot pre-import {name}: {exc}", file=sys.stderr, flush=True)
        else:
            loaded.append(name)
    return loaded


def _lttng_ust() -> ctypes.CDLL | None:
    """The LTTng-UST library loaded with rmw_fastrtps, if any (see :func:`_fork`)."""
    with open("/proc/self/maps", encoding="utf-8") as maps:
        paths = {line.split()[-1] for line in maps if "liblttng-ust-" in line}
    for path in sorted(paths):
        name = os.path.basename(path)
        if name.startswith("liblttng-ust-") and "tracepoint" not in name:
            library = ctypes.CDLL(path)  # already loaded: the same handle
            if hasattr(library, "ust_before_fork"):
                return library
    return None


def _fork(ust: ctypes.CDLL | None) -> int:
    """``os.fork`` wrapped in LTTng-UST's fork hooks when the library is loaded.

    Importing rclpy loads rmw_fastrtps, whose LTTng-UST starts two session-daemon listener
    threads. A child forked without the hooks would have none but believe it has them; with the
    hooks (what ``liblttng-ust-fork`` does for other programs) it starts its own, as a fresh
    process does. numpy's OpenBLAS threads handle fork themselves (``pthread_atfork``).
    """
    if ust is None:
        return os.fork()
    signals = ctypes.create_string_buffer(128)  # sigset_t
    ust.ust_before_fork(signals)
    try:
        pid = os.fork()
    except OSError:
        ust.ust_after_fork_parent(signals)
        raise
    if pid == 0:
        ust.ust_after_fork_child(signals)
    else:
        ust.ust_after_fork_parent(signals)
    return pid


def _become_child(request: Mapping[str, Any], zygote: int) -> None:
    """In the forked child: the node's session, parent-death signal, environment and argv."""
    os.setsid()
    die_with_parent()
    if os.getppid() != zygote:  # the zygote died before the parent-death signal was armed
        os.kill(os.getpid(), signal.SIGTERM)
    os.environ.clear()
    os.environ.update(request["env"])
    sys.argv = list(request["argv"])


def serve(sock: socket.socket, modules: Sequence[str]) -> Mapping[str, Any] | None:
    """Run the zygote: import, then fork on request and report exits.

    Returns:
        In a forked child, the request it is to run; in the zygote, None once the socket closed.
    """
    loaded = _import_all(modules)
    ust = _lttng_ust()
    zygote = os.getpid()
    _send(sock, {"ready": loaded, "threads": len(os.listdir("/proc/self/task"))})
    selector = selectors.DefaultSelector()
    selector.register(sock, selectors.EVENT_READ, 0)
    buffer = b""
    while True:
        for key, _ in selector.select():
            pid = int(key.data)
            if pid:  # a child's pidfd: it ended
                selector.unregister(key.fileobj)
                os.close(int(key.fd))
                _, status = os.waitpid(pid, 0)
                _send(sock, {"exit": pid, "code": os.waitstatus_to_exitcode(status)})
                continue
            chunk = sock.recv(1 << 16)
            if not chunk:
                return None
            buffer += chunk
            *lines, buffer = buffer.split(b"\n")
            for line in lines:
                request = json.loads(line)
                sys.stdout.flush()
                sys.stderr.flush()
                try:
                    child = _fork(ust)
                except OSError as exc:
                    _send(sock, {"error": f"fork failed: {exc.strerror}"})
                    continue
                if child == 0:
                    for registered in list(selector.get_map().values()):
                        if registered.data:
                            os.close(int(registered.fd))
                    selector.close()
                    sock.close()
                    _become_child(request, zygote)
                    return dict(request)
                selector.register(os.pidfd_open(child), selectors.EVENT_READ, child)
                _send(sock, {"pid": child})


def main() -> int:
    """``python -m hdrc3.zygote FD MODULE...``; a forked child runs its node's entry point."""
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
