"""Bounded waits on an rclpy executor for the multi-process tests (no sleeps)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from rclpy.executors import SingleThreadedExecutor

from hdrc3_base.answer_memory import ensure_key
from hdrc3_base.ros_runtime import first_answer


def spin_until(executor: SingleThreadedExecutor, done: Callable[[], bool], timeout: float) -> bool:
    """Spin until ``done()`` or ``timeout`` wall seconds; whether it is done."""
    deadline = time.monotonic() + timeout
    while not done():
        if time.monotonic() > deadline:
            return False
        executor.spin_once(timeout_sec=0.05)
    return True


def answer(executor: SingleThreadedExecutor, client: Any, request: Any, timeout: float) -> Any:
    """The first answer to a repeatable request (a query or a keyed command), or None.

    Sent again every two seconds: DDS can drop the first answers to a new client
    (``hdrc3_base.ros_runtime.first_answer``). A command gets a fresh ``request_key`` first.
    """
    ensure_key(request)
    return first_answer(
        client, request, timeout, lambda done, wait: spin_until(executor, done, wait)
    )
