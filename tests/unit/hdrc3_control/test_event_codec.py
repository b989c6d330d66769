from __future__ import annotations

import math

import pytest

from hdrc3_control.event_codec import (
    COMMAND_ARITY,
    DecodeStatus,
    command_id_of,
    decode,
    decode_command,
    encode,
)


@pytest.mark.parametrize(
    ("cid", "values", "reason"),
    [(1, (), ""), (2**64 - 1, (1.5, -2.0), ""), (7, (), "engine not running"), (9, (0.1,), "é")],
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
    ],
)
def test_bad_payloads_are_results_not_exceptions(
    data: bytes, count: int, status: DecodeStatus
) -> None:
    out = decode(data, count)
    assert out.status is status and not out.ok and out.problem


def test_bad_reason_text() -> None:
    assert decode(encode(1) + b"\xff\xfe", 0, with_reason=True).status is DecodeStatus.BAD_TEXT


@pytest.mark.parametrize(("name", "count"), sorted(COMMAND_ARITY.items()))
def test_every_command_event_decodes_with_its_arity(name: str, count: int) -> None:
    values = tuple(float(i) for i in range(count))
    assert decode_command(name, encode(5, values)).values == values
    assert not decode_command(name, encode(5, (*values, 1.0))).ok


def test_unknown_command_and_range() -> None:
    assert not decode_command("Nope-EV", encode(1)).ok
    assert command_id_of(b"abc") == 0
    with pytest.raises(ValueError, match="uint64"):
        encode(-1)
