"""Recovery operator specifications: parsed into frozen values; bad input at line and column."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_tst.recovery_spec import (
    DEFAULT_ATTEMPTS,
    DEFAULT_RECOVERY,
    Effect,
    EffectKind,
    RecoverySpecError,
    RecoverySpecParser,
)

PARSER = RecoverySpecParser()


def test_the_packaged_operators_parse() -> None:
    spec = PARSER.parse_file(DEFAULT_RECOVERY)
    assert set(spec.operators) == {
        "lower-lift-capacity",
        "carrier-too-heavy",
        "box-lost",
        "retry",
        "step-failed",
    }
    assert spec.operators["lower-lift-capacity"].effects == (
        Effect(EffectKind.LIFT_CAPACITY, "box", 0.8),
        Effect(EffectKind.RELEASE, "box"),
    )
    assert spec.operators["lower-lift-capacity"].attempts == 2
    assert spec.operators["box-lost"].effects == (Effect(EffectKind.LOST, "box"),)


@pytest.mark.parametrize(
    ("text", "effects", "attempts"),
    [
        ("recovery r: replan;", (Effect(EffectKind.REPLAN),), DEFAULT_ATTEMPTS),
        ("recovery r: lost(b), attempts 5;", (Effect(EffectKind.LOST, "b"),), 5),
        ("recovery r: release(c);", (Effect(EffectKind.RELEASE, "c"),), DEFAULT_ATTEMPTS),
        (
            "recovery r: lift-capacity = 0.5 * weight(c), replan;",
            (Effect(EffectKind.LIFT_CAPACITY, "c", 0.5), Effect(EffectKind.REPLAN)),
            DEFAULT_ATTEMPTS,
        ),
    ],
)
def test_operators(text: str, effects: tuple[Effect, ...], attempts: int) -> None:
    op = PARSER.parse(text).operators["r"]
    assert (op.effects, op.attempts) == (effects, attempts)


@pytest.mark.parametrize(
    ("text", "line", "column", "reason"),
    [
        ("recovery r: fly;", 1, 13, "unexpected"),
        ("recovery r: replan", 1, 19, "unexpected end"),
        ("# c\nrecovery r:\n  lift-capacity = 1.5 * weight(b);", 3, 3, "between 0 and 1"),
        ("recovery r: replan, attempts 0;", 1, 30, "attempts must be >= 1"),
        ("recovery r: replan;\nrecovery r: replan;", 2, 1, "declared twice"),
    ],
)
def test_bad_input_is_reported_at_its_position(
    text: str, line: int, column: int, reason: str
) -> None:
    with pytest.raises(RecoverySpecError) as caught:
        PARSER.parse(text, "x.recovery")
    assert (caught.value.line, caught.value.column) == (line, column)
    assert reason in caught.value.reason
    assert str(caught.value).startswith(f"x.recovery:{line}:{column}: ")


def test_an_unreadable_file_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(RecoverySpecError, match="cannot read"):
        PARSER.parse_file(tmp_path / "missing.recovery")
