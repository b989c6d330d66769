"""Running an rclpy node as a process: private context, signal handling, bounded spinning.

Every hdrc3 entry point (launcher, recorder, replayer, nodes) uses :class:`RosProcess`, which
keeps DDS on loopback by default, owns its own :class:`rclpy.context.Context` and turns SIGINT /
SIGTERM into a stop request that the main loop honours (rclpy's own handler would tear the
context down under the loop's feet).

The signal handler only writes a byte to a pipe; a thread of the process reads it and sets
:attr:`RosProcess.stop_requested`. Setting the :class:`threading.Event` in the handler takes the
event's lock, which the interrupted main thread may hold (inside ``Event.wait``/``set``, or a
first handler when a second signal arrives: a launcher's SIGINT and the parent-death SIGTERM):
the process then deadlocked and outlived its launcher (seen: a platform server stuck for good).
"""

from __future__ import annotations

import contextlib
import cProfile
import math
import os
import signal
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from types import FrameType, TracebackType
from typing import Any

import rclpy
from rclpy.client import Client
from rclpy.context import Context
from rclpy.executors import Executor, SingleThreadedExecutor
from rclpy.experimental.events_executor import EventsExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions

from hdrc3_base.errors import ConfigError, Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults

SERVICE_WAIT_S = 10.0
"""How long a new client looks for a service before calling it absent (one value for the CLI,
the safety pilot and the mission client: in a fresh clone's test run the platform server's
``ppcl/turn_to`` stayed unseen for the 5 s the CLI then waited, with the server running)."""

SERVICE_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=1000,
    durability=DurabilityPolicy.VOLATILE,
)
"""QoS of every hdrc3 service and of its clients: a burst of requests is queued, not dropped.

rclpy's default (``qos_profile_services_default``) keeps the last 10 requests in the server's
request reader and the last 10 answers in a client's response reader: of 50 requests sent at once,
those that arrive while the executor is busy overwrite each other (issue 21: 18-29 of 50 were
never answered). 1,000 covers the bursts ``bench/service_burst.py`` measures.
"""

STATUS_TOPIC = "/hdrc3/launch_status"
"""The launcher's snapshot of the processes it supervises (``LaunchStatus``): the system monitor
turns it into diagnostics, each Platform Server watches its own kernels on it."""
STATUS_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
"""Latched: a late subscriber gets the latest snapshot."""


