"""Parser: ``.hcsm`` text -> :class:`~hdrc3_hcsm.model.Model` via the lark grammar.

Bad input never raises out of :func:`parse_text`: lark errors become diagnostics with
``file:line:column`` and the tokens that were expected.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import lark
from lark import Token, Transformer, v_args
from lark.tree import Meta

from hdrc3_base.syntax_errors import describe
from hdrc3_hcsm.diagnostics import Diagnostic, Severity
from hdrc3_hcsm.model import (
    Action,
    And,
    Automaton,
    CondRef,
    Container,
    EventDecl,
    GetAction,
    Guard,
    Include,
    Model,
    NameDecl,
    Not,
    Or,
    PutAction,
    SendAction,
    SetAction,
    SlotDecl,
    SourcePos,
    State,
    StateKind,
    Transition,
)

# Slots declared without a size get this limit (bytes); the chapter's packets have fixed sizes.
DEFAULT_SLOT_SIZE = 256


class ParseStatus(enum.Enum):
    """Outcome of parsing one file."""

    OK = "ok"
    SYNTAX_ERROR = "syntax_error"
    UNREADABLE = "unreadable"


@dataclass(frozen=True)
class ParseResult:
    """A model (when the syntax was fine) and the diagnostics found while parsing."""

    status: ParseStatus
    model: Model | None
    diagnostics: tuple[Diagnostic, ...]


@cache
def _lark_parser() -> lark.Lark:
    grammar = resources.files("hdrc3_hcsm").joinpath("hcsm.lark").read_text(encoding="utf-8")
    # cache=True: lark keeps the analysed LALR tables in a file of the temp directory, keyed by
    # the grammar's hash (a bad or concurrent cache file is rebuilt): building them took 0.85 s
    # of a restarted kernel's start at load 12 (issue 21)
    return lark.Lark(
        grammar, parser="lalr", propagate_positions=True, maybe_placeholders=False, cache=True
    )


class _Builder(Transformer[Token, Model]):
    """Turn the lark parse tree into frozen dataclasses, keeping positions."""

    def __init__(self, file: str) -> None:
        super().__init__()
        self._file = file

    def _pos(self, item: Meta | Token) -> SourcePos:
        line = getattr(item, "line", 0) or 0
        column = getattr(item, "column", 0) or 0
        return SourcePos(self._file, line, column)

    def _tok(self, token: Token) -> tuple[str, SourcePos]:
        return str(token), self._pos(token)

    # --- declarations -------------------------------------------------------------------
    @v_args(meta=True)
    def header(self, meta: Meta, children: list[Token]) -> tuple[str, Any]:
        return ("header", (str(children[0]), str(children[1]), self._pos(meta)))

    def include_decl(self, children: list[Token]) -> tuple[str, Any]:
        path = str(children[0])[1:-1].replace('\\"', '"').replace("\\\\", "\\")
        return ("includes", (Include(path, self._pos(children[0])),))

    def name_list(self, children: list[Token]) -> tuple[NameDecl, ...]:
        return tuple(NameDecl(str(t), self._pos(t)) for t in children)

    def regions(self, children: list[Token]) -> tuple[str, ...]:
        return tuple(str(t) for t in children)

    def computers(self, children: list[Any]) -> tuple[str, Any]:
        return ("computers", children[0])

    def condition_decl(self, children: list[Any]) -> tuple[str, Any]:
        return ("conditions", children[0])

    def flag_decl(self, children: list[Any]) -> tuple[str, Any]:
        return ("flags", children[0])

    def event_from(self, children: list[Token]) -> tuple[str, str]:
        return ("from", str(children[0]))

    def event_to(self, children: list[Token]) -> tuple[str, str]:
        return ("to", str(children[0]))

    def event_decl(self, children: list[Any]) -> tuple[str, Any]:
        name, ident, *dirs = children
        source = next((v for k, v in dirs if k == "from"), None)
        target = next((v for k, v in dirs if k == "to"), None)
        return ("events", (EventDecl(str(name), int(ident), source, target, self._pos(name)),))

    def slot_decl(self, children: list[Token]) -> tuple[str, Any]:
        size = int(children[1]) if len(children) > 1 else DEFAULT_SLOT_SIZE
        return ("slots", (SlotDecl(str(children[0]), size, self._pos(children[0])),))

    def container_decl(self, children: list[Any]) -> tuple[str, Any]:
        name = children[0]
        return ("containers", (Container(str(name), children[1], self._pos(name)),))

    @v_args(meta=True)
    def root_decl(self, meta: Meta, children: list[Any]) -> tuple[str, Any]:
        return ("root", (children[0], self._pos(meta)))

    # --- automata -----------------------------------------------------------------------
    def state_decl(self, children: list[Token]) -> State:
        kind = StateKind(str(children[0]))
        return State(str(children[1]), kind, (), self._pos(children[1]))

    def super_decl(self, children: list[Any]) -> State:
        name = children[0]
        return State(str(name), StateKind.SUPER, children[1], self._pos(name))

    def trigger(self, children: list[Token]) -> Token:
        return children[0]

    def guard(self, children: list[Guard]) -> Guard:
        return children[0]

    def cond(self, children: list[Token]) -> Guard:
        return CondRef(str(children[0]), self._pos(children[0]))

    def not_op(self, children: list[Guard]) -> Guard:
        return Not(children[0])

    def and_expr(self, children: list[Guard]) -> Guard:
        return And(tuple(children))

    def or_expr(self, children: list[Guard]) -> Guard:
        return Or(tuple(children))

    def actions(self, children: list[Action]) -> tuple[Action, ...]:
        return tuple(children)

    def set_action(self, children: list[Token]) -> Action:
        return SetAction(str(children[0]), self._pos(children[0]))

    def get_action(self, children: list[Token]) -> Action:
        return GetAction(str(children[0]), self._pos(children[0]))

    def put_action(self, children: list[Token]) -> Action:
        return PutAction(str(children[0]), self._pos(children[0]))

    def send_data(self, children: list[Token]) -> tuple[str, str]:
        return ("data", str(children[0]))

    def send_target(self, children: list[Token]) -> tuple[str, str]:
        return ("to", str(children[0]))

    def send_action(self, children: list[Any]) -> Action:
        event, *opts = children
        data = next((v for k, v in opts if k == "data"), None)
        target = next((v for k, v in opts if k == "to"), None)
        return SendAction(str(event), data, target, self._pos(event))

    def transition(self, children: list[Any]) -> Transition:
        tid, source, target, trigger, *rest = children
        guard: Guard | None = None
        actions: tuple[Action, ...] = ()
        for part in rest:
            if isinstance(part, tuple):
                actions = part
            else:
                guard = part
        return Transition(
            str(tid), str(source), str(target), str(trigger), guard, actions, self._pos(tid)
        )

    def automaton(self, children: list[Any]) -> tuple[str, Any]:
        label, name, *members = children
        states = tuple(m for m in members if isinstance(m, State))
        transitions = tuple(m for m in members if isinstance(m, Transition))
        return (
            "automata",
            (Automaton(str(label), str(name), states, transitions, self._pos(label)),),
        )

    def start(self, children: list[tuple[str, Any]]) -> Model:
        parts: dict[str, list[Any]] = {}
        header: tuple[str, str, SourcePos] | None = None
        root: tuple[tuple[str, ...], SourcePos] | None = None
        redeclared: list[tuple[str, SourcePos]] = []
        for key, value in children:
            if key == "header":
                if header is not None:
                    redeclared.append(("model", value[2]))
                header = header or value
            elif key == "root":
                if root is not None:
                    redeclared.append(("root", value[1]))
                root = root or value
            else:
                parts.setdefault(key, []).extend(value)
        return Model(
            file=self._file,
            name=header[0] if header else None,
            computer=header[1] if header else None,
            header_pos=header[2] if header else None,
            computers=tuple(parts.get("computers", ())),
            events=tuple(parts.get("events", ())),
            conditions=tuple(parts.get("conditions", ())),
            flags=tuple(parts.get("flags", ())),
            slots=tuple(parts.get("slots", ())),
            containers=tuple(parts.get("containers", ())),
            automata=tuple(parts.get("automata", ())),
            root=root[0] if root else (),
            root_pos=root[1] if root else None,
            includes=tuple(parts.get("includes", ())),
            redeclared=tuple(redeclared),
        )


def _syntax_diagnostic(exc: lark.exceptions.UnexpectedInput, file: str, text: str) -> Diagnostic:
    problem = describe(exc, _lark_parser(), text, most=12)
    return Diagnostic(
        Severity.ERROR, "E001", problem.message, SourcePos(file, problem.line, problem.column)
    )


def parse_text(text: str, file: str = "<string>") -> ParseResult:
    """Parse ``.hcsm`` text; syntax errors come back as diagnostics, never as exceptions."""
    try:
        tree = _lark_parser().parse(text)
        model = _Builder(file).transform(tree)
    except lark.exceptions.UnexpectedInput as exc:
        return ParseResult(ParseStatus.SYNTAX_ERROR, None, (_syntax_diagnostic(exc, file, text),))
    except lark.exceptions.VisitError as exc:
        # Only out-of-range integers (e.g. huge ids) can fail inside the builder.
        diag = Diagnostic(
            Severity.ERROR, "E002", f"bad value: {exc.orig_exc}", SourcePos(file, 0, 0)
        )
        return ParseResult(ParseStatus.SYNTAX_ERROR, None, (diag,))
    return ParseResult(ParseStatus.OK, model, ())


def parse_file(path: str | Path) -> ParseResult:
    """Read and parse a ``.hcsm`` file; unreadable files give a diagnostic, not an exception."""
    file = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        # ValueError: a path with an embedded NUL byte.
        diag = Diagnostic(Severity.ERROR, "E000", f"cannot read file: {exc}", SourcePos(file, 0, 0))
        return ParseResult(ParseStatus.UNREADABLE, None, (diag,))
    return parse_text(text, file)
