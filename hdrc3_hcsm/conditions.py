"""A table of named Boolean conditions that other code sets and guards read.

Atomic conditions are implemented procedurally (chapter 6.1). Many are plain values that some
other part of the system keeps up to date (sensor checks, scripted runs, tests); this table turns
them into the zero-argument callables the interpreter binds its guards to.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

from hdrc3_hcsm.errors import BindingError
from hdrc3_hcsm.model import And, CondRef, Guard, Not


class ConditionTable:
    """Named conditions, all False until set."""

    def __init__(self, names: Iterable[str]) -> None:
        self.values = dict.fromkeys(names, False)

    def set(self, name: str, value: bool = True) -> None:
        """Set condition ``name`` (one of the names given at construction)."""
        if name not in self.values:
            raise BindingError(f"unknown condition {name!r}")
        self.values[name] = value

    def callables(self) -> dict[str, Callable[[], bool]]:
        """One zero-argument callable per condition, reading the current value."""
        return {name: self._reader(name) for name in self.values}

    def _reader(self, name: str) -> Callable[[], bool]:
        return lambda: self.values[name]


def blocking_condition(guard: Guard, conditions: Mapping[str, Callable[[], bool]]) -> str:
    """Name the condition that makes ``guard`` false (the guard must be false).

    Conjunctions are read left to right, so a guard written most-general-first explains itself
    by its first failing conjunct; a disjunction is explained by its first operand; a negated
    condition by the condition that holds.
    """
    if isinstance(guard, CondRef):
        return guard.name
    if isinstance(guard, Not):
        return blocking_condition(guard.operand, {k: _negated(v) for k, v in conditions.items()})
    if isinstance(guard, And):
        failing = next(g for g in guard.operands if not evaluate(g, conditions))
        return blocking_condition(failing, conditions)
    return blocking_condition(guard.operands[0], conditions)


def evaluate(guard: Guard, conditions: Mapping[str, Callable[[], bool]]) -> bool:
    """The value of ``guard`` under ``conditions`` (by name)."""
    if isinstance(guard, CondRef):
        return conditions[guard.name]()
    if isinstance(guard, Not):
        return not evaluate(guard.operand, conditions)
    if isinstance(guard, And):
        return all(evaluate(g, conditions) for g in guard.operands)
    return any(evaluate(g, conditions) for g in guard.operands)


def _negated(condition: Callable[[], bool]) -> Callable[[], bool]:
    return lambda: not condition()
