"""Parser: ``.talf`` text -> :class:`~hdrc3_deliberative.talf_syntax.TalfFile` (``talf.lark``).

Bad input never raises out of :func:`parse_text`: lark errors become diagnostics with
``file:line:column``, the offending text and the tokens that were expected. Names are checked
afterwards (:mod:`hdrc3_deliberative.talf_check`). The builder runs inside the LALR parse
(:mod:`hdrc3_base.inline_parsing`), not on a lark tree afterwards.
"""

from __future__ import annotations

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
from hdrc3_deliberative.talf_diagnostics import TalfDiagnostic, TalfStatus
from hdrc3_deliberative.talf_formulas import (
    And,
    Atom,
    Exists,
    Forall,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    TrueF,
    conj,
)
from hdrc3_deliberative.talf_syntax import (
    ActionTerm,
    CAct,
    CompositeSpec,
    Concurrent,
    ConstraintDef,
    Foreach,
    If,
    Interval,
    Mission,
    OpenDecl,
    Sequence,
    TalfFile,
    While,
)


@dataclass(frozen=True)
class ParseResult:
    """The syntax tree (when the syntax was fine) and the diagnostics."""

    status: TalfStatus
    tree: TalfFile | None
    diagnostics: tuple[TalfDiagnostic, ...] = ()


@cache
def lark_parser() -> InlineParser:
    """The LALR parser of ``talf.lark`` with its builder (built once per process)."""
    grammar = resources.files("hdrc3_deliberative").joinpath("talf.lark").read_text("utf-8")
    return InlineParser.of(grammar, _Builder())


def retime(formula: Formula, time: str) -> Formula:
    """Give the untimed atoms of ``formula`` the timepoint ``time`` (inner ``[t]`` wins)."""
    if isinstance(formula, Atom):
        if formula.time is not None:
            return formula
        return Atom(formula.name, formula.args, time, formula.pos)
    if isinstance(formula, Not):
        return Not(retime(formula.arg, time))
    if isinstance(formula, And):
        return And(tuple(retime(a, time) for a in formula.args))
    if isinstance(formula, Or):
        return Or(tuple(retime(a, time) for a in formula.args))
    if isinstance(formula, Implies | Iff):
        return type(formula)(retime(formula.left, time), retime(formula.right, time))
    if isinstance(formula, Exists | Forall):
        return type(formula)(formula.vars, retime(formula.body, time))
    return formula


