"""`hdrc3 tst run --fault`: parsing AGENT:SENSOR:MODE@NODE+SECONDS."""

from __future__ import annotations

import re

import pytest

from hdrc3.fault_trigger import TimedFault, fault_modes, parse_fault
from hdrc3_base.errors import ConfigError


def test_mode_names_come_from_the_service_definition() -> None:
    modes = fault_modes()
    assert modes["release"] == 5 and modes["hook_fail"] == 6 and modes["none"] == 0


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("uav0:hook:release@d/3+10", TimedFault("uav0", "hook", "release", "d/3", 10.0)),
        (" uav1:gps:drop@m[uav1]/s+0.5 ", TimedFault("uav1", "gps", "drop", "m[uav1]/s", 0.5)),
        ("uav0:hook:hook_fail@d/2.1+0", TimedFault("uav0", "hook", "hook_fail", "d/2.1", 0.0)),
    ],
)
def test_faults_parse(text: str, expected: TimedFault) -> None:
    assert parse_fault(text) == expected
    assert parse_fault(str(expected)) == expected


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("uav0:hook:release", "expected AGENT:SENSOR:MODE@NODE+SECONDS"),
        ("uav0:hook:explode@d/3+1", "unknown mode 'explode'"),
        ("uav0:hook:release@d/3+soon", "SECONDS must be a number >= 0"),
        ("uav0:hook:release@d/3+-1", "SECONDS must be a number >= 0"),
        ("uav0:hook:release@d/3+nan", "SECONDS must be a number >= 0"),
    ],
)
def test_bad_faults_are_refused_with_the_reason(text: str, reason: str) -> None:
    with pytest.raises(ConfigError, match=re.escape(reason)):
        parse_fault(text)
