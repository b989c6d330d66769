"""A table of named Boolean conditions that other code sets and guards read.

Atomic conditions are implemented procedurally (chapter 6.1). Many are plain values that some
other part of the system keeps up to date (sensor checks, scripted runs, tests); this table turns
them into the zero-argument callables the interpreter binds its guards to.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from hdrc3_hcsm.errors import BindingError


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
