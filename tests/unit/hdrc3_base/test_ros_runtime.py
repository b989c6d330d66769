"""RosProcess: SIGINT/SIGTERM become a stop request, whatever the main thread was doing."""

from __future__ import annotations

import contextlib
import signal

import pytest
from rclpy.node import Node

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


@pytest.mark.parametrize("events", [False, True])
def test_either_executor_delivers_raw_messages_in_order(ros_domain: int, events: bool) -> None:
    # the recorder spins on the events executor and takes every message as CDR bytes
    from rclpy.serialization import deserialize_message
    from std_msgs.msg import UInt32

    with RosProcess(domain_id=ros_domain, handle_signals=False, events=events) as process:
        node = process.add_node(Node("raw_probe", context=process.context))
        got: list[bytes] = []
        node.create_subscription(UInt32, "/raw_probe", got.append, 100, raw=True)
        pub = node.create_publisher(UInt32, "/raw_probe", 100)
        assert process.spin_until(lambda: pub.get_subscription_count() > 0, 10.0)
        for i in range(50):
            pub.publish(UInt32(data=i))
        assert process.spin_until(lambda: len(got) == 50, 10.0), len(got)
        assert all(isinstance(data, bytes) for data in got)
        assert [deserialize_message(d, UInt32).data for d in got] == list(range(50))
        node.destroy_node()


@pytest.mark.parametrize(
    ("server_after_attempts", "answered"),
    [
        (0, True),  # the first attempt is answered
        (1, True),  # the first request is lost, as a dropped answer is; the next is answered
        (None, False),  # no server at all: the bound ends it, without an exception
    ],
)
def test_first_answer_sends_again_until_one_is_answered(
    ros_domain: int, server_after_attempts: int | None, answered: bool
) -> None:
    from std_srvs.srv import Trigger

    from hdrc3_base.ros_runtime import SERVICE_QOS

    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        node = process.add_node(Node("first_answer_probe", context=process.context))
        served: list[int] = []

        def serve(request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
            served.append(1)
            response.success = True
            return response

        client = node.create_client(Trigger, "/first_answer", qos_profile=SERVICE_QOS)
        sent: list[int] = []
        original_call = client.call_async

        def call_async(request: Trigger.Request):  # type: ignore[no-untyped-def]
            if server_after_attempts is not None and len(sent) == server_after_attempts:
                node.create_service(Trigger, "/first_answer", serve, qos_profile=SERVICE_QOS)
                process.spin_until(client.service_is_ready, 10.0)
            sent.append(1)
            return original_call(request)

        client.call_async = call_async  # type: ignore[method-assign]
        response = process.first_answer(client, Trigger.Request(), timeout_s=6.0, attempt_s=1.0)
        assert (response is not None and response.success) is answered
        if server_after_attempts is None:
            assert not served
            assert len(sent) >= 2  # sent again after the first unanswered attempt
        else:
            assert len(served) >= 1
            assert len(sent) >= server_after_attempts + 1
        node.destroy_node()
