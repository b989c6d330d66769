"""FIPA ACL speech acts (chapter section 10; FIPA SC00061 message structure, SC00037 performatives).

An :class:`AclMessage` is a frozen value with the FIPA message parameters the delegation protocol
uses, plus the three fields of the authenticated envelope (``nonce``, ``sent_at``, ``signature``).
:func:`canonical_envelope` is the one byte layout the signature covers; :func:`decode` turns the
fields of a received message into a value or a :class:`Decoded` with the reason it is malformed,
so a gateway answers bad input with ``not-understood`` instead of raising. Written here rather than
taken from SPADE because SPADE's messages are tied to XMPP; only the FIPA field set carries over.
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import re
from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace

from hdrc3_base.agents import AGENT_NAME


class Performative(enum.Enum):
    """The 22 communicative acts of the FIPA Communicative Act Library (SC00037)."""

    ACCEPT_PROPOSAL = "accept-proposal"
    AGREE = "agree"
    CANCEL = "cancel"
    CFP = "cfp"
    CONFIRM = "confirm"
    DISCONFIRM = "disconfirm"
    FAILURE = "failure"
    INFORM = "inform"
    INFORM_IF = "inform-if"
    INFORM_REF = "inform-ref"
    NOT_UNDERSTOOD = "not-understood"
    PROPAGATE = "propagate"
    PROPOSE = "propose"
    PROXY = "proxy"
    QUERY_IF = "query-if"
    QUERY_REF = "query-ref"
    REFUSE = "refuse"
    REJECT_PROPOSAL = "reject-proposal"
    REQUEST = "request"
    REQUEST_WHEN = "request-when"
    REQUEST_WHENEVER = "request-whenever"
    SUBSCRIBE = "subscribe"


MAX_CONTENT = 256 * 1024
"""Largest content accepted, in characters (a TST of a few thousand nodes fits)."""
MAX_RECEIVERS = 64
"""Most receivers of one message."""
_TOKEN = re.compile(r"^[A-Za-z0-9._:+\-/@]{0,128}$")
_HEX = re.compile(r"^[0-9a-f]*$")


@dataclass(frozen=True)
class AclMessage:
    """One speech act; the last three fields are the sender's authentication of the rest."""

    performative: Performative
    sender: str
    receivers: tuple[str, ...]
    content: str = ""
    language: str = ""
    ontology: str = ""
    protocol: str = ""
    conversation_id: str = ""
    reply_with: str = ""
    in_reply_to: str = ""
    reply_by: float = 0.0
    """Answer deadline, seconds since the epoch (0: none)."""
    nonce: str = ""
    sent_at: float = 0.0
    signature: str = ""

    def reply(
        self, sender: str, performative: Performative, content: str = "", reply_with: str = ""
    ) -> AclMessage:
        """An answer from ``sender`` (one of the receivers) in the same conversation."""
        return AclMessage(
            performative,
            sender,
            (self.sender,),
            content,
            self.language,
            self.ontology,
            self.protocol,
            self.conversation_id,
            reply_with,
            self.reply_with,
        )

    def with_envelope(self, nonce: str, sent_at: float, signature: str) -> AclMessage:
        """The same act with its authentication fields set."""
        return replace(self, nonce=nonce, sent_at=sent_at, signature=signature)

    def fields(self) -> dict[str, object]:
        """Plain fields (the ROS message's layout): performative as its FIPA name."""
        out = asdict(self)
        out["performative"] = self.performative.value
        out["receivers"] = list(self.receivers)
        return out

    def __str__(self) -> str:
        to = ",".join(self.receivers)
        return f"({self.performative.value} {self.sender}->{to} conv={self.conversation_id})"


def canonical_envelope(msg: AclMessage) -> bytes:
    """The bytes a signature covers: every field but the signature, as sorted compact JSON."""
    return canonical_fields(msg.fields())


def canonical_fields(fields: Mapping[str, object]) -> bytes:
    """:func:`canonical_envelope` of raw fields (also of a message whose performative is unknown).

    Raises:
        TypeError: a field is not JSON-representable (callers pass decoded ROS fields).
    """
    body = {k: v for k, v in fields.items() if k != "signature"}
    return json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=True).encode()


@dataclass(frozen=True)
class Decoded:
    """A received message as a value, or the reason it is malformed."""

    message: AclMessage | None
    reason: str = ""
    unknown_performative: bool = False


_FIELD_TYPES = {f.name: f.type for f in dataclasses.fields(AclMessage)}
_TIMES = tuple(name for name, kind in _FIELD_TYPES.items() if kind == "float")
_STRINGS = ("performative", *(name for name, kind in _FIELD_TYPES.items() if kind == "str"))
_HEX_FIELDS = ("nonce", "signature")
_TOKENS = tuple(n for n in _STRINGS if n not in ("performative", "sender", "content", *_HEX_FIELDS))
"""Language, ontology, protocol and the conversation's tags: short printable tokens."""


def decode(fields: Mapping[str, object]) -> Decoded:
    """Validate the fields of a received message (never raises)."""
    for name in _STRINGS:
        if not isinstance(fields.get(name), str):
            return Decoded(None, f"field {name} is missing or not text")
    text = {name: str(fields[name]) for name in _STRINGS}
    receivers = fields.get("receivers")
    if not isinstance(receivers, list | tuple) or not all(isinstance(r, str) for r in receivers):
        return Decoded(None, "field receivers is missing or not a list of names")
    times: dict[str, float] = {}
    for name in _TIMES:
        value = fields.get(name)
        if not isinstance(value, int | float) or not math.isfinite(value) or value < 0:
            return Decoded(None, f"field {name} must be a finite time >= 0")
        times[name] = float(value)
    reason = _check(text, tuple(receivers))
    if reason:
        return Decoded(None, reason)
    try:
        performative = Performative(text["performative"])
    except ValueError:
        return Decoded(None, f"unknown performative {text['performative']!r}", True)
    values: dict[str, object] = {**text, **times, "receivers": tuple(receivers)}
    values["performative"] = performative
    return Decoded(AclMessage(**values))  # type: ignore[arg-type]


def _check(text: Mapping[str, str], receivers: tuple[str, ...]) -> str:
    if not AGENT_NAME.match(text["sender"]):
        return f"sender {text['sender'][:40]!r} is not an agent name"
    if not receivers or len(receivers) > MAX_RECEIVERS:
        return f"a message needs 1..{MAX_RECEIVERS} receivers, not {len(receivers)}"
    bad = [r for r in receivers if not AGENT_NAME.match(r)]
    if bad:
        return f"receiver {bad[0][:40]!r} is not an agent name"
    if len(text["content"]) > MAX_CONTENT:
        return f"content of {len(text['content'])} characters exceeds {MAX_CONTENT}"
    for name in _TOKENS:
        if not _TOKEN.match(text[name]):
            return f"field {name} is not a short token"
    for name in _HEX_FIELDS:
        if len(text[name]) > 128 or not _HEX.match(text[name]):
            return f"field {name} is not lower-case hex"
    return ""
