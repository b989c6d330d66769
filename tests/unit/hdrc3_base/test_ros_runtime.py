"""RosProcess: SIGINT/SIGTERM become a stop request, whatever the main thread was doing."""

from __future__ import annotations

import contextlib
import signal

import pytest

from hdrc3_base.ros_runtime import RosProcess

pytestmark = pytest.mark.ros


@pytest.mark.parametrize(
    ("signals", "inside_the_event_lock"),
    [
        ((signal.SIGINT,), False),
        ((signal.SIGTERM,), False),
        # a launcher's SIGINT, then the parent-death SIGTERM, while the main thread is inside
        # Event.wait/set: a handler that set the event itself deadlocked here for good
        ((signal.SIGINT, signal.SIGTERM), True),
    ],
)
def test_a_signal_is_a_stop_request(
    ros_domain: int, signals: tuple[signal.Signals, ...], inside_the_event_lock: bool
) -> None:
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    with RosProcess(domain_id=ros_domain) as process:
        held: contextlib.AbstractContextManager[object] = contextlib.nullcontext()
        if inside_the_event_lock:
            held = process.stop_requested._cond  # type: ignore[attr-defined]  # CPython's Event
        with held:
            for sig in signals:
                signal.raise_signal(sig)  # the handler runs before the next statement
        assert process.stop_requested.wait(10.0)
    assert {sig: signal.getsignal(sig) for sig in before} == before