class RosProcess:
    """Context manager owning an rclpy context, an executor and a stop event."""

    def __init__(
        self,
        args: Sequence[str] | None = None,
        domain_id: int | None = None,
        handle_signals: bool = True,
        events: bool = False,
    ) -> None:
        """Prepare the process; ``args`` are ROS arguments such as ``--ros-args -r __ns:=/a``.

        ``events`` selects rclpy's C++ ``EventsExecutor`` instead of the ``SingleThreadedExecutor``:
        a callback costs tens of microseconds instead of a wait-set rebuild over every entity of
        the node (hundreds of microseconds to milliseconds for a node with many subscriptions;
        see :func:`run_events_node`).
        """
        self._args = list(args) if args is not None else None
        self._domain_id = domain_id
        self._handle_signals = handle_signals
        self._events = events
        self.context = Context()
        self.executor: Executor | None = None
        self.stop_requested = threading.Event()
        self._previous: dict[int, object] = {}
        self._signal_pipe: tuple[int, int] | None = None
        self._signal_thread: threading.Thread | None = None

    def __enter__(self) -> RosProcess:
        apply_dds_defaults()
        rclpy.init(
            args=self._args,
            context=self.context,
            domain_id=self._domain_id,
            signal_handler_options=SignalHandlerOptions.NO,
        )
        self.executor = (
            EventsExecutor(context=self.context)
            if self._events
            else SingleThreadedExecutor(context=self.context)
        )
        if self._handle_signals and threading.current_thread() is threading.main_thread():
            self._signal_pipe = os.pipe()
            os.set_blocking(self._signal_pipe[1], False)
            self._signal_thread = threading.Thread(
                target=self._relay_signals, args=(self._signal_pipe[0],), daemon=True
            )
            self._signal_thread.start()
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._on_signal)
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)  # type: ignore[arg-type]
        self._previous = {}
        if self._signal_pipe is not None:
            os.close(self._signal_pipe[1])  # the relay thread reads end-of-file and returns
            if self._signal_thread is not None:
                self._signal_thread.join()
            os.close(self._signal_pipe[0])
            self._signal_pipe = self._signal_thread = None
        if self.executor is not None:
            self.executor.shutdown(timeout_sec=1.0)
        self.context.try_shutdown()

    def _on_signal(self, signum: int, frame: FrameType | None) -> None:
        """Async-signal-safe: no lock is taken here (see the module docstring)."""
        assert self._signal_pipe is not None  # installed together
        with contextlib.suppress(BlockingIOError):  # full of earlier signals: the stop is coming
            os.write(self._signal_pipe[1], b"\0")

    def _relay_signals(self, read_fd: int) -> None:
        while os.read(read_fd, 64):
            self.stop_requested.set()

    def add_node(self, node: Node) -> Node:
        """Let the executor spin ``node``."""
        assert self.executor is not None, "use RosProcess as a context manager"
        self.executor.add_node(node)
        return node

    def spin_once(self, timeout_s: float = 0.1) -> None:
        """Handle at most one ready callback, waiting up to ``timeout_s``."""
        assert self.executor is not None, "use RosProcess as a context manager"
        self.executor.spin_once(timeout_sec=timeout_s)

    def spin_until(
        self,
        done: Callable[[], bool],
        timeout_s: float,
        step_s: float = 0.05,
        tick: Callable[[], None] | None = None,
    ) -> bool:
        """Spin until ``done()`` is true, a stop is requested, or the wall-clock timeout passes.

        Args:
            done: Completion predicate, checked before every spin.
            timeout_s: Wall-clock bound.
            step_s: Longest wait for a callback per spin.
            tick: Called after every spin (e.g. to supervise child processes).

        Returns:
            Whether ``done()`` became true.

        """
        deadline = time.monotonic() + timeout_s
        while not done():
            if self.stop_requested.is_set() or time.monotonic() >= deadline:
                return False
            self.spin_once(step_s)
            if tick is not None:
                tick()
        return True

    def first_answer(
        self, client: Client, request: Any, timeout_s: float, attempt_s: float = 2.0
    ) -> Any | None:
        """:func:`first_answer` spinning this process's executor."""
        return first_answer(
            client, request, timeout_s, self.spin_until, attempt_s, self.stop_requested.is_set
        )

    def spin_until_stopped(
        self, step_s: float = 0.1, tick: Callable[[], None] | None = None
    ) -> None:
        """Spin until SIGINT/SIGTERM (or :attr:`stop_requested` set), calling ``tick`` each pass."""
        self.spin_until(lambda: not self.context.ok(), math.inf, step_s, tick)


def first_answer(
    client: Client,
    request: Any,
    timeout_s: float,
    spin_until: Callable[[Callable[[], bool], float], bool],
    attempt_s: float = 2.0,
    stopped: Callable[[], bool] = lambda: False,
) -> Any | None:
    """Call ``client`` until one answer arrives: proof that both directions of it are matched.

    ``service_is_ready()`` only says that the server's request reader matched this client's
    request writer. The answer travels on a second pair, the server's response writer and this
    client's response reader, which DDS discovers separately. Fast DDS (rmw_fastrtps,
    ``__rmw_send_response``) waits at most 100 ms for that pair and otherwise drops the answer
    with "client will not receive response" (rclpy only warns). On a loaded machine the first
    answers to a new client were lost that way (issue 21: 148 of 150 in CI).

    Only for requests that may be repeated: queries, and commands with a ``request_key`` (the
    server answers a known key with its first answer); an unanswered attempt may have been served.

    Args:
        client: A client whose service :meth:`Client.service_is_ready` reports.
        request: The request to send on each attempt.
        timeout_s: Wall-clock bound for all attempts.
        spin_until: Spins the client's executor until ``done()`` or ``timeout`` seconds; whether
            it is done (:meth:`RosProcess.spin_until`).
        attempt_s: How long one attempt waits before the request is sent again.
        stopped: Whether to give up at once (e.g. after SIGINT).

    Returns:
        The first response, or None when no attempt was answered in time.

    """
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        future = client.call_async(request)
        if spin_until(future.done, min(attempt_s, deadline - time.monotonic())):
            return future.result()
        client.remove_pending_request(future)
        if stopped():
            break
    return None


