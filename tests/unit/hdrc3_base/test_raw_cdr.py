"""CdrReader against rclpy's own serialization, for every field of several message types."""

from __future__ import annotations

import random
from typing import Any

import pytest
from geometry_msgs.msg import PoseWithCovarianceStamped, TwistStamped
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, NavSatFix

from hdrc3_base.errors import ConfigError
from hdrc3_base.raw_cdr import CdrReader, RawMessageError
from hdrc3_base.stamps import set_stamp_ns
from hdrc3_interfaces.msg import Attitude, Barometer, GroundContact, YacsStatus

FRAMES = ["", "a", "ab", "abc", "uav0/base_link_frd", "x" * 7, "x" * 8, "x" * 9, "y" * 12]
"""Frame ids of every length mod 8: the fields after the header move with it."""
STAMPS = [0, 1, 999_999_999, 1_000_000_000, 86_400_123_456_789]
TYPES = [Imu, Attitude, GroundContact, YacsStatus, Barometer, NavSatFix, TwistStamped, Clock]


def _leaves(msg: Any, prefix: str = "") -> list[tuple[str, Any]]:
    """(dotted path, holder) of every primitive field, in declaration order (arrays left out)."""
    out: list[tuple[str, Any]] = []
    for name, kind in msg.get_fields_and_field_types().items():
        value = getattr(msg, name)
        if hasattr(value, "get_fields_and_field_types"):
            out.extend(_leaves(value, f"{prefix}{name}."))
        elif "[" not in kind and kind != "string":
            out.append((f"{prefix}{name}", (msg, name, kind)))
    return out


def _random(kind: str, rng: random.Random) -> Any:
    if kind == "boolean":
        return rng.random() < 0.5
    if kind in ("float", "double"):
        return float(rng.uniform(-1e3, 1e3)) if kind == "double" else float(rng.randint(-99, 99))
    bits = int("".join(c for c in kind if c.isdigit()) or 8)
    if kind.startswith("u") or kind in ("octet", "char"):
        return rng.randrange(0, 2**bits)
    return rng.randrange(-(2 ** (bits - 1)), 2 ** (bits - 1))


def _filled(msg_type: Any, rng: random.Random, frame: str, ns: int) -> Any:
    msg = msg_type()
    for _path, (holder, name, kind) in _leaves(msg):
        setattr(holder, name, _random(kind, rng))
    if hasattr(msg, "header"):
        msg.header.frame_id = frame
        set_stamp_ns(msg.header.stamp, ns)
    return msg


@pytest.mark.parametrize("msg_type", TYPES, ids=lambda t: t.__name__)
@pytest.mark.parametrize(("frame", "ns"), list(zip(FRAMES, STAMPS * 2, strict=False)))
def test_every_field_and_a_sparse_choice_read_as_rclpy_wrote_them(
    msg_type: Any, frame: str, ns: int
) -> None:
    rng = random.Random(f"{msg_type.__name__}{frame}{ns}")
    msg = _filled(msg_type, rng, frame, ns)
    leaves = _leaves(msg)
    expected = [getattr(holder, name) for _p, (holder, name, _k) in leaves]
    data = serialize_message(msg)
    assert list(CdrReader(msg_type, [p for p, _ in leaves]).read(data)) == pytest.approx(expected)
    sparse = leaves[::3]
    got = CdrReader(msg_type, [p for p, _ in sparse]).read(data)
    assert list(got) == pytest.approx([getattr(h, n) for _p, (h, n, _k) in sparse])


def test_fixed_arrays_are_skipped_not_read() -> None:
    msg = _filled(Imu, random.Random(1), "uav0/base_link_frd", 5)
    msg.orientation_covariance[0] = -1.0  # arrays before and between the fields read
    msg.angular_velocity_covariance[8] = 7.0
    fields = ("angular_velocity.z", "linear_acceleration.x")
    got = CdrReader(Imu, fields).read(serialize_message(msg))
    assert got == (msg.angular_velocity.z, msg.linear_acceleration.x)


def test_big_endian_is_read() -> None:
    """Plain CDR in big endian (encapsulation 00 00): same fields."""
    body = (5).to_bytes(4, "big") + (7).to_bytes(4, "big") + (2).to_bytes(4, "big") + b"a\x00\x01"
    reader = CdrReader(GroundContact, ("header.stamp.sec", "header.stamp.nanosec", "on_ground"))
    assert reader.read(b"\x00\x00\x00\x00" + body) == (5, 7, True)


IMU = CdrReader(Imu, ("header.stamp.sec", "angular_velocity.x", "linear_acceleration.z"))


@pytest.mark.parametrize(
    ("reader", "data"),
    [
        pytest.param(IMU, b"", id="empty"),
        pytest.param(IMU, b"\x00\x01\x00", id="no-encapsulation"),
        pytest.param(IMU, b"\x07\x07\x00\x00" + bytes(300), id="unknown-encapsulation"),
        # named ids: rmw leaves CDR padding bytes unset, so serialized bytes differ between
        # processes, and pytest-xdist's workers must collect the same test names
        pytest.param(IMU, serialize_message(Imu())[:100], id="imu-cut-short"),
        pytest.param(
            IMU,
            b"\x00\x01\x00\x00" + bytes(8) + (1000).to_bytes(4, "little") + bytes(40),
            id="string-past-the-end",
        ),
        pytest.param(
            CdrReader(GroundContact, ("on_ground",)),
            serialize_message(GroundContact())[:-1],
            id="ground-contact-cut-short",
        ),
        pytest.param(
            CdrReader(Clock, ("clock.nanosec",)), b"\x00\x01\x00\x00\x01", id="clock-cut-short"
        ),
    ],
)
def test_bad_data_raises(reader: CdrReader, data: bytes) -> None:
    with pytest.raises(RawMessageError):
        reader.read(data)


@pytest.mark.parametrize(
    ("msg_type", "fields"),
    [
        (Imu, ("angular_velocity.w",)),  # no such field
        (Imu, ("orientation_covariance",)),  # an array
        (Imu, ("header.frame_id",)),  # a string
        (Imu, ("linear_acceleration.x", "angular_velocity.x")),  # not in wire order
        (PoseWithCovarianceStamped, ("pose.pose.position.q",)),
    ],
)
def test_misuse_is_refused_when_the_reader_is_made(msg_type: Any, fields: tuple[str]) -> None:
    with pytest.raises(ConfigError):
        CdrReader(msg_type, fields)
