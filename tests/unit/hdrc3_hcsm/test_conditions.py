"""Condition tables, guard evaluation and the condition that blocks a false guard."""

from __future__ import annotations

import pytest

from hdrc3_hcsm.conditions import ConditionTable, blocking_condition, evaluate
from hdrc3_hcsm.errors import BindingError
from hdrc3_hcsm.loader import load_text
from hdrc3_hcsm.model import Guard


def guard(text: str) -> Guard:
    """The guard of a one-transition model."""
    model = load_text(
        "model G on PFC; computers PFC; event E-EV = 1; condition A-CO, B-CO, C-CO;\n"
        f"automaton X Top {{ init S-ST; X.1: S-ST -> S-ST on E-EV [{text}]; }}\nroot Top;\n"
    )
    found = model.automata[0].transitions[0].guard
    assert found is not None
    return found


CASES = [
    # guard, true conditions, value, blocking condition (when false)
    ("A-CO AND B-CO AND C-CO", {"A-CO", "B-CO", "C-CO"}, True, None),
    ("A-CO AND B-CO AND C-CO", {"A-CO", "C-CO"}, False, "B-CO"),
    ("A-CO AND B-CO AND C-CO", set(), False, "A-CO"),
    ("A-CO AND (B-CO OR C-CO)", {"A-CO"}, False, "B-CO"),
    ("A-CO OR B-CO", set(), False, "A-CO"),
    ("A-CO OR B-CO", {"B-CO"}, True, None),
    ("NOT A-CO", {"A-CO"}, False, "A-CO"),
    ("A-CO AND NOT B-CO", {"A-CO", "B-CO"}, False, "B-CO"),
]


@pytest.mark.parametrize(("text", "true", "value", "blocking"), CASES)
def test_guard_value_and_blocking_condition(
    text: str, true: set[str], value: bool, blocking: str | None
) -> None:
    table = ConditionTable(["A-CO", "B-CO", "C-CO"])
    for name in true:
        table.set(name)
    conditions = table.callables()
    assert evaluate(guard(text), conditions) is value
    if blocking is not None:
        assert blocking_condition(guard(text), conditions) == blocking


def test_unknown_condition_is_refused() -> None:
    with pytest.raises(BindingError):
        ConditionTable(["A-CO"]).set("Z-CO")
