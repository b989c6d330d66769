"""Monitor formulas generated from the planning domain for flagged conditions (§9.3)."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.execution_monitor import EventKind, StartStatus
from hdrc3_deliberative.monitor_fakes import MonitorRig
from hdrc3_deliberative.monitor_generation import expand, read_domain_file
from hdrc3_deliberative.monitor_spec import MonitorSpecError, MonitorSpecParser
from hdrc3_deliberative.tal_language import TalReader

UAV_LOGISTICS = Path(__file__).resolve().parents[3] / (
    "hdrc3_deliberative/domains/uav_logistics/domain.tal"
)
PARSER = MonitorSpecParser()
DELIVERIES = """
domain deliveries
type helicopter, box
predicate carrying(h: helicopter, b: box)
predicate on_ground(h: helicopter)
operator pickup-box(b: box, h: helicopter)
  agent h
  duration 5
  pre not carrying(h, b)
  prevail not on_ground(h)
  effect [t'] carrying(h, b)
end
"""


def test_formulas_for_the_uav_logistics_pick_up() -> None:
    spec = PARSER.parse(
        "generate for pick-up-box: pre, prevail, effects, duration within 2000 ms;\n"
        "generate for drop-box: effects;"
    )
    out = expand(spec, read_domain_file(UAV_LOGISTICS))
    assert out.generate == ()
    texts = {decl.name: (decl.text, decl.parameters, decl.persistent) for decl in out.monitors}
    params = ("h", "b", "l")
    assert texts == {
        "pre:pick-up-box": (
            "(at(h, l)) and (at(b, l)) and (free(h)) and (hovering(h))"
            " and (weight(b) <= lift-capacity(h))",
            params,
            False,
        ),
        "prevail:pick-up-box": ("always (EXEC implies ((hovering(h))))", params, False),
        "effects:pick-up-box": (
            "EXEC until (not EXEC and eventually[0,2000]"
            " (not at(b, l) and not free(h) and holding-box(h, b)))",
            params,
            True,
        ),
        "duration:pick-up-box": ("eventually[0,22000] not EXEC", params, False),
        "effects:drop-box": (
            "EXEC until (not EXEC and eventually[0,1000]"
            " (not holding-box(h, b) and free(h) and at(b, l)))",
            params,
            True,
        ),
    }


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("generate for teleport: pre;", "operator 'teleport' is not in domain 'uav-logistics'"),
        ("generate for fly-to: prevail;", "has no prevail to monitor"),
        ("generate for fly-to: duration;", "has no duration to monitor"),  # flight-time(...)
        ("monitor pre:x: true;", "unexpected"),
    ],
)
def test_bad_requests_are_refused_at_their_position(text: str, reason: str) -> None:
    with pytest.raises(MonitorSpecError, match=reason) as info:
        expand(PARSER.parse(text, "g.monitors"), read_domain_file(UAV_LOGISTICS))
    assert str(info.value).startswith("g.monitors:1:")


def test_an_unreadable_domain(tmp_path: Path) -> None:
    with pytest.raises(PlanningInputError, match="cannot read"):
        read_domain_file(tmp_path / "none.tal")


def test_unexpanded_requests_make_the_monitor_refuse_to_start() -> None:
    rig = MonitorRig("generate for pickup-box: pre;")
    result = rig.start()
    assert result.status is StartStatus.UNKNOWN_SYMBOL and "needs the planning domain" in (
        result.reason
    )


def _run(carrying_from: int, grounded_at: int | None, stop: int) -> dict[str, EventKind]:
    """A pickup step from 1 s to ``stop`` ms; the generated formulas' final events."""
    rig = MonitorRig("")
    spec = PARSER.parse("generate for pickup-box: pre, prevail, effects, duration within 1500 ms;")
    rig.monitor.spec = expand(spec, TalReader().read_domain(DELIVERIES))
    assert rig.start().status is StartStatus.STARTED
    for now in range(0, 12001, 50):
        if now == 1000:
            rig.flag(now, "s1", "pickup-box", True, b="box1")
        if now == stop:
            rig.flag(now, "s1", "pickup-box", False, b="box1")
        if now % 40 == 0:
            rig.state(now, on_ground_flag=grounded_at is not None and now >= grounded_at)
        if now % 100 == 0:
            rig.sample("payload/carrying1", now, now >= carrying_from)
        rig.advance(now)
    return {
        e.monitor_id: e.kind
        for e in rig.events
        if e.kind in (EventKind.SATISFIED, EventKind.VIOLATED, EventKind.REFUSED)
    }


@pytest.mark.parametrize(
    ("name", "carrying_from", "grounded_at", "stop", "expected"),
    [
        ("nominal", 5500, None, 5000, {"pre": "S", "effects": "S", "duration": "S"}),
        ("box never lifted", 99999, None, 5000, {"pre": "S", "effects": "V", "duration": "S"}),
        ("already carrying", 0, None, 5000, {"pre": "V", "effects": "S", "duration": "S"}),
        ("landed during it", 5500, 3000, 5000, {"pre": "S", "prevail": "V", "effects": "S",
                                                "duration": "S"}),
        ("too slow", 8000, None, 7600, {"pre": "S", "effects": "S", "duration": "V"}),
    ],
)  # fmt: skip
def test_generated_formulas_on_a_pickup_step(
    name: str, carrying_from: int, grounded_at: int | None, stop: int, expected: dict[str, str]
) -> None:
    """pre at the first state; prevail over the step (retired after it when it held); effects
    within 1.5 s of the end; duration within 5 s + 1.5 s."""
    letters = {EventKind.SATISFIED: "S", EventKind.VIOLATED: "V", EventKind.REFUSED: "R"}
    got = {
        ident.split(":")[0]: letters[kind]
        for ident, kind in _run(carrying_from, grounded_at, stop).items()
    }
    assert got == expected, name
