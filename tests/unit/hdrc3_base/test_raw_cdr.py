"""The raw CDR readers against rclpy's own serialization."""

from __future__ import annotations

import random
from typing import Any

import pytest
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu

from hdrc3_base.raw_cdr import (
    RawMessageError,
    read_attitude,
    read_ground_contact,
    read_imu,
    read_stamp,
    read_yacs_status,
)
from hdrc3_base.stamps import set_stamp_ns
from hdrc3_interfaces.msg import Attitude, GroundContact, YacsStatus

FRAMES = ["", "a", "ab", "abc", "uav0/base_link_frd", "x" * 7, "x" * 8, "x" * 9, "y" * 12]
"""Frame ids of every length mod 8: the fields after the header move with it."""
STAMPS = [0, 1, 999_999_999, 1_000_000_000, 86_400_123_456_789]


def _stamped(msg: Any, ns: int, frame: str) -> Any:
    set_stamp_ns(msg.header.stamp, ns)
    msg.header.frame_id = frame
    return msg


def _cases(seed: int) -> list[tuple[int, str, random.Random]]:
    rng = random.Random(seed)
    return [(STAMPS[i % len(STAMPS)], frame, rng) for i, frame in enumerate(FRAMES)]


@pytest.mark.parametrize(("ns", "frame", "rng"), _cases(1))
def test_imu(ns: int, frame: str, rng: random.Random) -> None:
    msg = _stamped(Imu(), ns, frame)
    w = [rng.uniform(-5, 5) for _ in range(3)]
    a = [rng.uniform(-30, 30) for _ in range(3)]
    msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = w
    msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z = a
    msg.orientation.w = rng.uniform(-1, 1)  # fields skipped must not leak into those read
    msg.orientation_covariance[0] = -1.0
    msg.angular_velocity_covariance[8] = 7.0
    raw = read_imu(serialize_message(msg))
    assert raw.stamp_ns == ns
    assert raw.angular_velocity == tuple(w)
    assert raw.linear_acceleration == tuple(a)


@pytest.mark.parametrize(("ns", "frame", "rng"), _cases(2))
def test_attitude(ns: int, frame: str, rng: random.Random) -> None:
    values = [rng.uniform(-3.2, 6.3) for _ in range(3)]
    msg = _stamped(Attitude(roll=values[0], pitch=values[1], heading=values[2]), ns, frame)
    raw = read_attitude(serialize_message(msg))
    assert (raw.stamp_ns, raw.roll, raw.pitch, raw.heading) == (ns, *values)


@pytest.mark.parametrize(("ns", "frame"), [(ns, f) for ns in STAMPS[:2] for f in FRAMES])
@pytest.mark.parametrize("on_ground", [False, True])
def test_ground_contact(ns: int, frame: str, on_ground: bool) -> None:
    msg = _stamped(GroundContact(on_ground=on_ground), ns, frame)
    raw = read_ground_contact(serialize_message(msg))
    assert (raw.stamp_ns, raw.on_ground) == (ns, on_ground)


@pytest.mark.parametrize(("ns", "frame", "rng"), _cases(3))
def test_yacs_status(ns: int, frame: str, rng: random.Random) -> None:
    flags = [rng.random() < 0.5 for _ in range(3)]
    msg = _stamped(
        YacsStatus(
            mode=rng.choice([0, 1]),
            rc_link_ok=flags[0],
            engine_switch=flags[1],
            engine_running=flags[2],
            rotor_rpm=rng.uniform(0, 1100),
            source=rng.choice([0, 1, 2]),
            rejected_commands=rng.randrange(0, 2**32),
        ),
        ns,
        frame,
    )
    raw = read_yacs_status(serialize_message(msg))
    expected = (
        ns,
        msg.mode,
        msg.rc_link_ok,
        msg.engine_switch,
        msg.engine_running,
        msg.rotor_rpm,
        msg.source,
        msg.rejected_commands,
    )
    assert (
        raw.stamp_ns,
        raw.mode,
        raw.rc_link_ok,
        raw.engine_switch,
        raw.engine_running,
        raw.rotor_rpm,
        raw.source,
        raw.rejected_commands,
    ) == expected


@pytest.mark.parametrize("ns", STAMPS)
def test_clock(ns: int) -> None:
    msg = Clock()
    set_stamp_ns(msg.clock, ns)
    assert read_stamp(serialize_message(msg)) == ns


def test_big_endian_is_read() -> None:
    """Plain CDR in big endian (encapsulation 00 00): same fields."""
    body = (
        (5).to_bytes(4, "big")
        + (7).to_bytes(4, "big")
        + (2).to_bytes(4, "big")
        + b"a\x00"
        + b"\x01"
    )
    raw = read_ground_contact(b"\x00\x00\x00\x00" + body)
    assert (raw.stamp_ns, raw.on_ground) == (5_000_000_007, True)


@pytest.mark.parametrize(
    ("reader", "data"),
    [
        (read_imu, b""),
        (read_imu, b"\x00\x01\x00"),
        (read_imu, b"\x07\x07\x00\x00" + bytes(300)),  # unknown encapsulation
        (read_imu, serialize_message(Imu())[:100]),  # cut short
        (read_attitude, b"\x00\x01\x00\x00" + bytes(8) + (1000).to_bytes(4, "little")),
        (read_ground_contact, serialize_message(GroundContact())[:-1]),
        (read_yacs_status, serialize_message(YacsStatus())[:-3]),
        (read_stamp, b"\x00\x01\x00\x00\x01"),
    ],
)
def test_bad_data_raises(reader: Any, data: bytes) -> None:
    with pytest.raises(RawMessageError):
        reader(data)
