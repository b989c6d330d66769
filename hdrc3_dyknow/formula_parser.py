"""Parser of the monitor formula language (``monitor_language.lark``) into :mod:`formula` trees.

Concrete syntax, loosest binding first::

    forall x in SORT: phi          exists x in SORT: phi      (body extends to the right)
    phi implies psi                                            (right-associative)
    phi or psi
    phi and psi
    phi until[a,b] psi                                         (right-associative)
    not phi    always[a,b] phi    eventually[a,b] phi
    term < term   (also <= > >= == = !=)
    term + term   term - term   term * term   term / term   -term
    true  false  3.5  p  carrying(av, box)  executing-climb(av)  EXEC  ( ... )

Intervals are ``[a,b]`` in milliseconds with ``b`` possibly ``inf``; an omitted interval means
``[0,inf]``. Identifiers may contain ``-`` when a letter follows (``executing-climb``), so a
subtraction of two fluents needs spaces: ``a - b``. ``#`` starts a comment.

Usage::

    parser = FormulaParser()              # builds the LALR tables once; reuse it
    phi = parser.parse("always speed(uav0) < 50")

Syntax errors raise :class:`FormulaSyntaxError` with the line, column, offending text and the
tokens that were expected there.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from pathlib import Path

import lark
from lark import Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken, VisitError
from lark.lexer import PatternStr
from lark.tree import Meta

from hdrc3_base.errors import ConfigError
from hdrc3_dyknow.formula import (
    Always,
    And,
    Arithmetic,
    ArithOp,
    Atom,
    CompareOp,
    Comparison,
    Constant,
    Eventually,
    FluentTerm,
    Formula,
    Implies,
    Interval,
    Negative,
    Not,
    Number,
    Or,
    Quantified,
    Quantifier,
    Term,
    Until,
)

GRAMMAR_PATH = Path(__file__).with_name("monitor_language.lark")

# Readable names of the grammar's pattern terminals in "expected ..." lists.
_TERMINAL_NAMES = {
    "NAME": "identifier",
    "NUMBER": "number",
    "COMPARE_OP": "comparison operator",
    "$END": "end of formula",
}
_FORMULA_TYPES = (
    Constant,
    Atom,
    Comparison,
    Not,
    And,
    Or,
    Implies,
    Always,
    Eventually,
    Until,
    Quantified,
)
_TERM_TYPES = (Number, FluentTerm, Negative, Arithmetic)


class FormulaSyntaxError(ConfigError):
    """A monitor formula does not parse.

    Attributes:
        source: Where the text came from (file name or ``<formula>``).
        line: 1-based line of the error.
        column: 1-based column of the error.
        text: The offending text (a token, a character or ``end of formula``).
        expected: Readable descriptions of what would have been accepted there.
        reason: Short description of the problem.

    """

    def __init__(
        self,
        reason: str,
        *,
        source: str,
        line: int,
        column: int,
        text: str,
        expected: tuple[str, ...] = (),
    ) -> None:
        self.reason = reason
        self.source = source
        self.line = line
        self.column = column
        self.text = text
        self.expected = expected
        message = f"{source}:{line}:{column}: {reason}"
        if expected:
            message += f"; expected one of: {', '.join(expected)}"
        super().__init__(message)


class FormulaParser:
    """Parses monitor formula text; holds the LALR tables, so build one and reuse it."""

    def __init__(self) -> None:
        self._lark = lark.Lark(
            GRAMMAR_PATH.read_text(encoding="utf-8"),
            parser="lalr",
            lexer="basic",
            propagate_positions=True,
            maybe_placeholders=True,
        )

    def parse(self, text: str, source: str = "<formula>") -> Formula:
        """Parse ``text`` into a formula tree.

        Args:
            text: Formula in the concrete syntax (see module docstring).
            source: Name of the text's origin, used in error messages.

        Raises:
            FormulaSyntaxError: The text is not a well-formed monitor formula.

        """
        try:
            tree = self._lark.parse(text)
        except UnexpectedInput as exc:
            raise self._syntax_error(exc, text, source) from None
        try:
            result = _TreeBuilder(source).transform(tree)
        except VisitError as exc:
            if isinstance(exc.orig_exc, FormulaSyntaxError):
                raise exc.orig_exc from None
            raise
        return _as_formula(result, source, 1, 1)

    def _syntax_error(self, exc: UnexpectedInput, text: str, source: str) -> FormulaSyntaxError:
        if isinstance(exc, UnexpectedToken) and exc.token.type == "$END":
            line, column = _end_position(text)
            return FormulaSyntaxError(
                "unexpected end of formula",
                source=source,
                line=line,
                column=column,
                text="end of formula",
                expected=self._describe(exc.expected),
            )
        if isinstance(exc, UnexpectedToken):
            return FormulaSyntaxError(
                f"unexpected {str(exc.token)!r}",
                source=source,
                line=exc.line,
                column=exc.column,
                text=str(exc.token),
                expected=self._describe(exc.expected),
            )
        if isinstance(exc, UnexpectedCharacters):
            return FormulaSyntaxError(
                f"unexpected character {exc.char!r}",
                source=source,
                line=exc.line,
                column=exc.column,
                text=exc.char,
                expected=self._describe(self._acceptable_after(text[: exc.pos_in_stream])),
            )
        line, column = _end_position(text)
        return FormulaSyntaxError(
            "unexpected end of formula", source=source, line=line, column=column, text=""
        )

    def _acceptable_after(self, prefix: str) -> set[str]:
        """Terminals the parser accepts after ``prefix`` (the lexer alone knows only all)."""
        interactive = self._lark.parse_interactive(prefix)
        try:
            interactive.exhaust_lexer()
        except UnexpectedInput:
            return set()
        accepted: set[str] = interactive.accepts()  # type: ignore[no-untyped-call]
        return accepted

    def _describe(self, terminals: Iterable[str]) -> tuple[str, ...]:
        names = []
        for name in terminals:
            if name in _TERMINAL_NAMES:
                names.append(_TERMINAL_NAMES[name])
                continue
            pattern = self._lark.get_terminal(name).pattern
            names.append(repr(pattern.value) if isinstance(pattern, PatternStr) else name)
        return tuple(sorted(set(names)))


def parse_formula(text: str, source: str = "<formula>") -> Formula:
    """Parse one formula with a fresh :class:`FormulaParser` (convenient, not for hot loops)."""
    return FormulaParser().parse(text, source)


def _end_position(text: str) -> tuple[int, int]:
    lines = text.split("\n")
    return len(lines), len(lines[-1]) + 1


def _as_formula(item: object, source: str, line: int, column: int) -> Formula:
    if isinstance(item, FluentTerm):
        return Atom(item)
    if isinstance(item, _FORMULA_TYPES):
        return item
    raise FormulaSyntaxError(
        f"value term {item} used as a formula (compare it, e.g. '{item} > 0')",
        source=source,
        line=line,
        column=column,
        text=str(item),
    )


def _as_term(item: object, source: str, line: int, column: int) -> Term:
    if isinstance(item, _TERM_TYPES):
        return item
    if isinstance(item, Atom):
        return item.fluent
    raise FormulaSyntaxError(
        f"formula {item} used as a value term",
        source=source,
        line=line,
        column=column,
        text=str(item),
    )


@v_args(meta=True)
class _TreeBuilder(Transformer[Token, object]):
    """Turns the lark parse tree into formula dataclasses, checking formula/term positions."""

    def __init__(self, source: str) -> None:
        super().__init__()
        self._source = source

    def _formula(self, item: object, meta: Meta) -> Formula:
        return _as_formula(item, self._source, meta.line, meta.column)

    def _term(self, item: object, meta: Meta) -> Term:
        return _as_term(item, self._source, meta.line, meta.column)

    def quantified(self, meta: Meta, children: list[object]) -> Formula:
        keyword, variable, sort, body = children
        return Quantified(
            Quantifier(str(keyword)), str(variable), str(sort), self._formula(body, meta)
        )

    def implies(self, meta: Meta, children: list[object]) -> Formula:
        left, right = children
        return Implies(self._formula(left, meta), self._formula(right, meta))

    def disjunction(self, meta: Meta, children: list[object]) -> Formula:
        return Or(tuple(self._formula(child, meta) for child in children))

    def conjunction(self, meta: Meta, children: list[object]) -> Formula:
        return And(tuple(self._formula(child, meta) for child in children))

    def until(self, meta: Meta, children: list[object]) -> Formula:
        left, interval, right = children
        return Until(
            interval if isinstance(interval, Interval) else Interval(),
            self._formula(left, meta),
            self._formula(right, meta),
        )

    def negation(self, meta: Meta, children: list[object]) -> Formula:
        return Not(self._formula(children[0], meta))

    def tense(self, meta: Meta, children: list[object]) -> Formula:
        keyword, interval, body = children
        bounds = interval if isinstance(interval, Interval) else Interval()
        operand = self._formula(body, meta)
        return Always(bounds, operand) if keyword == "always" else Eventually(bounds, operand)

    def interval(self, meta: Meta, children: list[Token]) -> Interval:
        lower, upper = (math.inf if token == "inf" else float(token) for token in children)
        if lower == math.inf:
            raise FormulaSyntaxError(
                "an interval's lower bound must be finite",
                source=self._source,
                line=meta.line,
                column=meta.column,
                text=str(children[0]),
            )
        return Interval(lower, upper)

    def comparison(self, meta: Meta, children: list[object]) -> Formula:
        left, op, right = children
        symbol = "==" if op == "=" else str(op)
        return Comparison(CompareOp(symbol), self._term(left, meta), self._term(right, meta))

    def arithmetic(self, meta: Meta, children: list[object]) -> Term:
        left, op, right = children
        return Arithmetic(ArithOp(str(op)), self._term(left, meta), self._term(right, meta))

    def negative(self, meta: Meta, children: list[object]) -> Term:
        return Negative(self._term(children[1], meta))

    def number(self, meta: Meta, children: list[Token]) -> Term:
        return Number(float(children[0]))

    def true(self, meta: Meta, children: list[object]) -> Formula:
        return Constant(True)

    def false(self, meta: Meta, children: list[object]) -> Formula:
        return Constant(False)

    def fluent(self, meta: Meta, children: list[Token | FluentTerm | None]) -> FluentTerm:
        name, *args = children
        return FluentTerm(
            str(name),
            tuple(
                arg if isinstance(arg, FluentTerm) else str(arg) for arg in args if arg is not None
            ),
        )

    def nested(self, meta: Meta, children: list[Token | FluentTerm | None]) -> FluentTerm:
        return self.fluent(meta, children)
