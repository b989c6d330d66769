"""PDDL reader: STRIPS, typing, negative preconditions and equality.

The lexical layer is a lark s-expression grammar (``sexpr.lark``); a walker turns the lists into
the syntax tree of :mod:`hdrc3_deliberative.model` and reports every structural problem with
``file:line:column`` and what was expected.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import (
    ROOT_TYPE,
    Atom,
    AtomEffect,
    Condition,
    Domain,
    EffectTime,
    Equality,
    Literal,
    Operator,
    Param,
    Pos,
    Problem,
    Term,
)

ACCEPTED_REQUIREMENTS = (":strips", ":typing", ":negative-preconditions", ":equality")


@dataclass(frozen=True)
class SSym:
    """A symbol with its position (lower-cased: PDDL is case-insensitive)."""

    text: str
    pos: Pos


@dataclass(frozen=True)
class SList:
    """A parenthesised list with the position of its opening parenthesis."""

    items: tuple[SExpr, ...]
    pos: Pos


SExpr = SSym | SList


class SExprParser:
    """Parses text into s-expressions; owns the compiled lark parser."""

    def __init__(self) -> None:
        grammar = (Path(__file__).parent / "sexpr.lark").read_text()
        self._lark = Lark(grammar, parser="lalr", propagate_positions=True)

    def parse(self, text: str, source: str) -> list[SExpr]:
        """Parse a whole file; lexical errors raise PlanningInputError with position."""
        try:
            tree = self._lark.parse(text)
        except UnexpectedInput as exc:
            raise _lark_error(exc, source, text) from None
        return [_convert(child, source) for child in tree.children]


def _lark_error(exc: UnexpectedInput, source: str, text: str) -> PlanningInputError:
    end_line = text.count("\n") + 1
    end_column = len(text.rsplit("\n", 1)[-1]) + 1
    if isinstance(exc, UnexpectedEOF) or (
        isinstance(exc, UnexpectedToken) and exc.token.type == "$END"
    ):
        return PlanningInputError(
            "unexpected end of file: expected ')'", source, end_line, end_column
        )
    if isinstance(exc, UnexpectedToken):
        found = "')'" if exc.token.type == "RPAR" else repr(str(exc.token))
        if exc.token.type == "$END":
            found = "end of file"
        expected = "'(' or a symbol" if exc.token.type == "RPAR" else "')'"
        return PlanningInputError(
            f"unexpected {found}: expected {expected}", source, exc.line, exc.column
        )
    if isinstance(exc, UnexpectedCharacters):
        return PlanningInputError(
            f"unexpected character {exc.char!r}", source, exc.line, exc.column
        )
    return PlanningInputError(str(exc), source, getattr(exc, "line", 0), getattr(exc, "column", 0))


def _convert(node: Tree[Token] | Token, source: str) -> SExpr:
    if isinstance(node, Token):
        return SSym(str(node).lower(), Pos(source, node.line or 0, node.column or 0))
    pos = Pos(source, node.meta.line, node.meta.column) if not node.meta.empty else Pos(source)
    return SList(tuple(_convert(child, source) for child in node.children), pos)


def _fail(message: str, where: SExpr | Pos) -> PlanningInputError:
    pos = where if isinstance(where, Pos) else where.pos
    return PlanningInputError(message, pos.source, pos.line, pos.column)


def _describe(expr: SExpr) -> str:
    return f"'{expr.text}'" if isinstance(expr, SSym) else "a list"


def _symbol(expr: SExpr, what: str) -> str:
    if not isinstance(expr, SSym):
        raise _fail(f"expected {what}, found a list", expr)
    return expr.text


def _list(expr: SExpr, what: str) -> SList:
    if not isinstance(expr, SList):
        raise _fail(f"expected {what}, found {_describe(expr)}", expr)
    return expr


def _head(expr: SList, keyword: str) -> tuple[SExpr, ...]:
    if not expr.items or not isinstance(expr.items[0], SSym) or expr.items[0].text != keyword:
        found = _describe(expr.items[0]) if expr.items else "'()'"
        raise _fail(f"expected '({keyword} ...)', found {found}", expr)
    return expr.items[1:]


def _typed_list(items: tuple[SExpr, ...], variables: bool) -> tuple[Param, ...]:
    """Parse ``a b - t c`` into params; untyped names get the root type."""
    result: list[Param] = []
    pending: list[str] = []
    i = 0
    while i < len(items):
        sym = _symbol(items[i], "a name or '-'")
        if sym == "-":
            if i + 1 >= len(items):
                raise _fail("expected a type name after '-'", items[i])
            type_expr = items[i + 1]
            if isinstance(type_expr, SList):
                raise _fail("'(either ...)' types are not supported", type_expr)
            result.extend(Param(name, type_expr.text) for name in pending)
            pending = []
            i += 2
            continue
        if variables and not sym.startswith("?"):
            raise _fail(f"expected a variable '?name', found '{sym}'", items[i])
        pending.append(sym)
        i += 1
    result.extend(Param(name, ROOT_TYPE) for name in pending)
    return tuple(result)


def _term(expr: SExpr) -> Term:
    text = _symbol(expr, "a variable or constant")
    return Term(text, text.startswith("?"))


def _atom(expr: SList) -> Atom:
    if not expr.items:
        raise _fail("expected an atom '(predicate args...)', found '()'", expr)
    pred = _symbol(expr.items[0], "a predicate name")
    return Atom(pred, tuple(_term(arg) for arg in expr.items[1:]), expr.pos)


_UNSUPPORTED_GD = {
    "or": ":disjunctive-preconditions",
    "imply": ":disjunctive-preconditions",
    "exists": ":existential-preconditions",
    "forall": ":universal-preconditions",
    "when": ":conditional-effects",
    "increase": ":numeric-fluents",
    "decrease": ":numeric-fluents",
    "assign": ":numeric-fluents",
    "<": ":numeric-fluents",
    ">": ":numeric-fluents",
    "<=": ":numeric-fluents",
    ">=": ":numeric-fluents",
}


def _conditions(expr: SExpr, out: list[Condition], positive: bool = True) -> None:
    """Flatten a goal description (and/not/=/atoms) into literals."""
    node = _list(expr, "a condition '(...)'")
    if not node.items:
        return
    head = _symbol(node.items[0], "a predicate or connective")
    if head in _UNSUPPORTED_GD:
        raise _fail(
            f"'{head}' needs requirement {_UNSUPPORTED_GD[head]}, which is not supported", node
        )
    if head == "and":
        if not positive:
            raise _fail("negated conjunctions are not supported (STRIPS literals only)", node)
        for child in node.items[1:]:
            _conditions(child, out)
    elif head == "not":
        if len(node.items) != 2:
            raise _fail("expected '(not CONDITION)' with one argument", node)
        if not positive:
            raise _fail("double negation is not supported", node)
        _conditions(node.items[1], out, positive=False)
    elif head == "=":
        if len(node.items) != 3:
            raise _fail("expected '(= TERM TERM)'", node)
        out.append(Equality(_term(node.items[1]), _term(node.items[2]), positive))
    else:
        out.append(Literal(_atom(node), positive))


def _effects(expr: SExpr, out: list[AtomEffect], positive: bool = True) -> None:
    node = _list(expr, "an effect '(...)'")
    if not node.items:
        return
    head = _symbol(node.items[0], "a predicate or 'and'/'not'")
    if head in _UNSUPPORTED_GD:
        raise _fail(
            f"'{head}' needs requirement {_UNSUPPORTED_GD[head]}, which is not supported", node
        )
    if head == "and" and positive:
        for child in node.items[1:]:
            _effects(child, out)
    elif head == "not" and positive and len(node.items) == 2:
        _effects(node.items[1], out, positive=False)
    elif head in ("and", "not"):
        raise _fail(f"malformed '{head}' effect", node)
    else:
        out.append(AtomEffect(EffectTime.END, Literal(_atom(node), positive)))


class PddlReader:
    """Reads PDDL domain and problem files into syntax trees."""

    def __init__(self) -> None:
        self._parser = SExprParser()

    def _single(self, text: str, source: str, kind: str) -> SList:
        exprs = self._parser.parse(text, source)
        if len(exprs) != 1:
            raise _fail(f"expected exactly one '(define ({kind} ...) ...)'", exprs[-1])
        top = _list(exprs[0], "'(define ...)'")
        items = _head(top, "define")
        if not items:
            raise _fail(f"expected '({kind} NAME)' after 'define'", top)
        header = _head(_list(items[0], f"'({kind} NAME)'"), kind)
        if len(header) != 1:
            raise _fail(f"expected '({kind} NAME)'", items[0])
        return SList((header[0], *items[1:]), top.pos)

    def read_domain(self, text: str, source: str = "<domain>") -> Domain:
        """Parse a PDDL domain; raises PlanningInputError on any problem."""
        top = self._single(text, source, "domain")
        name = _symbol(top.items[0], "a domain name")
        requirements: tuple[str, ...] = (":strips",)
        types: dict[str, str] = {}
        constants: tuple[Param, ...] = ()
        predicates: dict[str, tuple[str, ...]] = {}
        operators: list[Operator] = []
        for section in top.items[1:]:
            node = _list(section, "a domain section '(:keyword ...)'")
            key = _symbol(node.items[0], "a section keyword") if node.items else ""
            body = node.items[1:]
            if key == ":requirements":
                requirements = tuple(_symbol(r, "a requirement") for r in body)
                for req, req_expr in zip(requirements, body, strict=True):
                    if req not in ACCEPTED_REQUIREMENTS:
                        raise _fail(
                            f"unsupported PDDL requirement '{req}' "
                            f"(accepted: {' '.join(ACCEPTED_REQUIREMENTS)})",
                            req_expr,
                        )
            elif key == ":types":
                for param in _typed_list(body, variables=False):
                    types[param.name] = param.type
            elif key == ":constants":
                constants = _typed_list(body, variables=False)
            elif key == ":predicates":
                for decl in body:
                    dl = _list(decl, "a predicate declaration '(name ?x - type ...)'")
                    pname = _symbol(dl.items[0], "a predicate name") if dl.items else ""
                    if not pname:
                        raise _fail("empty predicate declaration", dl)
                    params = _typed_list(dl.items[1:], variables=True)
                    predicates[pname] = tuple(p.type for p in params)
            elif key == ":action":
                operators.append(self._action(node))
            elif key in (":functions", ":durative-action", ":derived"):
                needed = {":functions": ":numeric-fluents", ":durative-action": ":durative-actions"}
                raise _fail(
                    f"'{key}' needs requirement {needed.get(key, ':derived-predicates')}, "
                    "which the PDDL reader does not support (use the TAL domain language)",
                    node,
                )
            else:
                raise _fail(
                    f"unknown domain section '{key}': expected :requirements, :types, "
                    ":constants, :predicates or :action",
                    node,
                )
        for parent in set(types.values()) - set(types) - {ROOT_TYPE}:
            types[parent] = ROOT_TYPE
        return Domain(
            name,
            types,
            constants,
            predicates,
            {},
            tuple(operators),
            frozenset(),
            requirements,
            source,
        )

    def _action(self, node: SList) -> Operator:
        items = node.items
        if len(items) < 2:
            raise _fail("expected an action name after ':action'", node)
        name = _symbol(items[1], "an action name")
        params: tuple[Param, ...] = ()
        pre: list[Condition] = []
        effects: list[AtomEffect] = []
        i = 2
        while i < len(items):
            key = _symbol(items[i], "':parameters', ':precondition' or ':effect'")
            if i + 1 >= len(items):
                raise _fail(f"expected a value after '{key}'", items[i])
            value = items[i + 1]
            if key == ":parameters":
                params = _typed_list(_list(value, "a parameter list").items, variables=True)
            elif key == ":precondition":
                _conditions(value, pre)
            elif key == ":effect":
                _effects(value, effects)
            else:
                raise _fail(
                    f"unexpected '{key}': expected ':parameters', ':precondition' or ':effect'",
                    items[i],
                )
            i += 2
        return Operator(name, params, tuple(pre), tuple(effects), pos=node.pos)

    def read_problem(self, text: str, source: str = "<problem>") -> Problem:
        """Parse a PDDL problem; raises PlanningInputError on any problem."""
        top = self._single(text, source, "problem")
        name = _symbol(top.items[0], "a problem name")
        domain_name = ""
        objects: tuple[Param, ...] = ()
        init: list[Atom] = []
        goal: list[Condition] = []
        for section in top.items[1:]:
            node = _list(section, "a problem section '(:keyword ...)'")
            key = _symbol(node.items[0], "a section keyword") if node.items else ""
            body = node.items[1:]
            if key == ":domain":
                if len(body) != 1:
                    raise _fail("expected '(:domain NAME)'", node)
                domain_name = _symbol(body[0], "a domain name")
            elif key == ":objects":
                objects = _typed_list(body, variables=False)
            elif key == ":init":
                for fact in body:
                    fl = _list(fact, "an initial fact '(predicate objects...)'")
                    if fl.items and isinstance(fl.items[0], SSym) and fl.items[0].text == "=":
                        raise _fail(
                            "numeric initial values need :numeric-fluents (unsupported)", fl
                        )
                    atom = _atom(fl)
                    if any(t.is_var for t in atom.args):
                        raise _fail("initial facts must be ground", fl)
                    init.append(atom)
            elif key == ":goal":
                if len(body) != 1:
                    raise _fail("expected '(:goal CONDITION)'", node)
                _conditions(body[0], goal)
            elif key == ":requirements":
                for req in body:
                    if _symbol(req, "a requirement") not in ACCEPTED_REQUIREMENTS:
                        raise _fail(f"unsupported PDDL requirement '{_symbol(req, '')}'", req)
            elif key == ":metric":
                continue  # plan quality metrics do not change which plans are valid
            else:
                raise _fail(
                    f"unknown problem section '{key}': expected :domain, :objects, :init or :goal",
                    node,
                )
        if not domain_name:
            raise _fail("missing '(:domain NAME)'", top)
        return Problem(name, domain_name, objects, tuple(init), (), tuple(goal), {}, source)
