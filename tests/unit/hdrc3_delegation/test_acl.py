"""FIPA ACL messages: fields, canonical envelope, decoding of malformed input."""

from __future__ import annotations

from typing import Any

import pytest

from hdrc3_delegation.acl import (
    MAX_CONTENT,
    AclMessage,
    Performative,
    canonical_envelope,
    decode,
)

MSG = AclMessage(
    Performative.CFP,
    "gcs",
    ("uav0", "uav1"),
    '{"a":1}',
    "hdrc3-delegation+json",
    "hdrc3-tst",
    "fipa-contract-net",
    "c1",
    "cfp-0-0",
    "",
    12.5,
    "ab" * 16,
    10.0,
    "cd" * 32,
)


def test_all_22_fipa_performatives() -> None:
    assert len(Performative) == 22
    assert Performative("accept-proposal") is Performative.ACCEPT_PROPOSAL


def test_fields_round_trip_through_decode() -> None:
    assert decode(MSG.fields()).message == MSG


def test_the_envelope_covers_every_field_but_the_signature() -> None:
    base = canonical_envelope(MSG)
    assert canonical_envelope(MSG.with_envelope(MSG.nonce, MSG.sent_at, "00")) == base
    for name, value in [("content", "x"), ("reply_by", 13.0), ("receivers", ("uav0",))]:
        changed = AclMessage(**{**MSG.__dict__, name: value})
        assert canonical_envelope(changed) != base, name


def test_reply_keeps_the_conversation() -> None:
    answer = MSG.reply("uav1", Performative.PROPOSE, "{}")
    assert (answer.sender, answer.receivers) == ("uav1", ("gcs",))
    assert (answer.conversation_id, answer.in_reply_to) == ("c1", "cfp-0-0")
    assert answer.protocol == MSG.protocol


def _with(**changes: Any) -> dict[str, object]:
    fields = MSG.fields()
    fields.update(changes)
    return fields


@pytest.mark.parametrize(
    ("fields", "reason"),
    [
        (_with(sender="GCS!"), "sender"),
        (_with(receivers=[]), "receivers"),
        (_with(receivers=["uav0", 3]), "receivers"),
        (_with(content="x" * (MAX_CONTENT + 1)), "exceeds"),
        (_with(reply_by=float("nan")), "reply_by"),
        (_with(sent_at=-1.0), "sent_at"),
        (_with(protocol="has spaces"), "protocol"),
        (_with(nonce="XYZ"), "nonce"),
        (_with(language=None), "language"),
        ({"performative": "cfp"}, "sender"),
    ],
)
def test_malformed_fields_are_named(fields: dict[str, object], reason: str) -> None:
    decoded = decode(fields)
    assert decoded.message is None
    assert reason in decoded.reason


def test_an_unknown_performative_is_flagged() -> None:
    decoded = decode(_with(performative="beg"))
    assert decoded.message is None and decoded.unknown_performative
    assert "beg" in decoded.reason
