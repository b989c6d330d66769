"""Parser: ``.tst`` text -> :class:`~hdrc3_tst.syntax.TstFile` through the lark grammar.

Bad input never raises out of :func:`parse_text`: lark errors become diagnostics with
``file:line:column``, the offending text and the tokens that were expected. The builder runs
inside the LALR parse (:mod:`hdrc3_base.inline_parsing`), not on a lark tree afterwards.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import lark
from lark import Token

from hdrc3_base.inline_parsing import BadValue, InlineBuilder, InlineParser
from hdrc3_base.syntax_errors import describe
from hdrc3_deliberative.mission_syntax import (
    AgentsDecl,
    AreaDecl,
    Cmp,
    Comparison,
    ConsRef,
    LinExpr,
    Membership,
    Name,
    Number,
    PathDecl,
    PointDecl,
    SourcePos,
    Term,
    WorldDecl,
)
from hdrc3_tst.diagnostics import Diagnostic
from hdrc3_tst.syntax import (
    ActionTask,
    CallTask,
    ConcurrentTask,
    Condition,
    ConsDef,
    Constraint,
    ForeachTask,
    GoalTask,
    IfTask,
    SequenceTask,
    TstDef,
    TstFile,
    WhileTask,
)


class ParseStatus(enum.Enum):
    """Outcome of parsing one file."""

    OK = "ok"
    SYNTAX_ERROR = "syntax_error"
    UNREADABLE = "unreadable"


@dataclass(frozen=True)
class ParseResult:
    """The syntax tree (when the syntax was fine) and the diagnostics."""

    status: ParseStatus
    tree: TstFile | None
    diagnostics: tuple[Diagnostic, ...]


@cache
def lark_parser() -> InlineParser:
    """The LALR parser of ``tst.lark`` with its builder (built once per process)."""
    grammar = resources.files("hdrc3_tst").joinpath("tst.lark").read_text(encoding="utf-8")
    # Positions come from the tokens (propagate_positions would cost 45 % of the parse).
    return InlineParser.of(grammar, _Builder())


class _Builder(InlineBuilder):
    """Turn each reduction into frozen dataclasses, keeping positions."""

    def _pos(self, item: Token) -> SourcePos:
        return SourcePos(self.file, getattr(item, "line", 0) or 0, getattr(item, "column", 0) or 0)

    # --- small pieces -------------------------------------------------------------------
    def number(self, children: list[Token]) -> Number:
        value = float(children[0])
        if not math.isfinite(value):
            self.reject(f"number {children[0]!s} is out of range")
        return Number(value, self._pos(children[0]))

    def neg_number(self, children: list[Token]) -> Number:
        number = self.number(children)
        return Number(-number.value, number.pos)

    # Lists are left-recursive rules that keep their separators (tst.lark): the first
    # element starts a list, each further one is appended; the rule using the list makes
    # it a tuple.
    @staticmethod
    def _append(children: list[Any]) -> list[Any]:
        if len(children) == 1:
            return children
        children[0].append(children[2])
        return children[0]  # type: ignore[no-any-return]

    name_list = _append
    xy_list = _append
    children = _append

    def args(self, children: list[Any]) -> list[Name | Number]:
        """``[list ","] (NAME | NUMBER | "-" NUMBER)``: the list with the argument appended."""
        out: list[Name | Number] = children[0] if isinstance(children[0], list) else []
        item: Token = children[-1]
        if item.type == "NAME":
            out.append(Name(str(item), self._pos(item)))
        elif len(children) in (2, 4):  # "-" NUMBER
            out.append(self.neg_number([item]))
        else:
            out.append(self.number([item]))
        return out

    @staticmethod
    def expr(children: list[Any]) -> list[Any]:
        """``term (ADDOP term)*`` as one list (:meth:`_linear` reads it)."""
        if len(children) == 1:
            return children
        children[0] += children[1:]
        return children[0]  # type: ignore[no-any-return]

    def xy(self, children: list[Number]) -> tuple[float, float]:
        return (children[0].value, children[1].value)

    def xyz(self, children: list[Number]) -> tuple[float, float, float]:
        return (children[0].value, children[1].value, children[2].value)

    def with_vars(self, children: list[list[Token]]) -> list[Token]:
        return children[0]

    def timepoint(self, children: list[Token]) -> str:
        return str(children[0])

    # --- constraints --------------------------------------------------------------------
    def const_term(self, children: list[Token]) -> Term:
        return Term(self.number(children).value)

    def var_term(self, children: list[Token]) -> Term:
        return Term(1.0, Name(str(children[0]), self._pos(children[0])))

    def scaled_term(self, children: list[Any]) -> Term:
        coef = self.number(children).value
        return Term(coef, Name(str(children[1]), self._pos(children[1])))

    def neg_term(self, children: list[Term]) -> Term:
        return Term(-children[0].coef, children[0].name)

    @staticmethod
    def _linear(items: list[Any]) -> LinExpr:
        """``term (ADDOP term)*`` as collected by the ``expr`` list."""
        terms = [items[0]]
        for op, term in zip(items[1::2], items[2::2], strict=True):
            terms.append(term if op == "+" else Term(-term.coef, term.name))
        return LinExpr(tuple(terms))

    def comparison(self, children: list[Any]) -> Comparison:
        # At the operator: expressions may start with a constant, which keeps no position.
        op: Token = children[1]
        left, right = self._linear(children[0]), self._linear(children[2])
        return Comparison(left, Cmp(str(op)), right, self._pos(op))

    def membership(self, children: list[Any]) -> Membership:
        var = Name(str(children[0]), self._pos(children[0]))
        return Membership(var, tuple(children[1]), var.pos)

    def cons_ref(self, children: list[Token]) -> ConsRef:
        return ConsRef(Name(str(children[0]), self._pos(children[0])))

    def true_cons(self, children: list[Any]) -> None:
        return None

    @staticmethod
    def cons(children: list[Any]) -> list[Constraint]:
        # `true` is the neutral element (TALF: an omitted where is `where TRUE`).
        if len(children) == 1:
            return [] if children[0] is None else children
        if children[2] is not None:
            children[0].append(children[2])
        return children[0]  # type: ignore[no-any-return]

    def where_clause(self, children: list[list[Constraint]]) -> tuple[Constraint, ...]:
        return tuple(children[0])

    def cond(self, children: list[Any]) -> Condition:
        negated, name, args = children
        return Condition(str(name), _tuple(args), negated is not None, None, self._pos(name))

    # --- tasks --------------------------------------------------------------------------
    def action(self, children: list[Any]) -> ActionTask:
        return ActionTask(str(children[0]), _tuple(children[1]), self._pos(children[0]))

    def goal(self, children: list[Any]) -> GoalTask:
        return GoalTask(str(children[0]), _tuple(children[1]), self._pos(children[0]))

    def call(self, children: list[Any]) -> CallTask:
        return CallTask(str(children[0]), _tuple(children[1]), self._pos(children[0]))

    def sequence(self, children: list[list[TstDef]]) -> SequenceTask:
        return SequenceTask(tuple(children[0]))

    def concurrent(self, children: list[list[TstDef]]) -> ConcurrentTask:
        return ConcurrentTask(tuple(children[0]))

    @staticmethod
    def _timed(cond: Condition, time: str | None) -> Condition:
        return Condition(cond.name, cond.args, cond.negated, time, cond.pos)

    def if_task(self, children: list[Any]) -> IfTask:
        time, cond, then, orelse = children
        return IfTask(self._timed(cond, time), then, orelse)

    def while_task(self, children: list[Any]) -> WhileTask:
        time, cond, body = children
        return WhileTask(self._timed(cond, time), body)

    def foreach_task(self, children: list[Any]) -> ForeachTask:
        names, time, cond, body = children
        return ForeachTask(_names(names), self._timed(cond, time), body)

    def _tst(self, children: list[Any]) -> TstDef:
        name, params, with_vars, task, *rest = children
        where = rest[0] if rest and rest[0] is not None else ()
        with_names = () if with_vars is None else _names(with_vars)
        return TstDef(str(name), _names(params), with_names, task, where, self._pos(name))

    tst = _tst
    child = _tst

    # --- declarations -------------------------------------------------------------------
    def world_decl(self, children: list[Token]) -> WorldDecl:
        return WorldDecl(str(children[0]), self._pos(children[0]))

    def agents_decl(self, children: list[list[Token]]) -> AgentsDecl:
        return AgentsDecl(_names(children[0]), self._pos(children[0][0]))

    def area_decl(self, children: list[Any]) -> AreaDecl:
        return AreaDecl(str(children[0]), tuple(children[1]), self._pos(children[0]))

    def place_alt(self, children: list[Any]) -> tuple[str, float]:
        return (str(children[0]), children[1].value)

    def point_decl(self, children: list[Any]) -> PointDecl:
        name, where, pos = str(children[0]), children[1], self._pos(children[0])
        if isinstance(where[0], str):
            return PointDecl(name, None, where[0], where[1], pos)
        return PointDecl(name, where, None, 0.0, pos)

    def path_decl(self, children: list[Any]) -> PathDecl:
        return PathDecl(str(children[0]), _names(children[1]), self._pos(children[0]))

    def cons_def(self, children: list[Any]) -> ConsDef:
        return ConsDef(str(children[0]), tuple(children[1]), self._pos(children[0]))

    def start(self, children: list[Any]) -> TstFile:
        return TstFile(tuple(children))


def _tuple(items: list[Any] | None) -> tuple[Any, ...]:
    """An optional list (``[args]``) as a tuple."""
    return () if items is None else tuple(items)


def _names(tokens: list[Token]) -> tuple[str, ...]:
    return tuple(map(str, tokens))


def _syntax_diagnostic(exc: lark.exceptions.UnexpectedInput, file: str, text: str) -> Diagnostic:
    problem = describe(exc, lark_parser().lark, text)
    message = problem.message
    if "'where'" in problem.expected and problem.found in ("';'", "end of file"):
        message += " (a composite child ends with a where clause, `where true` if none)"
    return Diagnostic("E001", message, SourcePos(file, problem.line, problem.column))


def parse_text(text: str, file: str = "<string>") -> ParseResult:
    """Parse ``.tst`` text; syntax errors come back as diagnostics, never as exceptions."""
    try:
        tree = lark_parser().parse(text, file)
    except lark.exceptions.UnexpectedInput as exc:
        return ParseResult(ParseStatus.SYNTAX_ERROR, None, (_syntax_diagnostic(exc, file, text),))
    except BadValue as exc:  # only numbers too large for a float
        diag = Diagnostic("E002", f"bad value: {exc}", SourcePos(file, 0, 0))
        return ParseResult(ParseStatus.SYNTAX_ERROR, None, (diag,))
    return ParseResult(ParseStatus.OK, tree, ())


def parse_file(path: str | Path) -> ParseResult:
    """Read and parse a ``.tst`` file; an unreadable file gives a diagnostic, not an exception."""
    file = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        diag = Diagnostic("E000", f"cannot read file: {exc}", SourcePos(file, 0, 0))
        return ParseResult(ParseStatus.UNREADABLE, None, (diag,))
    return parse_text(text, file)
