"""Reader of execution monitor specifications (HDRC3 chapter 9.3, ``monitor_spec.lark``).

A specification says how often states are synthesised from DyKnow streams and lists the monitor
formulas: *global* ones, active for the whole execution, and *operator-specific* ones, activated
each time a step of their operator starts, with the operator's arguments bound (Example 9.2)::

    states period 40 ms, max_delay 200 ms, stale 1000 ms;
    monitor speed_limit brake: always forall av in AV: speed(av) <= 12;
    monitor climbed for climb(av): EXEC until altitude(av) >= 7.0;
    monitor pickup for pickup-box(av, box) recovery retry_pickup:
        eventually[0,5000] always[0,1000] carrying(av, box);
    monitor held for pickup-box(av, box) persistent:
        EXEC until[0,5000] (carrying(av, box) until executing-putdown-box(av, box));

Options: ``recovery NAME`` names the recovery operator to run on a violation (§9.3.1),
``brake`` asks for an emergency brake, ``persistent`` keeps an operator-specific formula active
after its step ends until it is decided (Example 9.4 outlives its pick-up); otherwise it is
retired after the first state at or after the step's end. The first parameter of an operator is
the agent executing it. Formulas use the language of :mod:`hdrc3_dyknow.formula_parser`.

Every error is a :class:`MonitorSpecError` with ``source:line:column``; a formula's syntax error
is reported at its position in the file.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from pathlib import Path

import lark
from lark import Token, Tree
from lark.exceptions import UnexpectedInput

from hdrc3_base.errors import SourceError
from hdrc3_dyknow.formula import Formula
from hdrc3_dyknow.formula_parser import FormulaParser, FormulaSyntaxError
from hdrc3_platform_server.data_interface import DI_RATE_HZ

GRAMMAR_PATH = Path(__file__).with_name("monitor_spec.lark")
DEFAULT_SPEC = Path(__file__).with_name("default.monitors")
"""The packaged specification (robust speed limit, Example 9.3)."""


class MonitorSpecError(SourceError):
    """A monitor specification is malformed; the message starts with ``source:line:column``."""


class Generated(enum.Enum):
    """Conditions of an operator whose monitor formulas can be generated (§9.3)."""

    PRE = "pre"
    PREVAIL = "prevail"
    EFFECTS = "effects"
    DURATION = "duration"


@dataclass(frozen=True, slots=True)
class GenerateDecl:
    """``generate for OP: kinds [within N ms];`` -- flags for :mod:`monitor_generation`."""

    operator: str
    kinds: frozenset[Generated]
    slack_ms: int = 1000
    line: int = 1
    column: int = 1


@dataclass(frozen=True, slots=True)
class StateSettings:
    """How states are synthesised from streams (ms).

    Attributes:
        period_ms: One state every period, on the grid ``k * period_ms``. By default the
            Data Interface's own period (25 Hz: 40 ms): on its grid a state never waits for a
            later sample and a violation is seen within the formula's bound plus one period.
        max_delay_ms: How long a state waits for late samples (§9.3.2: "delaying state
            generation slightly to allow values to propagate").
        stale_ms: A stream without a sample for longer than this is stale: its value is
            missing and a stale-data alarm is raised.

    """

    period_ms: int = round(1000 / DI_RATE_HZ)
    max_delay_ms: int = 200
    stale_ms: int = 1000


@dataclass(frozen=True, slots=True)
class MonitorDecl:
    """One monitor formula of a specification.

    Attributes:
        name: Unique name within the specification.
        formula: The parsed formula.
        text: The formula as written.
        operator: Operator (action type) that activates it; "" for a global formula.
        parameters: The operator's parameter names; the first is the executing agent.
        recovery: Recovery operator to run on a violation ("" for none).
        brake: Whether a violation requires an emergency brake.
        persistent: Keep an operator formula after its step ends, until decided.
        line: Line of the declaration.
        column: Column of the declaration.

    """

    name: str
    formula: Formula
    text: str
    operator: str = ""
    parameters: tuple[str, ...] = ()
    recovery: str = ""
    brake: bool = False
    persistent: bool = False
    line: int = 1
    column: int = 1

    @property
    def is_global(self) -> bool:
        """True for a formula active for the whole execution."""
        return not self.operator


@dataclass(frozen=True, slots=True)
class MonitorSpec:
    """A parsed specification: state settings and monitor declarations in file order."""

    settings: StateSettings = field(default_factory=StateSettings)
    monitors: tuple[MonitorDecl, ...] = ()
    source: str = "<monitor spec>"
    generate: tuple[GenerateDecl, ...] = ()
    """Flags for formulas to generate from the planning domain (``monitor_generation.expand``)."""

    def for_operator(self, operator: str) -> tuple[MonitorDecl, ...]:
        """Declarations activated by steps of ``operator``."""
        return tuple(decl for decl in self.monitors if decl.operator == operator)


class MonitorSpecParser:
    """Parses monitor specifications; holds the LALR tables, so build one and reuse it."""

    def __init__(self, formula_parser: FormulaParser | None = None) -> None:
        self._lark = lark.Lark(
            GRAMMAR_PATH.read_text(encoding="utf-8"),
            parser="lalr",
            lexer="contextual",
            propagate_positions=True,
            maybe_placeholders=True,
        )
        self._formulas = formula_parser or FormulaParser()

    def parse(self, text: str, source: str = "<monitor spec>") -> MonitorSpec:
        """Parse ``text``.

        Raises:
            MonitorSpecError: Syntax error, bad setting or duplicate name (with position).

        """
        try:
            tree = self._lark.parse(text)
        except UnexpectedInput as exc:
            line, column = exc.line, exc.column
            token = getattr(exc, "token", None)
            found = token if token is not None else getattr(exc, "char", "")
            if line < 1 or getattr(token, "type", "") == "$END":
                lines = text.rstrip().split("\n")
                line, column, found = len(lines), len(lines[-1]) + 1, ""
            raise MonitorSpecError(
                f"unexpected {str(found)!r}" if found else "unexpected end of specification",
                source,
                line,
                column,
            ) from None
        settings = StateSettings()
        monitors: list[MonitorDecl] = []
        generate: list[GenerateDecl] = []
        for statement in tree.children:
            assert isinstance(statement, Tree)
            if statement.data == "states":
                settings = self._settings(statement, settings, source)
            elif statement.data == "generate":
                generate.append(self._generate(statement))
            else:
                decl = self._monitor(statement, source)
                if any(other.name == decl.name for other in monitors):
                    raise MonitorSpecError(
                        f"monitor {decl.name!r} is declared twice", source, decl.line, decl.column
                    )
                monitors.append(decl)
        return MonitorSpec(settings, tuple(monitors), source, tuple(generate))

    def parse_file(self, path: Path) -> MonitorSpec:
        """Read and parse a specification file.

        Raises:
            MonitorSpecError: The file cannot be read or is malformed.

        """
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise MonitorSpecError(f"cannot read the file: {exc}", str(path), 1, 1) from None
        return self.parse(text, str(path))

    @staticmethod
    def _settings(tree: Tree[Token], settings: StateSettings, source: str) -> StateSettings:
        values = {
            "period": settings.period_ms,
            "max_delay": settings.max_delay_ms,
            "stale": settings.stale_ms,
        }
        for item in tree.children:
            assert isinstance(item, Tree)
            values[str(item.data)] = int(str(item.children[0]))
        if values["period"] <= 0 or values["stale"] <= 0:
            raise MonitorSpecError(
                f"period and stale must be > 0 ms, got {values['period']} and {values['stale']}",
                source,
                tree.meta.line,
                tree.meta.column,
            )
        return StateSettings(values["period"], values["max_delay"], values["stale"])

    @staticmethod
    def _generate(tree: Tree[Token]) -> GenerateDecl:
        operator, *rest = tree.children
        kinds = frozenset(
            Generated(str(item.children[0])) for item in rest if isinstance(item, Tree)
        )
        within = rest[-1]
        return GenerateDecl(
            str(operator),
            kinds,
            int(str(within)) if isinstance(within, Token) else 1000,
            tree.meta.line,
            tree.meta.column,
        )

    def _monitor(self, tree: Tree[Token], source: str) -> MonitorDecl:
        name, operator, *rest = tree.children
        formula_token = rest[-1]
        assert isinstance(formula_token, Token) and isinstance(name, Token)
        options = {str(item.data): item.children for item in rest[:-1] if isinstance(item, Tree)}
        action = ""
        parameters: tuple[str, ...] = ()
        if isinstance(operator, Tree):
            head, *params = operator.children
            action = str(head)
            parameters = tuple(str(p) for p in params if p is not None)
            if not parameters:
                raise MonitorSpecError(
                    f"operator {action!r} needs at least the agent parameter",
                    source,
                    operator.meta.line,
                    operator.meta.column,
                )
            if len(set(parameters)) != len(parameters):
                raise MonitorSpecError(
                    f"operator {action!r} repeats a parameter",
                    source,
                    operator.meta.line,
                    operator.meta.column,
                )
        text = str(formula_token)
        stripped = text.lstrip()
        skipped = text[: len(text) - len(stripped)]
        line = (formula_token.line or 1) + skipped.count("\n")
        column = (
            len(skipped) - skipped.rfind("\n") if "\n" in skipped else (formula_token.column or 1)
        ) + (0 if "\n" in skipped else len(skipped))
        formula = self._formula(stripped.rstrip(), source, line, column)
        return MonitorDecl(
            name=str(name),
            formula=formula,
            text=" ".join(stripped.split()),
            operator=action,
            parameters=parameters,
            recovery=str(options["recovery"][0]) if "recovery" in options else "",
            brake="brake" in options,
            persistent="persistent" in options,
            line=tree.meta.line,
            column=tree.meta.column,
        )

    def _formula(self, text: str, source: str, line: int, column: int) -> Formula:
        try:
            return self._formulas.parse(text, source)
        except FormulaSyntaxError as exc:
            # Positions inside the formula, shifted to where the formula starts in the file.
            at_line = line + exc.line - 1
            at_column = exc.column + (column - 1 if exc.line == 1 else 0)
            reason = exc.reason
            if exc.expected:
                reason += f"; expected one of: {', '.join(exc.expected)}"
            raise MonitorSpecError(reason, source, at_line, at_column) from None
