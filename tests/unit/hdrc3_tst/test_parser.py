from __future__ import annotations

import logging
from collections.abc import Callable
from pathlib import Path
from typing import Any

import lark
import pytest

from hdrc3_deliberative.mission_syntax import (
    Cmp,
    Comparison,
    ConsRef,
    LinExpr,
    Membership,
    Name,
    Number,
    Term,
)
from hdrc3_tst.parser import ParseStatus, parse_file, parse_text
from hdrc3_tst.syntax import (
    ActionTask,
    ConcurrentTask,
    ConsDef,
    ForeachTask,
    IfTask,
    SequenceTask,
    TstDef,
    WhileTask,
)

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "tst"


def test_example_6_2_parses_as_written_in_the_chapter() -> None:
    result = parse_file(EXAMPLES / "example_6_2.tst")
    assert result.status is ParseStatus.OK and result.tree is not None
    tau0 = result.tree.tsts()[0]
    assert (tau0.name, tau0.params, tau0.with_vars) == (
        "tau0",
        ("TS0", "TE0"),
        ("TS1", "TE1", "TS4", "TE4"),
    )
    assert isinstance(tau0.task, SequenceTask)
    tau1, tau4 = tau0.task.children
    assert isinstance(tau1.task, ConcurrentTask)
    assert [c.name for c in tau1.task.children] == ["tau2", "tau3"]
    # The where clauses belong to the composite nodes, as the constraint sets' names say.
    assert tau1.where == (ConsRef(Name("cons_tau1")),)
    assert tau0.where == (ConsRef(Name("cons_tau0")),)
    assert tau4.where == () and tau1.task.children[1].where == ()
    assert tau1.task.children[0].task == ActionTask(
        "scan-area", (Name("TS2"), Name("TE2"), Name("Speed2"), Name("AreaA"))
    )
    defs = {i.name: i for i in result.tree.items if isinstance(i, ConsDef)}
    assert len(defs["cons_tau0"].constraints) == 5 and len(defs["cons_tau1"].constraints) == 6
    first = defs["cons_tau0"].constraints[1]
    assert isinstance(first, Comparison) and first.op is Cmp.LT
    assert (first.pos.line, first.pos.column) == (18, 32)


def test_every_construct() -> None:
    text = """
    m(P, TS, TE) = with A, B sequence
      c(TS, TE) = if [TS] not low(P, 3) then x(TS, TE) = wait(TS, TE, 1)
      else y(TS, TE) = goal g(a, -2)
      where true;
      w(TS, TE) = while ok() z(TS, TE) = call lib(TS, TE) where TE - TS <= 2 * A + -1;
      f(TS, TE) = foreach V, W where [TS] seen(V, W) do conc v(TS, TE) = hover(TS, TE, 1.5e1)
      where P in {uav0, uav1}
    where P != uav1
    """
    result = parse_text(text)
    assert result.status is ParseStatus.OK and result.tree is not None
    m = result.tree.tsts()[0]
    c, w, f = m.children()
    assert isinstance(c.task, IfTask) and c.task.cond.negated and c.task.cond.time == "TS"
    assert c.task.cond.args == (Name("P"), Number(3.0))
    assert isinstance(w.task, WhileTask) and w.task.body.task.__class__.__name__ == "CallTask"
    assert w.where == (
        Comparison(
            Expr_(Term(1.0, Name("TE")), Term(-1.0, Name("TS"))),
            Cmp.LE,
            Expr_(Term(2.0, Name("A")), Term(-1.0)),
        ),
    )
    assert isinstance(f.task, ForeachTask) and f.task.vars == ("V", "W")
    assert f.task.body.task == ActionTask("hover", (Name("TS"), Name("TE"), Number(15.0)))
    assert f.where == (Membership(Name("P"), (Name("uav0"), Name("uav1"))),)
    goal = c.task.orelse.task
    assert goal.args == (Name("a"), Number(-2.0))  # type: ignore[union-attr]


def Expr_(*terms: Term):
    return LinExpr(terms)


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ("t(TS, TE) = sequence", "1:21", "unexpected end of file; expected one of: NAME"),
        ("t(TS, TE) = fly-to(TS, $)", "1:24", "unexpected '$'"),
        ("t(TS TE) = wait(TS, TE, 1)", "1:6", "unexpected 'TE'; expected one of: ')'"),
        (
            "t(TS, TE) = sequence\n a(TS, TE) = sequence b(TS, TE) = wait(TS, TE, 1);\n c(TS, TE) = wait(TS, TE, 1)",  # noqa: E501
            "3:29",
            "expected one of: 'where' (a composite child ends with a where clause",
        ),
        ("t(TS, TE) = wait(TS, TE, 1) where TS <", "1:39", "unexpected end of file"),
        ("area A = polygon((0, 0), (1, x))", "1:30", "unexpected 'x'"),
    ],
)
def test_syntax_errors_say_where_and_what_was_expected(text: str, where: str, message: str) -> None:
    result = parse_text(text, "bad.tst")
    assert result.status is ParseStatus.SYNTAX_ERROR and result.tree is None
    (diag,) = result.diagnostics
    assert str(diag).startswith(f"bad.tst:{where}: error E001: ")
    assert message in diag.message


