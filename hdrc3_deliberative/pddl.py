"""PDDL reader: STRIPS and typing, numeric fluents, durative actions with a fixed duration.

Accepted beyond STRIPS (README "Accepted PDDL" says exactly what): ``(either ...)`` parameter
and object types; ``:numeric-fluents`` (``:functions``, ``increase``/``decrease``/``assign``,
comparisons in preconditions and goals, ``(= (f o) v)`` initial values); ``:durative-actions``
with ``(= ?duration EXPRESSION)``, ``at start`` preconditions, ``over all`` conditions (TAL
prevail conditions) and ``at start``/``at end`` effects. ``at end`` conditions, duration
inequalities, continuous effects and the ADL connectives are rejected by name.

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
    BinOp,
    Comparison,
    Condition,
    Domain,
    Effect,
    EffectTime,
    Equality,
    FuncTerm,
    Literal,
    Num,
    NumEffect,
    NumExpr,
    Operator,
    Param,
    Pos,
    Problem,
    Term,
)
from hdrc3_deliberative.names import union_members, union_type

ACCEPTED_REQUIREMENTS = (
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":equality",
    ":numeric-fluents",
    ":fluents",
    ":action-costs",
    ":durative-actions",
)


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


def _type_name(expr: SExpr) -> str:
    """A type name, or ``(either a b)`` as the canonical union name of :mod:`names`."""
    if isinstance(expr, SSym):
        return expr.text
    members = _head(expr, "either")
    if not members:
        raise _fail("expected '(either TYPE TYPE ...)' with at least one type", expr)
    return union_type(tuple(_symbol(m, "a type name") for m in members))


def _typed_list(items: tuple[SExpr, ...], variables: bool) -> tuple[Param, ...]:
    """Parse ``a b - t c`` (or ``- (either t u)``) into params; untyped names get the root type."""
    result: list[Param] = []
    pending: list[str] = []
    i = 0
    while i < len(items):
        sym = _symbol(items[i], "a name or '-'")
        if sym == "-":
            if i + 1 >= len(items):
                raise _fail("expected a type name after '-'", items[i])
            tname = _type_name(items[i + 1])
            result.extend(Param(name, tname) for name in pending)
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
    "scale-up": ":numeric-fluents (scale-up/scale-down are not supported)",
    "scale-down": ":numeric-fluents (scale-up/scale-down are not supported)",
}
_COMPARISONS = ("<", "<=", ">", ">=")
_NEGATED = {"<": ">=", "<=": ">", ">": "<=", ">=": "<", "=": "!=", "!=": "="}
_ASSIGN = {"increase": "+=", "decrease": "-=", "assign": ":="}
_ARITH = ("+", "-", "*", "/")


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _num_expr(expr: SExpr, duration: NumExpr | None = None) -> NumExpr:
    """A numeric expression: number, ``(f args)``, ``(op a b)``, ``(- a)`` or ``?duration``."""
    if isinstance(expr, SSym):
        value = _number(expr.text)
        if value is not None:
            return Num(value)
        if expr.text == "?duration" and duration is not None:
            return duration
        hint = " (?duration is only defined in durative actions)" * (expr.text == "?duration")
        raise _fail(f"expected a number or '(function args...)', found '{expr.text}'{hint}", expr)
    head = _symbol(expr.items[0], "a function or arithmetic operator") if expr.items else ""
    if not head:
        raise _fail("expected a numeric expression, found '()'", expr)
    if head in _ARITH:
        args = [_num_expr(a, duration) for a in expr.items[1:]]
        if head == "-" and len(args) == 1:
            return BinOp("-", Num(0.0), args[0])
        if len(args) != 2:
            raise _fail(f"'{head}' takes two arguments, got {len(args)}", expr)
        return BinOp(head, args[0], args[1])
    return FuncTerm(_atom(expr))


def _is_numeric(expr: SExpr) -> bool:
    """Whether an argument of ``=`` is numeric (a number or a parenthesised term)."""
    return isinstance(expr, SList) or _number(expr.text) is not None


def _conditions(
    expr: SExpr, out: list[Condition], positive: bool = True, duration: NumExpr | None = None
) -> None:
    """Flatten a goal description (and/not/=/comparisons/atoms) into conditions."""
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
            _conditions(child, out, duration=duration)
    elif head == "not":
        if len(node.items) != 2:
            raise _fail("expected '(not CONDITION)' with one argument", node)
        if not positive:
            raise _fail("double negation is not supported", node)
        _conditions(node.items[1], out, positive=False, duration=duration)
    elif head in _COMPARISONS or (head == "=" and any(map(_is_numeric, node.items[1:]))):
        if len(node.items) != 3:
            raise _fail(f"expected '({head} EXPRESSION EXPRESSION)'", node)
        op = head if positive else _NEGATED[head]
        left, right = (_num_expr(a, duration) for a in node.items[1:])
        out.append(Comparison(op, left, right))
    elif head == "=":
        if len(node.items) != 3:
            raise _fail("expected '(= TERM TERM)'", node)
        out.append(Equality(_term(node.items[1]), _term(node.items[2]), positive))
    else:
        out.append(Literal(_atom(node), positive))


def _effects(
    expr: SExpr,
    out: list[Effect],
    time: EffectTime = EffectTime.END,
    duration: NumExpr | None = None,
) -> None:
    """Flatten an effect (and/not/increase/decrease/assign/atoms) into timed effects."""
    node = _list(expr, "an effect '(...)'")
    if not node.items:
        return
    head = _symbol(node.items[0], "a predicate or 'and'/'not'")
    if head in _UNSUPPORTED_GD:
        raise _fail(
            f"'{head}' needs requirement {_UNSUPPORTED_GD[head]}, which is not supported", node
        )
    if head == "and":
        for child in node.items[1:]:
            _effects(child, out, time, duration)
    elif head == "not" and len(node.items) == 2:
        target = _list(node.items[1], "an atom '(predicate args...)'")
        out.append(AtomEffect(time, Literal(_atom(target), False)))
    elif head == "not":
        raise _fail("malformed 'not' effect: expected '(not ATOM)'", node)
    elif head in _ASSIGN:
        if len(node.items) != 3:
            raise _fail(f"expected '({head} (FUNCTION args...) EXPRESSION)'", node)
        if isinstance(node.items[2], SSym) and node.items[2].text == "#t":
            raise _fail(
                "continuous effects ('#t') need :continuous-effects, which is not supported", node
            )
        target = _list(node.items[1], "a function term '(function args...)'")
        value = _num_expr(node.items[2], duration)
        out.append(NumEffect(time, _ASSIGN[head], _atom(target), value))
    else:
        out.append(AtomEffect(time, Literal(_atom(node), True)))


def _timed_parts(expr: SExpr, what: str) -> list[tuple[str, SExpr, SList]]:
    """``(and (at start X) (over all Y) ...)`` -> [("at start", X, node), ...]."""
    node = _list(expr, f"a durative {what} '(...)'")
    if not node.items:
        return []
    head = _symbol(node.items[0], f"'and', 'at' or 'over' in a durative {what}")
    if head == "and":
        return [part for child in node.items[1:] for part in _timed_parts(child, what)]
    if head in ("at", "over") and len(node.items) == 3 and isinstance(node.items[1], SSym):
        return [(f"{head} {node.items[1].text}", node.items[2], node)]
    raise _fail(
        f"expected '(at start ...)', '(at end ...)' or '(over all ...)' in a durative {what}, "
        f"found '({head} ...)'",
        node,
    )


def _duration(expr: SExpr) -> NumExpr:
    node = _list(expr, "a duration constraint '(= ?duration EXPRESSION)'")
    items = node.items
    head = _symbol(items[0], "'='") if items else ""
    if head in ("<=", ">=", "<", ">", "and"):
        raise _fail(
            f"duration constraint '({head} ...)' needs :duration-inequalities, which is not "
            "supported (TALplanner actions have one fixed duration: '(= ?duration EXPRESSION)')",
            node,
        )
    if head != "=" or len(items) != 3 or _symbol(items[1], "'?duration'") != "?duration":
        raise _fail("expected '(= ?duration EXPRESSION)'", node)
    return _num_expr(items[2])


def _function_decls(body: tuple[SExpr, ...]) -> dict[str, tuple[str, ...]]:
    """``(f ?x - t) (g) - number ...``: numeric functions (object fluents are rejected)."""
    result: dict[str, tuple[str, ...]] = {}
    i = 0
    while i < len(body):
        item = body[i]
        if isinstance(item, SSym):
            if item.text != "-" or i + 1 >= len(body):
                raise _fail(
                    f"expected a function declaration '(name ?x - type)', found '{item.text}'",
                    item,
                )
            kind = _symbol(body[i + 1], "'number'")
            if kind != "number":
                raise _fail(
                    f"function type '{kind}' needs :object-fluents, which is not supported "
                    "(only '- number')",
                    body[i + 1],
                )
            i += 2
            continue
        fname = _symbol(item.items[0], "a function name") if item.items else ""
        if not fname:
            raise _fail("empty function declaration", item)
        result[fname] = tuple(p.type for p in _typed_list(item.items[1:], variables=True))
        i += 1
    return result


def _initial_value(node: SList) -> tuple[Atom, float]:
    """``(= (f o1 o2) 3.5)`` in ``:init``."""
    if len(node.items) != 3 or not isinstance(node.items[1], SList):
        raise _fail("expected '(= (FUNCTION objects...) NUMBER)'", node)
    atom = _atom(node.items[1])
    value = _number(node.items[2].text) if isinstance(node.items[2], SSym) else None
    if value is None:
        raise _fail("expected a number as the initial value of a function", node.items[2])
    if any(t.is_var for t in atom.args):
        raise _fail("initial values must be ground", node)
    return atom, value


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
        functions: dict[str, tuple[str, ...]] = {}
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
            elif key == ":functions":
                functions.update(_function_decls(body))
            elif key == ":action":
                operators.append(self._action(node))
            elif key == ":durative-action":
                operators.append(self._durative_action(node))
            elif key == ":derived":
                raise _fail(
                    "':derived' needs requirement :derived-predicates, which is not supported",
                    node,
                )
            else:
                raise _fail(
                    f"unknown domain section '{key}': expected :requirements, :types, "
                    ":constants, :predicates, :functions, :action or :durative-action",
                    node,
                )
        parents = {t for t in types.values() if union_members(t) is None}
        for parent in parents - set(types) - {ROOT_TYPE}:
            types[parent] = ROOT_TYPE
        return Domain(
            name,
            types,
            constants,
            predicates,
            functions,
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
        effects: list[Effect] = []
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

    def _durative_action(self, node: SList) -> Operator:
        """``:durative-action``: ``at start`` preconditions, ``over all`` prevail conditions."""
        items = node.items
        if len(items) < 2:
            raise _fail("expected an action name after ':durative-action'", node)
        name = _symbol(items[1], "an action name")
        fields: dict[str, SExpr] = {}
        for i in range(2, len(items), 2):
            key = _symbol(items[i], "':parameters', ':duration', ':condition' or ':effect'")
            if key not in (":parameters", ":duration", ":condition", ":effect"):
                raise _fail(
                    f"unexpected '{key}': expected ':parameters', ':duration', ':condition' "
                    "or ':effect'",
                    items[i],
                )
            if i + 1 >= len(items):
                raise _fail(f"expected a value after '{key}'", items[i])
            fields[key] = items[i + 1]
        if ":duration" not in fields:
            raise _fail(f"durative action '{name}' has no ':duration'", node)
        params: tuple[Param, ...] = ()
        if ":parameters" in fields:
            params = _typed_list(_list(fields[":parameters"], "a parameter list").items, True)
        duration = _duration(fields[":duration"])
        pre: list[Condition] = []
        prevail: list[Condition] = []
        conditions = _timed_parts(fields.get(":condition", SList((), node.pos)), "condition")
        for when, cond, where in conditions:
            if when == "at start":
                _conditions(cond, pre, duration=duration)
            elif when == "over all":
                _conditions(cond, prevail, duration=duration)
            else:
                raise _fail(
                    f"'({when} ...)' conditions are not supported by TALplanner's model "
                    "(accepted: 'at start' preconditions and 'over all' prevail conditions)",
                    where,
                )
        effects: list[Effect] = []
        times = {"at start": EffectTime.START, "at end": EffectTime.END}
        for when, eff, where in _timed_parts(fields.get(":effect", SList((), node.pos)), "effect"):
            if when not in times:
                raise _fail(
                    f"'({when} ...)' effects are not supported (accepted: 'at start', 'at end')",
                    where,
                )
            _effects(eff, effects, times[when], duration)
        return Operator(
            name, params, tuple(pre), tuple(effects), duration, None, tuple(prevail), node.pos
        )

    def read_problem(self, text: str, source: str = "<problem>") -> Problem:
        """Parse a PDDL problem; raises PlanningInputError on any problem."""
        top = self._single(text, source, "problem")
        name = _symbol(top.items[0], "a problem name")
        domain_name = ""
        objects: tuple[Param, ...] = ()
        init: list[Atom] = []
        init_values: list[tuple[Atom, float]] = []
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
                        init_values.append(_initial_value(fl))
                        continue
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
        return Problem(
            name, domain_name, objects, tuple(init), tuple(init_values), tuple(goal), {}, source
        )
