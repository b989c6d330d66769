from __future__ import annotations

import socket

import pytest

from hdrc3.live.server import LiveServer, PortInUseError
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
