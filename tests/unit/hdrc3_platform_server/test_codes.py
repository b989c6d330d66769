"""The pure core's codes equal the constants of the messages the node copies them into."""

from __future__ import annotations

import enum

import pytest

from hdrc3_interfaces.msg import FclReturn, PlatformEvent, PpclReturn
from hdrc3_platform_server.codes import EventKind, FclCode, PpclCode


@pytest.mark.parametrize(
    ("codes", "message", "prefix"),
    [
        (FclCode, FclReturn, "FCL_"),
        (PpclCode, PpclReturn, "PPCL_"),
        (EventKind, PlatformEvent, "KIND_"),
    ],
)
def test_codes_equal_the_message_constants(
    codes: type[enum.IntEnum], message: type, prefix: str
) -> None:
    constants = {
        name.removeprefix(prefix): getattr(message, name)
        for name in dir(message)
        if name.startswith(prefix) and isinstance(getattr(message, name), int)
    }
    assert {code.name: code.value for code in codes} == constants