def test_a_number_too_large_for_a_float_is_reported() -> None:
    result = parse_text("t(TS, TE) = wait(TS, TE, 1e999)", "big.tst")
    assert result.status is ParseStatus.SYNTAX_ERROR
    assert "out of range" in result.diagnostics[0].message


@pytest.mark.parametrize("path", ["/nonexistent/x.tst", "\0bad"])
def test_unreadable_files_give_a_diagnostic(path: str) -> None:
    result = parse_file(path)
    assert result.status is ParseStatus.UNREADABLE
    assert result.diagnostics[0].code == "E000"


def test_the_grammar_has_no_lalr_conflicts(caplog: pytest.LogCaptureFixture) -> None:
    grammar = (Path(__file__).resolve().parents[3] / "hdrc3_tst" / "tst.lark").read_text()
    lark.logger.setLevel(logging.DEBUG)
    try:
        with caplog.at_level(logging.DEBUG, logger="lark"):
            lark.Lark(grammar, parser="lalr", debug=True, maybe_placeholders=True)
    finally:
        lark.logger.setLevel(logging.WARNING)
    assert not [r for r in caplog.records if "conflict" in r.getMessage()]


def test_tstdef_children_in_order() -> None:
    result = parse_text(
        "t(TS, TE) = concurrent a(TS, TE) = wait(TS, TE, 1); b(TS, TE) = land(TS, TE)"
    )
    assert result.tree is not None
    t = result.tree.tsts()[0]
    assert [c.name for c in t.children()] == ["a", "b"]
    assert all(isinstance(c, TstDef) and c.children() == () for c in t.children())


def test_declarations_and_lists() -> None:
    text = (
        "agents a1, a2,\n  a3\n"
        "area F = polygon((-1, 0), (2, -3.5), (4, 5))\n"
        "path R = (p, q, r)\n"
        "c = true and X - Y + 2 * Z - 3 >= -1 and true and X in {a1, -2, 4}\n"
    )
    result = parse_text(text, "d.tst")
    assert result.status is ParseStatus.OK and result.tree is not None
    agents, area, path, cons = result.tree.items
    assert agents.names == ("a1", "a2", "a3") and (agents.pos.line, agents.pos.column) == (1, 8)
    assert area.vertices == ((-1.0, 0.0), (2.0, -3.5), (4.0, 5.0))
    assert path.points == ("p", "q", "r")
    assert isinstance(cons, ConsDef)
    assert cons.constraints == (  # `true` is dropped wherever it stands
        Comparison(
            Expr_(Term(1.0, Name("X")), Term(-1.0, Name("Y")), Term(2.0, Name("Z")), Term(-3.0)),
            Cmp.GE,
            Expr_(Term(-1.0)),
        ),
        Membership(Name("X"), (Name("a1"), Number(-2.0), Number(4.0))),
    )
    assert all(type(n) is str for n in (*agents.names, *path.points))


@pytest.mark.parametrize(
    ("text", "check"),
    [
        # A keyword is one only where the grammar takes it (lark's contextual lexer).
        ("agents at, in, world", lambda t: t.items[0].names == ("at", "in", "world")),
        ("m(TS, TE) = path(TS, TE)", lambda t: t.tsts()[0].task.name == "path"),
        # Where only a keyword fits, it is matched even when letters follow it.
        (
            "m(T) = foreach X where c(X) do concn(T) = wait(T, 1)",
            lambda t: t.tsts()[0].task.body.name == "n",
        ),
    ],
)
def test_keywords_depend_on_the_context(text: str, check: Callable[[Any], bool]) -> None:
    result = parse_text(text)
    assert result.status is ParseStatus.OK and result.tree is not None
    assert check(result.tree)


def test_a_constant_too_large_in_a_constraint_is_reported() -> None:
    result = parse_text("t(TS, TE) = wait(TS, TE, 1) where TE <= 2e999 * TS", "big.tst")
    assert result.status is ParseStatus.SYNTAX_ERROR
    assert "out of range" in result.diagnostics[0].message
