"""`hdrc3 tst run --fault`: parsing AGENT:SENSOR:MODE@NODE+SECONDS, and when faults are due."""

from __future__ import annotations

import math
import re

import pytest

from hdrc3.fault_trigger import FaultSchedule, TimedFault, fault_modes, parse_fault
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
        ("uav0:hook:release@fly-to#2+10", TimedFault("uav0", "hook", "release", "fly-to", 10.0, 2)),
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
        ("uav0:hook:release@fly-to#0+1", "expected NODE or ACTION#N with N >= 1"),
        ("uav0:hook:release@fly-to#two+1", "expected NODE or ACTION#N with N >= 1"),
        ("uav0:hook:release@#2+1", "expected NODE or ACTION#N with N >= 1"),
    ],
)
def test_bad_faults_are_refused_with_the_reason(text: str, reason: str) -> None:
    with pytest.raises(ConfigError, match=re.escape(reason)):
        parse_fault(text)


# (agent, node id, kind, state, start) at sim times 0, 1, 2, ...
DELIVERY = [
    ("uav0", "d/1", "fly-to", "running", 0.5),
    ("uav0", "d/1", "fly-to", "running", 0.5),  # a status sent again counts once
    ("uav1", "e/1", "fly-to", "running", 0.5),  # another agent's fly-to
    ("uav0", "d/2", "pick-up-box", "running", math.nan),  # running, waiting to begin
    ("uav0", "d/2", "pick-up-box", "failed", 3.0),
    ("uav0", "d/2.1", "pick-up-box", "running", 5.0),  # the goal planned again
    ("uav0", "d/2.2", "fly-to", "running", 6.0),
    ("uav0", "d/3", "fly-to", "running", 7.0),
]


@pytest.mark.parametrize(
    ("text", "armed_at"),
    [
        ("uav0:hook:release@fly-to#2+10", 6),  # the carrying flight, whatever its id
        ("uav0:hook:release@d/2.1+1", 5),
        ("uav0:hook:release@d/2+0", None),  # never began running
        ("uav1:gps:drop@d/3+0", 7),  # a node id arms a fault of any agent
        ("uav1:gps:drop@fly-to#2+0", None),  # uav1 ran one fly-to
        ("uav0:hook:release@fly-to#4+0", None),
    ],
)
def test_a_fault_is_due_its_delay_after_its_node_began(text: str, armed_at: int | None) -> None:
    fault = parse_fault(text)
    schedule = FaultSchedule([fault])
    for now, status in enumerate(DELIVERY):
        schedule.on_status(*status, now=float(now))
    if armed_at is None:
        assert schedule.due(1e9) == [] and schedule.pending() == [fault]
        return
    assert schedule.due(armed_at + fault.delay_s - 0.01) == []
    assert schedule.due(armed_at + fault.delay_s) == [fault]
    assert schedule.due(1e9) == [] and schedule.pending() == []  # injected once