def node_name_counts(node: Node) -> Counter[str]:
    """How many nodes of each fully qualified name the graph shows (2+ means a name clash)."""
    return Counter(
        f"{namespace.rstrip('/')}/{name}"
        for name, namespace in node.get_node_names_and_namespaces()
    )


def node_names(node: Node) -> set[str]:
    """Fully qualified names of the nodes currently visible in the graph."""
    return set(node_name_counts(node))


class SteppedNode(Node):
    """A node that drives its own loop (lockstep ticks) with the executor it is given."""

    def run(self, executor: Executor, stop: threading.Event) -> None:
        """Serve callbacks and step until ``stop`` is set (the one hook subclasses provide)."""
        raise NotImplementedError


PROFILE_DIR_VARIABLE = "HDRC3_PROFILE_DIR"
"""Set to a directory: each stepped node profiles its loop there (``<label>-<pid>.prof``)."""


@contextlib.contextmanager
def _profiled(label: str) -> Iterator[None]:
    """Profile the block (cProfile) on the thread's CPU clock when ``HDRC3_PROFILE_DIR`` is set.

    The thread CPU clock leaves out the time spent waiting for the other side of the lockstep;
    profiling slows a node down several times, so it is for where the time goes, not how much.
    """
    directory = os.environ.get(PROFILE_DIR_VARIABLE)
    if not directory:
        yield
        return
    profile = cProfile.Profile(time.thread_time)
    profile.enable()
    try:
        yield
    finally:
        profile.disable()
        profile.dump_stats(str(Path(directory) / f"{label}-{os.getpid()}.prof"))


def run_stepped_node(
    factory: Callable[[Context], SteppedNode], label: str, args: Sequence[str]
) -> int:
    """Entry-point body of a lockstepped node on the light events executor.

    Returns:
        0 after SIGINT/SIGTERM, 2 (with one line on stderr) when the node rejects its
        parameters.
    """
    try:
        with RosProcess(args=args) as process:
            node = factory(process.context)
            executor = EventsExecutor(context=process.context)
            executor.add_node(node)
            try:
                with _profiled(label):
                    node.run(executor, process.stop_requested)
            finally:
                executor.shutdown()
                node.destroy_node()
    except Hdrc3Error as exc:
        print(f"{label}: error: {exc}", file=sys.stderr, flush=True)
        return 2
    return 0


def run_events_node(factory: Callable[[Context], Node], label: str) -> int:
    """Entry-point body of a node on the light events executor (fast state streams).

    Returns:
        0 after SIGINT/SIGTERM, 2 (with ``label: reason`` on stderr) on bad parameters.
    """
    try:
        with RosProcess(args=sys.argv) as process:
            node = factory(process.context)
            executor = EventsExecutor(context=process.context)
            executor.add_node(node)
            try:
                while not process.stop_requested.is_set() and process.context.ok():
                    executor.spin_once(timeout_sec=0.1)
            finally:
                executor.shutdown()
                node.destroy_node()
    except ConfigError as exc:
        print(f"{label}: {exc}", file=sys.stderr)
        return 2
    return 0


def run_node(factory: Callable[[Context], Node], args: Sequence[str] | None = None) -> int:
    """Entry-point body of a node process: create it, spin until a signal, clean up."""
    with RosProcess(args=args) as process:
        node = process.add_node(factory(process.context))
        try:
            process.spin_until_stopped()
        finally:
            node.destroy_node()
    return 0
