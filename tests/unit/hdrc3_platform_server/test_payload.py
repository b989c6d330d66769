from __future__ import annotations

import pytest

from hdrc3_control import event_codec
from hdrc3_platform_server.payload import PayloadError, command_id_of, decode, encode


@pytest.mark.parametrize(
    ("cid", "numbers", "reason"),
    [(1, (), ""), (2**64 - 1, (1.5, -2.0), "why"), (7, (0.0,) * 14, ""), (3, (), "ünïcode")],
)
def test_round_trip_and_agreement_with_the_pfc_codec(
    cid: int, numbers: tuple[float, ...], reason: str
) -> None:
    data = encode(cid, numbers, reason)
    p = decode(data, len(numbers))
    assert (p.command_id, p.numbers, p.reason) == (cid, numbers, reason)
    assert command_id_of(data) == cid
    other = event_codec.decode(data, len(numbers), with_reason=True)
    assert other.ok and other.command_id == cid and other.reason == reason


@pytest.mark.parametrize(("data", "count"), [(b"", 0), (b"1234567", 0), (encode(1, (1.0,)), 2)])
def test_short_payloads(data: bytes, count: int) -> None:
    with pytest.raises(PayloadError):
        decode(data, count)


def test_invalid_utf8_reason_is_replaced() -> None:
    assert decode(encode(1) + b"\xff", 0).reason == "\ufffd"
    assert command_id_of(b"abc") is None
