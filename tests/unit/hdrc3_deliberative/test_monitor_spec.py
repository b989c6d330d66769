"""Monitor specification reader: declarations, settings, positioned errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_deliberative.monitor_spec import (
    DEFAULT_SPEC,
    Generated,
    MonitorSpecError,
    MonitorSpecParser,
    StateSettings,
)

PARSER = MonitorSpecParser()
SPEC = """\
states period 50 ms, max_delay 100 ms, stale 700 ms;
# Example 9.2 and 9.3
monitor speed brake recovery hover_and_replan: always speed(uav0) <= 12;
monitor pickup for pickup-box(av, box) recovery retry:
    eventually[0,5000] always[0,1000] carrying(av, box);
monitor climbed for climb(av) persistent: EXEC until altitude(av) >= 7.0;
"""


def test_declarations_and_settings() -> None:
    spec = PARSER.parse(SPEC, "s.monitors")
    assert spec.settings == StateSettings(50, 100, 700)
    speed, pickup, climbed = spec.monitors
    assert (speed.name, speed.is_global, speed.brake, speed.recovery) == (
        "speed",
        True,
        True,
        "hover_and_replan",
    )
    assert (pickup.operator, pickup.parameters, pickup.recovery, pickup.line) == (
        "pickup-box",
        ("av", "box"),
        "retry",
        4,
    )
    assert pickup.text == "eventually[0,5000] always[0,1000] carrying(av, box)"
    assert str(pickup.formula) == pickup.text
    assert climbed.persistent and not climbed.brake
    assert spec.for_operator("pickup-box") == (pickup,)
    assert spec.for_operator("land") == ()


def test_defaults_without_states_statement() -> None:
    spec = PARSER.parse("monitor a: always true;")
    assert spec.settings == StateSettings()


def test_the_packaged_default_parses() -> None:
    spec = PARSER.parse_file(DEFAULT_SPEC)
    assert {decl.name for decl in spec.monitors} == {
        "speed_limit",
        "climb_reached",
        "carrier_lifted",
        "box_lifted",
        "box_held",
    }


@pytest.mark.parametrize(
    ("text", "line", "column", "reason"),
    [
        # a formula's syntax error at its position in the file, on its first and a later line
        ("monitor a: always speed(av) <<= 3;", 1, 30, "unexpected '<='"),
        ("monitor a for climb(av):\n  always (speed(av) < 3;", 2, 24, "unexpected end"),
        ("monitor a:\n\n   eventually[0,] p;", 3, 17, "unexpected ']'"),
        ("monitor a: p;\nmonitor a: q;", 2, 1, "declared twice"),
        ("states period 0 ms;", 1, 1, "must be > 0"),
        ("monitor b for c(): x;", 1, 11, "at least the agent"),
        ("monitor b for c(av, av): x;", 1, 11, "repeats a parameter"),
        ("monitor b", 1, 10, "unexpected end"),
        ("watch b: p;", 1, 1, "unexpected"),
        ("states period 10 s;", 1, 18, "unexpected"),
    ],
)
def test_errors_carry_line_and_column(text: str, line: int, column: int, reason: str) -> None:
    with pytest.raises(MonitorSpecError) as info:
        PARSER.parse(text, "f.monitors")
    error = info.value
    assert (error.line, error.column) == (line, column), str(error)
    assert reason in error.reason
    assert str(error).startswith(f"f.monitors:{line}:{column}: ")


def test_unreadable_file(tmp_path: Path) -> None:
    with pytest.raises(MonitorSpecError, match="cannot read"):
        PARSER.parse_file(tmp_path / "missing.monitors")


def test_generate_requests() -> None:
    spec = PARSER.parse(
        "monitor a: true;\ngenerate for pick-up-box: effects, pre within 2500 ms;\n"
        "generate for drop-box: duration;"
    )
    first, second = spec.generate
    assert (first.operator, first.kinds, first.slack_ms, first.line) == (
        "pick-up-box",
        frozenset({Generated.EFFECTS, Generated.PRE}),
        2500,
        2,
    )
    assert (second.operator, second.kinds, second.slack_ms) == (
        "drop-box",
        frozenset({Generated.DURATION}),
        1000,
    )
    with pytest.raises(MonitorSpecError, match="unexpected") as info:
        PARSER.parse("generate for x: pre, effect;")
    assert (info.value.line, info.value.column) == (1, 22)
