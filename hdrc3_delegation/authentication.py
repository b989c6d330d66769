"""Authenticated speech acts: HMAC-SHA256 over the canonical envelope, replay protection.

A sender signs with its own key from the keystore; a receiver recomputes the HMAC with the
sender's key (``hmac.compare_digest``), requires ``sent_at`` within :attr:`Authenticator.window`
of its own clock, and remembers each ``(sender, nonce)`` for that window so a copy is refused.
Nonces older than the window are forgotten, since the time check already refuses their messages.
The standard library's ``hmac`` and ``secrets`` are the implementation; nothing hand-rolled.
"""

from __future__ import annotations

import enum
import hashlib
import hmac
import math
import secrets
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass

from hdrc3_delegation.acl import AclMessage, canonical_envelope, canonical_fields
from hdrc3_delegation.errors import DelegationError
from hdrc3_delegation.keystore import Keystore, KeystoreError

NONCE_BYTES = 16


class Verdict(enum.Enum):
    """Whether a received message is accepted, and if not, why."""

    ACCEPTED = "accepted"
    UNKNOWN_SENDER = "unknown_sender"
    BAD_SIGNATURE = "bad_signature"
    REPLAYED = "replayed"
    STALE = "stale"
    """Signed too long ago (or too far in the future) for the time window."""
    NOT_ADDRESSED = "not_addressed"
    OVERLOADED = "overloaded"
    """More fresh nonces than the replay cache holds: refused rather than forgetting one."""


@dataclass(frozen=True)
class Check:
    """A verdict and its readable reason (never containing a key)."""

    verdict: Verdict
    reason: str = ""

    @property
    def accepted(self) -> bool:
        """The message may be processed."""
        return self.verdict is Verdict.ACCEPTED


class Authenticator:
    """Signs outgoing and checks incoming speech acts for one agent."""

    def __init__(
        self, agent: str, keystore: Keystore, window: float = 30.0, capacity: int = 100_000
    ) -> None:
        """``agent`` signs with its own key (which the keystore must hold)."""
        own = keystore.key(agent)
        if own is None:
            raise KeystoreError(f"the keystore has no key for {agent} (has {keystore.agents})")
        self.agent = agent
        self.keystore = keystore
        self.window = window
        self.capacity = capacity
        self._own = own
        self._seen: set[tuple[str, str]] = set()
        self._order: deque[tuple[float, str, str]] = deque()

    def sign(self, msg: AclMessage, now: float) -> AclMessage:
        """The message with a fresh nonce, ``sent_at = now`` and its signature."""
        if msg.sender != self.agent:
            raise DelegationError(f"{self.agent} cannot sign a message from {msg.sender}")
        unsigned = msg.with_envelope(secrets.token_hex(NONCE_BYTES), now, "")
        return unsigned.with_envelope(unsigned.nonce, now, _mac(self._own, unsigned))

    def verify(self, msg: AclMessage, now: float) -> Check:
        """Accept once: known sender, valid HMAC, fresh time, unseen nonce, addressed to us."""
        return self._verify(
            msg.sender,
            msg.receivers,
            msg.nonce,
            msg.sent_at,
            msg.signature,
            canonical_envelope(msg),
            now,
        )

    def verify_fields(self, fields: Mapping[str, object], now: float) -> Check:
        """:meth:`verify` of raw fields that do not decode (e.g. an unknown performative).

        Only fields of the right types reach here (the ROS message guarantees them); anything
        else is refused as a bad signature.
        """
        sender, receivers, nonce = (
            fields.get("sender"),
            fields.get("receivers"),
            fields.get("nonce"),
        )
        sent_at, signature = fields.get("sent_at"), fields.get("signature")
        if not (
            isinstance(sender, str)
            and isinstance(nonce, str)
            and isinstance(signature, str)
            and isinstance(sent_at, float | int)
            and isinstance(receivers, list | tuple)
        ):
            return Check(Verdict.BAD_SIGNATURE, "envelope fields missing")
        try:
            envelope = canonical_fields(fields)
        except (TypeError, ValueError):
            return Check(Verdict.BAD_SIGNATURE, "envelope not representable")
        return self._verify(
            sender,
            tuple(str(r) for r in receivers),
            nonce,
            float(sent_at),
            signature,
            envelope,
            now,
        )

    def _verify(
        self,
        sender: str,
        receivers: tuple[str, ...],
        nonce: str,
        sent_at: float,
        signature: str,
        envelope: bytes,
        now: float,
    ) -> Check:
        self._forget(now)
        key = self.keystore.key(sender)
        if key is None:
            return Check(Verdict.UNKNOWN_SENDER, f"no key for sender {sender[:40]!r}")
        expected = hmac.new(key, envelope, hashlib.sha256).hexdigest()
        if not hmac.compare_digest(expected, signature):
            return Check(Verdict.BAD_SIGNATURE, f"signature does not match {sender}'s key")
        if not math.isfinite(sent_at) or abs(now - sent_at) > self.window:
            return Check(
                Verdict.STALE,
                f"signed {now - sent_at:+.1f} s from now, outside +-{self.window:g} s",
            )
        tag = (sender, nonce)
        if len(nonce) != 2 * NONCE_BYTES:
            return Check(Verdict.BAD_SIGNATURE, "nonce of the wrong length")
        if tag in self._seen:
            return Check(Verdict.REPLAYED, f"nonce {nonce[:8]}... of {sender} seen before")
        if self.agent not in receivers:
            return Check(Verdict.NOT_ADDRESSED, f"addressed to {','.join(receivers)}")
        if len(self._seen) >= self.capacity:
            return Check(Verdict.OVERLOADED, f"{self.capacity} fresh nonces held")
        self._seen.add(tag)
        self._order.append((sent_at, *tag))
        return Check(Verdict.ACCEPTED)

    @property
    def remembered(self) -> int:
        """Nonces held for replay detection now."""
        return len(self._seen)

    def _forget(self, now: float) -> None:
        """Drop nonces whose messages the time window refuses anyway."""
        order = self._order
        while order and order[0][0] < now - self.window:
            _, sender, nonce = order.popleft()
            self._seen.discard((sender, nonce))


def _mac(key: bytes, msg: AclMessage) -> str:
    return hmac.new(key, canonical_envelope(msg), hashlib.sha256).hexdigest()
