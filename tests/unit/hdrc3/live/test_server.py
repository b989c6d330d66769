from __future__ import annotations

import socket
import time

import pytest

from hdrc3.live.channels import CHANNELS, STATIC_CHANNEL_NAMES, registered
from hdrc3.live.probe import FoxgloveProbe
from hdrc3.live.server import LiveServer, PortInUseError
from hdrc3.live.view import Emission
from hdrc3_base.errors import ConfigError


def test_port_in_use_is_a_clear_error():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        with pytest.raises(PortInUseError, match=f"port {port} on 127.0.0.1 is in use"):
            LiveServer(port=port)


@pytest.mark.parametrize("port", [-1, 70000])
def test_port_out_of_range(port):
    with pytest.raises(ConfigError, match="invalid port"):
        LiveServer(port=port)


def test_binds_a_free_port_on_loopback():
    server = LiveServer(port=0)
    try:
        assert server.port > 0
        assert server.resubscribed() == set()
    finally:
        server.close()


def test_per_agent_channels_are_advertised_and_report_their_subscribers():
    server = LiveServer(port=0)
    try:
        color = registered("/live/camera/color")
        assert color is None  # only instances are channels
        (entry,) = [c for c in CHANNELS if c.topic == "/live/camera/color"]
        topic = server.advertise(entry, "uav0")
        assert topic == "/live/camera/color/uav0" and not server.has_subscribers(topic)
        with FoxgloveProbe(f"ws://127.0.0.1:{server.port}") as client:
            assert client.wait_for_channels({topic, *STATIC_CHANNEL_NAMES}, timeout_s=10)
            assert "/live/camera/color" not in client.channels
            client.subscribe([topic])
            frame = None
            deadline = time.monotonic() + 10
            while frame is None and time.monotonic() < deadline:  # until the subscription holds
                server.send([Emission(topic, b"jpeg")], 1)
                frame = client.receive(timeout_s=0.05)
            assert frame is not None and frame.data == b"jpeg"
            assert server.has_subscribers(topic)
            # a per-agent channel first seen in an emission is advertised with it
            server.send([Emission("/live/camera/thermal/uav3", b"x")], 2)
            assert client.wait_for_channels({"/live/camera/thermal/uav3"}, timeout_s=10)
        server.send([Emission("/live/not_registered", b"x")], 3)  # dropped, no error
    finally:
        server.close()