class _Builder(InlineBuilder):
    """Turn each reduction into frozen dataclasses, keeping positions."""

    def _pos(self, token: Token) -> SourcePos:
        return SourcePos(
            self.file, getattr(token, "line", 0) or 0, getattr(token, "column", 0) or 0
        )

    def _name(self, token: Token) -> Name:
        return Name(str(token), self._pos(token))

    # --- small pieces -------------------------------------------------------------------
    def number(self, children: list[Token]) -> Number:
        value = float(children[0])
        if not math.isfinite(value):
            self.reject(f"{self._pos(children[0])}: number {children[0]!s} is out of range")
        return Number(value)

    def neg_number(self, children: list[Token]) -> Number:
        return Number(-self.number(children).value)

    def name_arg(self, children: list[Token]) -> Name:
        return self._name(children[0])

    def args(self, children: list[Any]) -> tuple[Any, ...]:
        return tuple(children)

    def name_list(self, children: list[Token]) -> tuple[str, ...]:
        return tuple(str(c) for c in children)

    def xy(self, children: list[Number]) -> tuple[float, float]:
        return (children[0].value, children[1].value)

    def xyz(self, children: list[Number]) -> tuple[float, float, float]:
        return (children[0].value, children[1].value, children[2].value)

    def interval(self, children: list[Token]) -> tuple[Interval, SourcePos]:
        return Interval(str(children[0]), str(children[1])), self._pos(children[0])

    def timepoint(self, children: list[Token]) -> str:
        return str(children[0])

    def label(self, children: list[Token]) -> Token:
        return children[0]

    def agent(self, children: list[Token]) -> str:
        return str(children[0])

    def with_vars(self, children: list[tuple[str, ...]]) -> tuple[str, ...]:
        return children[0]

    def where_clause(self, children: list[Formula]) -> Formula:
        return children[0]

    # --- formulas -----------------------------------------------------------------------
    def const_term(self, children: list[Number]) -> Term:
        return Term(children[0].value)

    def var_term(self, children: list[Token]) -> Term:
        return Term(1.0, self._name(children[0]))

    def scaled_term(self, children: list[Any]) -> Term:
        return Term(children[0].value, self._name(children[1]))

    def neg_term(self, children: list[Term]) -> Term:
        return Term(-children[0].coef, children[0].name)

    def expr(self, children: list[Any]) -> LinExpr:
        terms = [children[0]]
        for op, term in zip(children[1::2], children[2::2], strict=True):
            terms.append(term if str(op) == "+" else Term(-term.coef, term.name))
        return LinExpr(tuple(terms))

    def f_chain(self, children: list[Any]) -> Formula:
        links = [
            Comparison(left, Cmp(str(op)), right, self._pos(op))
            for left, op, right in zip(children[0::2], children[1::2], children[2::2], strict=False)
        ]
        return conj(*links)

    def f_member(self, children: list[Any]) -> Membership:
        var = self._name(children[0])
        return Membership(var, children[1], var.pos)

    def f_ref(self, children: list[Token]) -> ConsRef:
        return ConsRef(self._name(children[0]))

    def f_atom(self, children: list[Any]) -> Atom:
        return Atom(str(children[0]), children[1] or (), None, self._pos(children[0]))

    def f_true(self, children: list[Any]) -> TrueF:
        return TrueF()

    def f_not(self, children: list[Formula]) -> Formula:
        return Not(children[0])

    def f_and(self, children: list[Formula]) -> Formula:
        return conj(*children)

    def f_or(self, children: list[Formula]) -> Formula:
        left, right = children
        return Or((*(left.args if isinstance(left, Or) else (left,)), right))

    def f_timed(self, children: list[Any]) -> Formula:
        return retime(children[1], children[0])

    def f_exists(self, children: list[Any]) -> Formula:
        return Exists(children[0], children[1])

    def f_forall(self, children: list[Any]) -> Formula:
        return Forall(children[0], children[1])

    # --- composite actions --------------------------------------------------------------
    def action_term(self, children: list[Any]) -> ActionTerm:
        return ActionTerm(str(children[0]), children[1] or (), None, self._pos(children[0]))

    def timed_term(self, children: list[Any]) -> ActionTerm:
        (interval, _), term = children
        return ActionTerm(term.name, term.args, interval, term.pos)

    def sequence(self, children: list[CAct]) -> Sequence:
        return Sequence(tuple(children))

    def concurrent(self, children: list[CAct]) -> Concurrent:
        return Concurrent(tuple(children))

    def if_task(self, children: list[Any]) -> If:
        return If(children[0], children[1], children[2])

    def while_task(self, children: list[Any]) -> While:
        return While(children[0], children[1])

    def foreach_task(self, children: list[Any]) -> Foreach:
        return Foreach(children[0], children[1], children[2])

    def cact(self, children: list[Any]) -> CAct:
        label, (interval, pos), agent, with_vars, task, where = children
        if label is not None:
            pos = self._pos(label)
        where = None if isinstance(where, TrueF) else where
        label_text = None if label is None else str(label)
        return CAct(interval, task, with_vars or (), where, agent, label_text, pos)

    # --- items --------------------------------------------------------------------------
    def spec(self, children: list[Any]) -> CompositeSpec:
        (interval, _), name, params, body = children
        return CompositeSpec(interval, str(name), params or (), body, self._pos(name))

    def mission(self, children: list[Any]) -> Mission:
        return Mission(str(children[0]), children[1], self._pos(children[0]))

    def constraint_def(self, children: list[Any]) -> ConstraintDef:
        return ConstraintDef(str(children[0]), children[1], self._pos(children[0]))

    def open_decl(self, children: list[tuple[str, ...]]) -> OpenDecl:
        return OpenDecl(children[0])

    def world_decl(self, children: list[Token]) -> WorldDecl:
        return WorldDecl(str(children[0]), self._pos(children[0]))

    def agents_decl(self, children: list[tuple[str, ...]]) -> AgentsDecl:
        return AgentsDecl(children[0])

    def area_decl(self, children: list[Any]) -> AreaDecl:
        return AreaDecl(str(children[0]), tuple(children[1:]), self._pos(children[0]))

    def place_alt(self, children: list[Any]) -> tuple[str, float]:
        return (str(children[0]), children[1].value)

    def point_decl(self, children: list[Any]) -> PointDecl:
        name, where, pos = str(children[0]), children[1], self._pos(children[0])
        if isinstance(where[0], str):
            return PointDecl(name, None, where[0], where[1], pos)
        return PointDecl(name, where, None, 0.0, pos)

    def path_decl(self, children: list[Any]) -> PathDecl:
        return PathDecl(str(children[0]), children[1], self._pos(children[0]))

    def start(self, children: list[Any]) -> TalfFile:
        return TalfFile(tuple(children))


def _syntax_diagnostic(
    exc: lark.exceptions.UnexpectedInput, file: str, text: str
) -> TalfDiagnostic:
    problem = describe(exc, lark_parser().lark, text)
    return TalfDiagnostic("T001", problem.message, SourcePos(file, problem.line, problem.column))


def parse_text(text: str, file: str = "<string>") -> ParseResult:
    """Parse ``.talf`` text; syntax errors come back as diagnostics, never as exceptions."""
    try:
        tree = lark_parser().parse(text, file)
    except lark.exceptions.UnexpectedInput as exc:
        return ParseResult(TalfStatus.SYNTAX_ERROR, None, (_syntax_diagnostic(exc, file, text),))
    except BadValue as exc:  # only numbers too large for a float
        diag = TalfDiagnostic("T002", f"bad value: {exc}", SourcePos(file, 0, 0))
        return ParseResult(TalfStatus.SYNTAX_ERROR, None, (diag,))
    return ParseResult(TalfStatus.OK, tree)


def parse_file(path: str | Path) -> ParseResult:
    """Read and parse a ``.talf`` file; an unreadable file gives a diagnostic, not an exception."""
    file = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        diag = TalfDiagnostic("T000", f"cannot read file: {exc}", SourcePos(file, 0, 0))
        return ParseResult(TalfStatus.UNREADABLE, None, (diag,))
    return parse_text(text, file)
