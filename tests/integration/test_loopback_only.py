"""While an hdrc3 system runs, no DDS packet leaves the loopback interface."""

from __future__ import annotations

import os
import socket
import struct
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.ros
ETH_P_ALL = 0x0003
OBSERVE_S = 3.0


def _external_interfaces() -> list[str]:
    names = []
    for path in Path("/sys/class/net").iterdir():
        flags = int((path / "flags").read_text(), 16)
        if path.name != "lo" and flags & 0x1:  # IFF_UP
            names.append(path.name)
    return names


def _dds_udp_port(frame: bytes, low: int, high: int) -> int | None:
    """Return the DDS port of an IPv4/UDP Ethernet frame touching [low, high], else None."""
    if len(frame) < 42 or frame[12:14] != b"\x08\x00" or frame[23] != 17:
        return None
    header_len = (frame[14] & 0x0F) * 4
    src, dst = struct.unpack("!HH", frame[14 + header_len : 18 + header_len])
    for port in (src, dst):
        if low <= port <= high:
            return port
    return None


@pytest.mark.skipif(os.geteuid() != 0, reason="packet capture needs root")
def test_no_dds_traffic_outside_loopback(hdrc3_cli, ros_domain: int) -> None:
    interfaces = _external_interfaces()
    if not interfaces:
        pytest.skip("no external interface to watch")
    sockets = []
    for name in interfaces:
        sock = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ALL))
        sock.bind((name, 0))
        sock.settimeout(0.1)
        sockets.append(sock)
    low = 7400 + 250 * ros_domain
    high = low + 249
    launch = hdrc3_cli("launch", "--agents", "uav0,uav1")
    launch.wait_for_line("READY", timeout=60)
    leaked: list[tuple[str, int]] = []
    deadline = time.monotonic() + OBSERVE_S
    while time.monotonic() < deadline:
        for name, sock in zip(interfaces, sockets, strict=True):
            try:
                frame = sock.recv(65535)
            except TimeoutError:
                continue
            port = _dds_udp_port(frame, low, high)
            if port is not None:
                leaked.append((name, port))
    assert launch.interrupt() == 0
    for sock in sockets:
        sock.close()
    assert leaked == []


def test_port_filter_recognises_dds_frames() -> None:
    ip = bytes([0x45, 0, 0, 28, 0, 0, 0, 0, 64, 17, 0, 0]) + bytes(8)
    frame = bytes(12) + b"\x08\x00" + ip + struct.pack("!HHHH", 50000, 7400, 8, 0)
    assert _dds_udp_port(frame, 7400, 7649) == 7400
    assert _dds_udp_port(frame, 7650, 7899) is None
