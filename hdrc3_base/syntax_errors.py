"""A lark syntax error as its place and one readable sentence, for every language of the stack.

``unexpected ';'; expected one of: '(', NAME`` at the line and column where it happened. Literal
terminals are shown as their text and pattern terminals by name; the end of the text is "end
of file", placed after its last character. The HCSM, TST and TALF parsers wrap the result in
their own diagnostics (their codes and hints differ).
"""

from __future__ import annotations

from dataclasses import dataclass

import lark

MOST_EXPECTED = 16
"""Expected terminals named at most (sorted)."""


@dataclass(frozen=True)
class SyntaxProblem:
    """Where a text stops following its grammar, and why."""

    line: int
    column: int
    message: str
    expected: tuple[str, ...]
    """The terminals that would have been accepted, as displayed (all of them)."""
    found: str
    """What was there instead: ``';'``, or ``end of file``."""


def _display(parser: lark.Lark, terminal: str) -> str:
    """A literal terminal as its text (``';'``), a pattern terminal by its name."""
    try:
        pattern = parser.get_terminal(terminal).pattern
    except KeyError:
        return terminal
    if isinstance(pattern, lark.lexer.PatternStr):
        return repr(pattern.value)
    return terminal


def describe(
    exc: lark.exceptions.UnexpectedInput, parser: lark.Lark, text: str, most: int = MOST_EXPECTED
) -> SyntaxProblem:
    """The place and sentence of a syntax error ``parser`` raised on ``text``."""
    line = int(getattr(exc, "line", 0) or 0)
    column = int(getattr(exc, "column", 0) or 0)
    names = getattr(exc, "expected", None) or getattr(exc, "allowed", None) or ()
    expected = tuple(sorted({_display(parser, name) for name in names}))
    if isinstance(exc, lark.exceptions.UnexpectedCharacters):
        at = exc.pos_in_stream or 0
        found = repr(text[at]) if at < len(text) else "end of file"
    elif isinstance(exc, lark.exceptions.UnexpectedToken) and exc.token.type != "$END":
        found = repr(str(exc.token))
    else:
        found = "end of file"
        line = text.count("\n") + 1
        column = len(text) - text.rfind("\n")
    message = f"unexpected {found}"
    if expected:
        message += "; expected one of: " + ", ".join(expected[:most])
    return SyntaxProblem(line, column, message, expected, found)
