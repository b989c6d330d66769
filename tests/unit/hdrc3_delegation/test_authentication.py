"""Signing and checking speech acts: forged, replayed, stale and misaddressed messages."""

from __future__ import annotations

import dataclasses
import hashlib
import hmac

import pytest

from hdrc3_delegation.acl import AclMessage, Performative
from hdrc3_delegation.authentication import Authenticator, Verdict
from hdrc3_delegation.errors import DelegationError
from hdrc3_delegation.keystore import KeystoreError, parse_keystore

KEYS = parse_keystore(
    "[keys]\n"
    + "".join(f'{a} = "{i:02x}{"5a" * 31}"\n' for i, a in enumerate(["gcs", "uav0", "uav1"]))
)
OTHER = parse_keystore('[keys]\ngcs = "' + "77" * 32 + '"\n')
MSG = AclMessage(Performative.CFP, "gcs", ("uav0",), "{}", conversation_id="c")


def signed(now: float = 100.0) -> AclMessage:
    return Authenticator("gcs", KEYS).sign(MSG, now)


def test_a_signed_message_is_accepted_once() -> None:
    receiver = Authenticator("uav0", KEYS)
    msg = signed()
    assert receiver.verify(msg, 101.0).accepted
    assert receiver.verify(msg, 101.5).verdict is Verdict.REPLAYED


@pytest.mark.parametrize(
    ("tamper", "verdict"),
    [
        (lambda m: dataclasses.replace(m, content='{"x":1}'), Verdict.BAD_SIGNATURE),
        (lambda m: dataclasses.replace(m, receivers=("uav0", "uav1")), Verdict.BAD_SIGNATURE),
        (lambda m: dataclasses.replace(m, sender="uav1"), Verdict.BAD_SIGNATURE),
        (lambda m: dataclasses.replace(m, sender="uav7"), Verdict.UNKNOWN_SENDER),
        (lambda m: dataclasses.replace(m, signature=""), Verdict.BAD_SIGNATURE),
        (lambda m: Authenticator("gcs", OTHER).sign(MSG, 100.0), Verdict.BAD_SIGNATURE),
        (lambda m: Authenticator("gcs", KEYS).sign(MSG, 40.0), Verdict.STALE),
        (lambda m: Authenticator("gcs", KEYS).sign(MSG, 160.0), Verdict.STALE),
    ],
)
def test_forged_and_stale_messages_are_refused(tamper, verdict: Verdict) -> None:  # type: ignore[no-untyped-def]
    check = Authenticator("uav0", KEYS).verify(tamper(signed()), 101.0)
    assert check.verdict is verdict
    assert "5a5a" not in check.reason


def test_a_message_for_someone_else_is_not_processed() -> None:
    assert Authenticator("uav1", KEYS).verify(signed(), 101.0).verdict is Verdict.NOT_ADDRESSED


def test_nonces_are_forgotten_only_when_the_window_refuses_them_anyway() -> None:
    receiver = Authenticator("uav0", KEYS, window=30.0)
    msg = signed(100.0)
    assert receiver.verify(msg, 100.0).accepted
    for now in (120.0, 129.9):
        assert receiver.verify(msg, now).verdict is Verdict.REPLAYED
    assert receiver.verify(msg, 131.0).verdict is Verdict.STALE
    assert receiver.remembered == 0


def test_a_full_replay_cache_refuses_instead_of_forgetting() -> None:
    receiver = Authenticator("uav0", KEYS, capacity=2)
    verdicts = [receiver.verify(signed(), 100.0).verdict for _ in range(3)]
    assert verdicts == [Verdict.ACCEPTED, Verdict.ACCEPTED, Verdict.OVERLOADED]


def test_misuse_raises() -> None:
    with pytest.raises(KeystoreError, match="no key for uav9"):
        Authenticator("uav9", KEYS)
    with pytest.raises(DelegationError, match="cannot sign"):
        Authenticator("uav0", KEYS).sign(MSG, 0.0)


def test_raw_fields_of_an_unknown_performative_verify_like_the_message() -> None:
    from hdrc3_delegation.acl import canonical_fields

    fields = signed().fields()
    fields["performative"] = "beg"
    key = KEYS.key("gcs")
    assert key is not None
    fields["signature"] = hmac.new(key, canonical_fields(fields), hashlib.sha256).hexdigest()
    receiver = Authenticator("uav0", KEYS)
    assert receiver.verify_fields(fields, 101.0).accepted
    assert receiver.verify_fields(fields, 101.0).verdict is Verdict.REPLAYED
    forged = dict(fields, content="{}", nonce="ef" * 16)
    assert receiver.verify_fields(forged, 101.0).verdict is Verdict.BAD_SIGNATURE
    assert receiver.verify_fields({"sender": "gcs"}, 101.0).verdict is Verdict.BAD_SIGNATURE
