"""Reader of the TAL planning language (domains, problems, control formulas).

Grammar: ``tal.lark``. The transformer turns parse trees into the syntax tree of
:mod:`hdrc3_deliberative.model`; statements are then sorted into a Domain, a Problem or a
ControlSpec. Parse errors carry ``file:line:column`` and the expected tokens.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken
from lark.tree import Meta

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import (
    ROOT_TYPE,
    Atom,
    AtomEffect,
    BinOp,
    Comparison,
    Condition,
    ControlRule,
    ControlSpec,
    Domain,
    Effect,
    EffectTime,
    Equality,
    FAnd,
    FAtom,
    FCompare,
    FConst,
    FEq,
    FGoal,
    FImplies,
    FNot,
    FOr,
    Formula,
    FQuant,
    FuncTerm,
    Literal,
    MapRelation,
    Num,
    NumEffect,
    NumExpr,
    Operator,
    Param,
    Pos,
    Problem,
    RuleKind,
    StepDecl,
    Term,
    TimeRef,
)

_TOKEN_NAMES = {
    "LPAR": "'('",
    "RPAR": "')'",
    "COMMA": "','",
    "COLON": "':'",
    "DOT": "'.'",
    "NAME": "a name",
    "NUMBER": "a number",
    "SIGNED_NUMBER": "a number",
    "CMPOP": "a comparison",
    "ASSIGNOP": "':=', '+=' or '-='",
    "EFFTIME": '"[t+1]", "[t\']" or "(t,t\']"',
    "TIMEREF": "'[t]' or '[t+1]'",
    "$END": "end of file",
}


def _expected(names: set[str], lark: Lark) -> str:
    shown: list[str] = []
    for name in names:
        if name in _TOKEN_NAMES:
            shown.append(_TOKEN_NAMES[name])
            continue
        try:
            shown.append(repr(lark.get_terminal(name).pattern.value))
        except KeyError:
            shown.append(name.lower())
    return ", ".join(sorted(set(shown))[:14])


# --- statements produced by the transformer ----------------------------------------------


@dataclass(frozen=True)
class _Stmt:
    kind: str
    pos: Pos
    data: tuple[Any, ...]


class _ToModel(Transformer[Token, list[_Stmt]]):
    """Parse tree -> model values. Every rule that needs a position takes meta."""

    def __init__(self, source: str) -> None:
        super().__init__()
        self._source = source

    def _pos(self, meta: Meta) -> Pos:
        return Pos(self._source, getattr(meta, "line", 0), getattr(meta, "column", 0))

    def start(self, items: list[_Stmt]) -> list[_Stmt]:
        return items

    # names, params, terms
    def name_list(self, items: list[Token]) -> tuple[str, ...]:
        return tuple(str(t) for t in items)

    def param(self, items: list[Token]) -> Param:
        return Param(str(items[0]), str(items[1]))

    def param_list(self, items: list[Param]) -> tuple[Param, ...]:
        return tuple(items)

    def arg_list(self, items: list[Token]) -> tuple[str, ...]:
        return tuple(str(t) for t in items)

    @v_args(meta=True)
    def call(self, meta: Meta, items: list[Any]) -> Atom:
        args = items[1] or ()
        return Atom(str(items[0]), tuple(Term(a) for a in args), self._pos(meta))

    # numeric expressions
    def number(self, items: list[Token]) -> Num:
        return Num(float(items[0]))

    def name_ref(self, items: list[Token]) -> Term:
        return Term(str(items[0]))

    def _bin(self, op: str, items: list[Any]) -> BinOp:
        return BinOp(op, _num(items[0]), _num(items[1]))

    def add(self, items: list[Any]) -> BinOp:
        return self._bin("+", items)

    def sub(self, items: list[Any]) -> BinOp:
        return self._bin("-", items)

    def mul(self, items: list[Any]) -> BinOp:
        return self._bin("*", items)

    def div(self, items: list[Any]) -> BinOp:
        return self._bin("/", items)

    # conditions
    def neg_cond(self, items: list[Atom]) -> Condition:
        return Literal(items[0], False)

    def pos_cond(self, items: list[Atom]) -> Condition:
        return Literal(items[0], True)

    def cmp_cond(self, items: list[Any]) -> Condition:
        op, left, right = str(items[1]), items[0], items[2]
        if isinstance(left, Term) and isinstance(right, Term) and op in ("=", "!="):
            return Equality(left, right, op == "=")
        return Comparison(op, _num(left), _num(right))

    def cond_list(self, items: list[Condition]) -> tuple[Condition, ...]:
        return tuple(items)

    # effects
    def del_effect(self, items: list[Atom]) -> tuple[str, Any]:
        return ("lit", Literal(items[0], False))

    def add_effect(self, items: list[Atom]) -> tuple[str, Any]:
        return ("lit", Literal(items[0], True))

    def num_effect(self, items: list[Any]) -> tuple[str, Any]:
        return ("num", (str(items[1]), items[0], _num(items[2])))

    # statements
    @v_args(meta=True)
    def domain_decl(self, meta: Meta, items: list[Token]) -> _Stmt:
        return _Stmt("domain", self._pos(meta), (str(items[0]),))

    @v_args(meta=True)
    def type_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        parent = str(items[1]) if items[1] is not None else ROOT_TYPE
        return _Stmt("type", self._pos(meta), (items[0], parent))

    def _feature(self, kind: str, meta: Meta, items: list[Any]) -> _Stmt:
        params = items[1] or ()
        return _Stmt(kind, self._pos(meta), (str(items[0]), tuple(p.type for p in params)))

    @v_args(meta=True)
    def predicate_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return self._feature("predicate", meta, items)

    @v_args(meta=True)
    def function_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return self._feature("function", meta, items)

    @v_args(meta=True)
    def resource_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return self._feature("resource", meta, items)

    def agent_clause(self, items: list[Token]) -> tuple[str, Any]:
        return ("agent", str(items[0]))

    def duration_clause(self, items: list[Any]) -> tuple[str, Any]:
        return ("duration", _num(items[0]))

    def pre_clause(self, items: list[Any]) -> tuple[str, Any]:
        return ("pre", items[0])

    def prevail_clause(self, items: list[Any]) -> tuple[str, Any]:
        return ("prevail", items[0])

    def effect_clause(self, items: list[Any]) -> tuple[str, Any]:
        time = EffectTime.START if str(items[0]) == "[t+1]" else EffectTime.END
        effects: list[Effect] = []
        for kind, value in items[1:]:
            if kind == "lit":
                effects.append(AtomEffect(time, value))
            else:
                op, target, expr = value
                effects.append(NumEffect(time, op, target, expr))
        return ("effect", tuple(effects))

    @v_args(meta=True)
    def operator_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        name, params, clauses = str(items[0]), items[1] or (), items[2:]
        pos = self._pos(meta)
        agent: str | None = None
        duration: NumExpr = Num(1.0)
        pre: tuple[Condition, ...] = ()
        prevail: tuple[Condition, ...] = ()
        effects: tuple[Effect, ...] = ()
        for kind, value in clauses:
            if kind == "agent":
                agent = value
            elif kind == "duration":
                duration = value
            elif kind == "pre":
                pre += value
            elif kind == "prevail":
                prevail += value
            else:
                effects += value
        op = Operator(name, params, pre, effects, duration, agent, prevail, pos)
        return _Stmt("operator", pos, (op,))

    @v_args(meta=True)
    def problem_decl(self, meta: Meta, items: list[Token]) -> _Stmt:
        return _Stmt("problem", self._pos(meta), (str(items[0]), str(items[1])))

    def position(self, items: list[Token]) -> tuple[float, float, float]:
        return (float(items[0]), float(items[1]), float(items[2]))

    @v_args(meta=True)
    def object_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("object", self._pos(meta), (items[0], str(items[1]), items[2]))

    def init_atom(self, items: list[Atom]) -> tuple[Atom, float | None]:
        return (items[0], None)

    def init_value(self, items: list[Any]) -> tuple[Atom, float | None]:
        if str(items[1]) != "=":
            raise PlanningInputError(
                f"expected '=' in initial value, found '{items[1]}'",
                self._source,
                items[1].line or 0,
                items[1].column or 0,
            )
        return (items[0], float(items[2]))

    @v_args(meta=True)
    def init_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("init", self._pos(meta), tuple(items))

    @v_args(meta=True)
    def goal_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("goal", self._pos(meta), items[0])

    # control formulas
    def f_implies(self, items: list[Formula]) -> Formula:
        return FImplies(items[0], items[1])

    def f_or(self, items: list[Formula]) -> Formula:
        return FOr(tuple(items))

    def f_and(self, items: list[Formula]) -> Formula:
        return FAnd(tuple(items))

    def f_not(self, items: list[Formula]) -> Formula:
        return FNot(items[0])

    def f_forall(self, items: list[Any]) -> Formula:
        return FQuant(True, items[0], items[1])

    def f_exists(self, items: list[Any]) -> Formula:
        return FQuant(False, items[0], items[1])

    def f_timed(self, items: list[Any]) -> Formula:
        time = TimeRef.NOW if str(items[0]) == "[t]" else TimeRef.NEXT
        return _retime(items[1], time)

    def f_goal(self, items: list[Atom]) -> Formula:
        return FGoal(items[0])

    def f_true(self, items: list[Any]) -> Formula:
        return FConst(True)

    def f_false(self, items: list[Any]) -> Formula:
        return FConst(False)

    def f_atom(self, items: list[Atom]) -> Formula:
        return FAtom(items[0], None)

    def f_cmp(self, items: list[Any]) -> Formula:
        """Object (in)equality between two bare names, else a numeric comparison."""
        left, token, right = items
        op = str(token)
        if isinstance(left, Term) and isinstance(right, Term):
            if op not in ("=", "!="):
                raise PlanningInputError(
                    f"expected '=' or '!=' between objects, found '{op}'",
                    self._source,
                    token.line or 0,
                    token.column or 0,
                )
            return FEq(left, right, op == "=")
        for side in (left, right):
            if isinstance(side, Term):
                raise PlanningInputError(
                    f"'{side.name}' is an object, not a number: write a function term "
                    f"such as '{side.name}()' or compare objects with '=' / '!='",
                    self._source,
                    token.line or 0,
                    token.column or 0,
                )
        pos = Pos(self._source, token.line or 0, token.column or 0)
        return FCompare(op, _num(left), _num(right), None, pos)

    @v_args(meta=True)
    def rule_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("rule", self._pos(meta), (str(items[0]), RuleKind.ALWAYS, items[1]))

    @v_args(meta=True)
    def final_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("rule", self._pos(meta), (str(items[0]), RuleKind.FINAL, items[1]))

    @v_args(meta=True)
    def prefer_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("prefer", self._pos(meta), items[0])

    @v_args(meta=True)
    def agents_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        return _Stmt("agents", self._pos(meta), items[0])

    @v_args(meta=True)
    def step_decl(self, meta: Meta, items: list[Any]) -> _Stmt:
        kind = MapRelation(str(items[0]))
        return _Stmt("step", self._pos(meta), (kind, str(items[1]), str(items[2])))


def _num(value: Any) -> NumExpr:
    """A bare name inside arithmetic is a 0-ary function term."""
    if isinstance(value, Term):
        return FuncTerm(Atom(value.name, ()))
    if isinstance(value, Atom):
        return FuncTerm(value)
    assert isinstance(value, Num | BinOp | FuncTerm)
    return value


def _retime(formula: Formula, time: TimeRef) -> Formula:
    """Give untimed atoms below a ``[t]``/``[t+1]`` marker that time (inner markers win)."""
    if isinstance(formula, FAtom):
        return formula if formula.time is not None else FAtom(formula.atom, time)
    if isinstance(formula, FNot):
        return FNot(_retime(formula.arg, time))
    if isinstance(formula, FAnd):
        return FAnd(tuple(_retime(a, time) for a in formula.args))
    if isinstance(formula, FOr):
        return FOr(tuple(_retime(a, time) for a in formula.args))
    if isinstance(formula, FImplies):
        return FImplies(_retime(formula.left, time), _retime(formula.right, time))
    if isinstance(formula, FQuant):
        return FQuant(formula.universal, formula.variables, _retime(formula.body, time))
    if isinstance(formula, FCompare) and formula.time is None:
        return FCompare(formula.op, formula.left, formula.right, time, formula.pos)
    return formula


class TalReader:
    """Parses TAL planning-language files; owns the compiled lark parser."""

    def __init__(self) -> None:
        grammar = (Path(__file__).parent / "tal.lark").read_text()
        self._lark = Lark(grammar, parser="lalr", propagate_positions=True, maybe_placeholders=True)

    def _statements(self, text: str, source: str) -> list[_Stmt]:
        try:
            tree = self._lark.parse(text)
        except UnexpectedInput as exc:
            raise _syntax_error(exc, source, self._lark, text) from None
        try:
            result: list[_Stmt] = _ToModel(source).transform(tree)
        except Exception as exc:  # lark wraps callback errors; unwrap ours
            inner = getattr(exc, "orig_exc", exc)
            if isinstance(inner, PlanningInputError):
                raise inner from None
            raise
        return result

    @staticmethod
    def _reject(stmts: list[_Stmt], allowed: set[str], what: str) -> None:
        for stmt in stmts:
            if stmt.kind not in allowed:
                raise PlanningInputError(
                    f"'{stmt.kind}' statement is not allowed in a {what} file",
                    stmt.pos.source,
                    stmt.pos.line,
                    stmt.pos.column,
                )

    def read_domain(self, text: str, source: str = "<domain>") -> Domain:
        """Parse a TAL domain file."""
        stmts = self._statements(text, source)
        self._reject(
            stmts, {"domain", "type", "predicate", "function", "resource", "operator"}, "domain"
        )
        name = next((s.data[0] for s in stmts if s.kind == "domain"), "")
        if not name:
            raise PlanningInputError("missing 'domain NAME' statement", source, 1, 1)
        types: dict[str, str] = {}
        predicates: dict[str, tuple[str, ...]] = {}
        functions: dict[str, tuple[str, ...]] = {}
        resources: set[str] = set()
        operators: list[Operator] = []
        for stmt in stmts:
            if stmt.kind == "type":
                for tname in stmt.data[0]:
                    types[tname] = stmt.data[1]
            elif stmt.kind == "predicate":
                predicates[stmt.data[0]] = stmt.data[1]
            elif stmt.kind in ("function", "resource"):
                functions[stmt.data[0]] = stmt.data[1]
                if stmt.kind == "resource":
                    resources.add(stmt.data[0])
            elif stmt.kind == "operator":
                operators.append(stmt.data[0])
        return Domain(
            name,
            types,
            (),
            predicates,
            functions,
            tuple(operators),
            frozenset(resources),
            (),
            source,
        )

    def read_problem(self, text: str, source: str = "<problem>") -> Problem:
        """Parse a TAL problem file."""
        stmts = self._statements(text, source)
        self._reject(stmts, {"problem", "object", "init", "goal"}, "problem")
        header = next((s for s in stmts if s.kind == "problem"), None)
        if header is None:
            raise PlanningInputError("missing 'problem NAME for DOMAIN' statement", source, 1, 1)
        objects: list[Param] = []
        positions: dict[str, tuple[float, float, float]] = {}
        init: list[Atom] = []
        values: list[tuple[Atom, float]] = []
        goal: list[Condition] = []
        for stmt in stmts:
            if stmt.kind == "object":
                names, tname, position = stmt.data
                objects.extend(Param(n, tname) for n in names)
                if position is not None:
                    positions.update(dict.fromkeys(names, position))
            elif stmt.kind == "init":
                for atom, value in stmt.data:
                    if value is None:
                        init.append(atom)
                    else:
                        values.append((atom, value))
            elif stmt.kind == "goal":
                goal.extend(stmt.data)
        return Problem(
            header.data[0],
            header.data[1],
            tuple(objects),
            tuple(init),
            tuple(values),
            tuple(goal),
            positions,
            source,
        )

    def read_control(self, text: str, source: str = "<control>") -> ControlSpec:
        """Parse a control file: rules, final rules, ``prefer``, ``agents`` and ``step``."""
        stmts = self._statements(text, source)
        self._reject(stmts, {"rule", "prefer", "agents", "step"}, "control")
        rules = tuple(
            ControlRule(s.data[0], s.data[1], s.data[2], s.pos) for s in stmts if s.kind == "rule"
        )
        prefer = tuple(n for s in stmts if s.kind == "prefer" for n in s.data)
        agents = tuple(n for s in stmts if s.kind == "agents" for n in s.data)
        steps = tuple(
            StepDecl(s.data[0], s.data[1], s.data[2], s.pos) for s in stmts if s.kind == "step"
        )
        return ControlSpec(rules, prefer, agents, source, steps)


def _syntax_error(exc: UnexpectedInput, source: str, lark: Lark, text: str) -> PlanningInputError:
    line, column = getattr(exc, "line", 0), getattr(exc, "column", 0)
    if isinstance(exc, UnexpectedEOF) or (
        isinstance(exc, UnexpectedToken) and exc.token.type == "$END"
    ):
        line = text.count("\n") + 1  # lark reports the last token; point at the end instead
        column = len(text.rsplit("\n", 1)[-1]) + 1
    if isinstance(exc, UnexpectedToken):
        found = "end of file" if exc.token.type == "$END" else repr(str(exc.token))
        return PlanningInputError(
            f"unexpected {found}: expected {_expected(set(exc.accepts or exc.expected), lark)}",
            source,
            line,
            column,
        )
    if isinstance(exc, UnexpectedCharacters):
        allowed = _expected(set(exc.allowed or ()), lark)
        return PlanningInputError(
            f"unexpected character {exc.char!r}: expected {allowed}", source, line, column
        )
    if isinstance(exc, UnexpectedEOF):
        return PlanningInputError(
            f"unexpected end of file: expected {_expected(set(exc.expected), lark)}",
            source,
            line,
            column,
        )
    return PlanningInputError(str(exc), source, line, column)
