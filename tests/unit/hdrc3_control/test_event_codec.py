from __future__ import annotations

import math

import pytest

from hdrc3_control.event_codec import DecodeStatus, command_id_of, decode, encode


@pytest.mark.parametrize(
    ("cid", "values", "reason"),
    [
        (1, (), ""),
        (2**64 - 1, (1.5, -2.0), ""),
        (7, (), "engine not running"),
        (9, (0.1,), "é"),
        (2**64 - 1, (1.5, -2.0), "why"),
        (7, (0.0,) * 14, ""),
        (3, (), "ünïcode"),
    ],
)
def test_round_trip(cid: int, values: tuple[float, ...], reason: str) -> None:
    data = encode(cid, values, reason)
    out = decode(data, len(values), with_reason=bool(reason))
    assert out.ok and (out.command_id, out.values, out.reason) == (cid, values, reason)
    assert command_id_of(data) == cid


@pytest.mark.parametrize(
    ("data", "count", "status"),
    [
        (b"\x01\x02", 0, DecodeStatus.TOO_SHORT),
        (encode(1, (1.0,)), 0, DecodeStatus.WRONG_LENGTH),
        (encode(1, (math.nan,)), 1, DecodeStatus.NOT_FINITE),
        (encode(1, (1.0, 2.0)), 3, DecodeStatus.TOO_SHORT),
        (b"", 0, DecodeStatus.TOO_SHORT),
        (b"1234567", 0, DecodeStatus.TOO_SHORT),
        (encode(1, (1.0,)), 2, DecodeStatus.TOO_SHORT),
    ],
)
def test_bad_payloads_are_results_not_exceptions(
    data: bytes, count: int, status: DecodeStatus
) -> None:
    out = decode(data, count)
    assert out.status is status and not out.ok and out.problem


def test_bad_reason_text_is_flagged_and_still_readable() -> None:
    out = decode(encode(1) + b"\xff\xfe", 0, with_reason=True)
    assert out.status is DecodeStatus.BAD_TEXT and not out.ok
    assert (out.command_id, out.reason) == (1, "\ufffd\ufffd")


def test_short_id_and_range() -> None:
    assert command_id_of(b"abc") == 0
    with pytest.raises(ValueError, match="uint64"):
        encode(-1)
