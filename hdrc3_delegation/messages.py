"""``hdrc3_interfaces/msg/AclMessage`` <-> :class:`~hdrc3_delegation.acl.AclMessage`."""

from __future__ import annotations

from typing import Any

from hdrc3_delegation.acl import AclMessage, Decoded, decode
from hdrc3_interfaces.msg import AclMessage as AclMessageMsg

FIELDS = tuple(AclMessage.__dataclass_fields__)
"""The message's fields, in the dataclass's order (the ROS message has the same names)."""


def to_msg(msg: AclMessage) -> Any:
    """The ROS message of a speech act."""
    out = AclMessageMsg()
    for name, value in msg.fields().items():
        setattr(out, name, value)
    return out


def raw_fields(ros: Any) -> dict[str, object]:
    """The plain fields of a received ROS message (receivers as a list)."""
    fields: dict[str, object] = {name: getattr(ros, name) for name in FIELDS}
    fields["receivers"] = [str(r) for r in ros.receivers]
    return fields


def from_msg(ros: Any) -> Decoded:
    """A received ROS message as a value, or why it is malformed."""
    return decode(raw_fields(ros))
