"""Reader of recovery operator specifications (HDRC3 chapter 9.3.1, ``recovery.lark``).

A monitor formula names the recovery operator to run when it is violated (``recovery NAME`` in
a monitor specification). An operator says which of the planner's assumptions the violation
refutes, and how many failures on the same fault are tolerated before the goal gives up::

    recovery lower-lift-capacity: lift-capacity = 0.8 * weight(box), attempts 2;
    recovery box-lost: lost(box);
    recovery retry: replan;

``lift-capacity = F * weight(P)``: the helicopter lifts only ``F`` times the load held by the
violated formula's parameter ``P`` (0 < F < 1: the load it failed with is out of reach);
``lost(P)``: the load ``P`` lies below where the aircraft was at the violation; ``replan``:
nothing learnt, plan again. Every error is a :class:`RecoverySpecError` with
``source:line:column``.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

import lark
from lark import Token, Tree
from lark.exceptions import UnexpectedInput

from hdrc3_base.errors import SourceError

GRAMMAR_PATH = Path(__file__).with_name("recovery.lark")
DEFAULT_RECOVERY = Path(__file__).with_name("default.recovery")
"""The packaged operators (the ones the default monitor specification names)."""
DEFAULT_ATTEMPTS = 3
"""Failures on one fault before the goal gives up, unless the operator says otherwise."""


class RecoverySpecError(SourceError):
    """A recovery specification is malformed; the message starts with ``source:line:column``."""


class EffectKind(enum.Enum):
    """What a recovery operator changes in the planning problem."""

    LIFT_CAPACITY = "lift-capacity"
    LOST = "lost"
    RELEASE = "release"
    """Not a change of the problem but of the world: the hook lets go of the load and winds in
    before the goal is planned again (a load gripped but not lifted must not be flown off)."""
    REPLAN = "replan"


@dataclass(frozen=True, slots=True)
class Effect:
    """One change: its kind, the formula parameter holding the load, the factor."""

    kind: EffectKind
    parameter: str = ""
    factor: float = 1.0


@dataclass(frozen=True, slots=True)
class RecoveryOperator:
    """A named recovery operator."""

    name: str
    effects: tuple[Effect, ...]
    attempts: int = DEFAULT_ATTEMPTS
    """Failures on one fault that are recovered from; the next one gives up."""
    line: int = 1
    column: int = 1


@dataclass(frozen=True, slots=True)
class RecoverySpec:
    """Parsed operators by name."""

    operators: Mapping[str, RecoveryOperator]
    source: str = "<recovery spec>"


class RecoverySpecParser:
    """Parses recovery specifications; holds the LALR tables, so build one and reuse it."""

    def __init__(self) -> None:
        self._lark = lark.Lark(
            GRAMMAR_PATH.read_text(encoding="utf-8"),
            parser="lalr",
            propagate_positions=True,
            maybe_placeholders=True,
        )

    def parse(self, text: str, source: str = "<recovery spec>") -> RecoverySpec:
        """Parse ``text``.

        Raises:
            RecoverySpecError: Syntax error, bad factor or count, duplicate name (with position).

        """
        try:
            tree = self._lark.parse(text)
        except UnexpectedInput as exc:
            token = getattr(exc, "token", None)
            found = token if token is not None else getattr(exc, "char", "")
            line, column = exc.line, exc.column
            if line < 1 or getattr(token, "type", "") == "$END":
                lines = text.rstrip().split("\n")
                line, column, found = len(lines), len(lines[-1]) + 1, ""
            reason = f"unexpected {str(found)!r}" if found else "unexpected end of specification"
            raise RecoverySpecError(reason, source, line, column) from None
        operators: dict[str, RecoveryOperator] = {}
        for statement in tree.children:
            assert isinstance(statement, Tree)
            op = self._operator(statement, source)
            if op.name in operators:
                raise RecoverySpecError(
                    f"recovery operator {op.name!r} is declared twice", source, op.line, op.column
                )
            operators[op.name] = op
        return RecoverySpec(MappingProxyType(operators), source)

    def parse_file(self, path: Path) -> RecoverySpec:
        """Read and parse a specification file.

        Raises:
            RecoverySpecError: The file cannot be read or is malformed.

        """
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise RecoverySpecError(f"cannot read the file: {exc}", str(path), 1, 1) from None
        return self.parse(text, str(path))

    @staticmethod
    def _operator(tree: Tree[Token], source: str) -> RecoveryOperator:
        name, *rest = tree.children
        attempts_token = rest[-1]
        effects: list[Effect] = []
        for item in rest[:-1]:
            assert isinstance(item, Tree)
            kind = EffectKind(str(item.data).replace("_", "-"))
            if kind is EffectKind.LIFT_CAPACITY:
                factor_token, parameter = item.children
                factor = float(str(factor_token))
                if not 0.0 < factor < 1.0:
                    raise RecoverySpecError(
                        f"the lift-capacity factor must be between 0 and 1, got {factor:g}",
                        source,
                        item.meta.line,
                        item.meta.column,
                    )
                effects.append(Effect(kind, str(parameter), factor))
            elif kind in (EffectKind.LOST, EffectKind.RELEASE):
                effects.append(Effect(kind, str(item.children[0])))
            else:
                effects.append(Effect(kind))
        attempts = DEFAULT_ATTEMPTS
        if isinstance(attempts_token, Token):
            attempts = int(str(attempts_token))
            if attempts < 1:
                raise RecoverySpecError(
                    f"attempts must be >= 1, got {attempts}",
                    source,
                    attempts_token.line or tree.meta.line,
                    attempts_token.column or tree.meta.column,
                )
        return RecoveryOperator(
            str(name), tuple(effects), attempts, tree.meta.line, tree.meta.column
        )
