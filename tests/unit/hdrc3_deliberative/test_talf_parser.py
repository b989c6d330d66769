"""TALF parser: trees of good input, located diagnostics of bad input."""

from __future__ import annotations

from pathlib import Path

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
from hdrc3_deliberative.talf_diagnostics import TalfStatus
from hdrc3_deliberative.talf_formulas import And, Atom, Exists, Not
from hdrc3_deliberative.talf_parser import parse_file, parse_text
from hdrc3_deliberative.talf_syntax import (
    ActionTerm,
    CAct,
    Concurrent,
    Foreach,
    If,
    Interval,
    Mission,
    Sequence,
    While,
)


def _var(name: str, coef: float = 1.0) -> LinExpr:
    return LinExpr((Term(coef, Name(name)),))


def _mission(text: str) -> CAct:
    parsed = parse_text(f"mission m: {text}")
    assert parsed.status is TalfStatus.OK, parsed.diagnostics
    assert parsed.tree is not None
    return parsed.tree.missions()[0].body


T = Interval("t", "t2")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("[t, t2] hover(5)", CAct(T, ActionTerm("hover", (Number(5.0),)))),
        (
            "[t, t2] by av with u, u2 do [u, u2] fly-to(-3, Dest)",
            CAct(
                T,
                ActionTerm("fly-to", (Number(-3.0), Name("Dest")), Interval("u", "u2")),
                ("u", "u2"),
                None,
                "av",
            ),
        ),
        (
            "[t, t2] ([a, b] land() ; [c, d] take-off())",
            CAct(
                T,
                Sequence(
                    (
                        CAct(Interval("a", "b"), ActionTerm("land", ())),
                        CAct(Interval("c", "d"), ActionTerm("take-off", ())),
                    )
                ),
            ),
        ),
        (
            "[t, t2] ([a, b] land())",
            CAct(T, Sequence((CAct(Interval("a", "b"), ActionTerm("land", ())),))),
        ),
        (
            "[t, t2] ([a, b] land() || [c, d] land())",
            CAct(
                T,
                Concurrent(
                    (
                        CAct(Interval("a", "b"), ActionTerm("land", ())),
                        CAct(Interval("c", "d"), ActionTerm("land", ())),
                    )
                ),
            ),
        ),
        (
            "[t, t2] if [t] not airborne(P) then [t, t2] take-off() else [t, t2] hover(1)",
            CAct(
                T,
                If(
                    Not(Atom("airborne", (Name("P"),), "t")),
                    CAct(T, ActionTerm("take-off", ())),
                    CAct(T, ActionTerm("hover", (Number(1.0),))),
                ),
            ),
        ),
        (
            "[t, t2] while [c] exists x (owns(x)) do [t, t2] hover(1) where true where t2 - t <= 9",
            CAct(
                T,
                While(
                    Exists(("x",), Atom("owns", (Name("x"),), "c")),
                    CAct(T, ActionTerm("hover", (Number(1.0),))),
                ),
                where=Comparison(
                    LinExpr((Term(1.0, Name("t2")), Term(-1.0, Name("t")))),
                    Cmp.LE,
                    LinExpr((Term(9.0),)),
                ),
            ),
        ),
        (
            "[t, t2] foreach av where [t] can-scan(av) do conc [t, t2] by av land()",
            CAct(
                T,
                Foreach(
                    ("av",),
                    Atom("can-scan", (Name("av"),), "t"),
                    CAct(T, ActionTerm("land", ()), agent="av"),
                ),
            ),
        ),
        (
            "[t, t2] land() where a = b = 2 * c and P in {uav0, 1} and cons1",
            CAct(
                T,
                ActionTerm("land", ()),
                where=And(
                    (
                        Comparison(_var("a"), Cmp.EQ, _var("b")),
                        Comparison(_var("b"), Cmp.EQ, _var("c", 2.0)),
                        Membership(Name("P"), (Name("uav0"), Number(1.0))),
                        ConsRef(Name("cons1")),
                    )
                ),
            ),
        ),
        (
            # [t] scopes over the whole formula after it, as in the chapter's where clauses
            "[t, t2] land() where [t] a(x) and b(x) and t = t2",
            CAct(
                T,
                ActionTerm("land", ()),
                where=And(
                    (
                        Atom("a", (Name("x"),), "t"),
                        Atom("b", (Name("x"),), "t"),
                        Comparison(_var("t"), Cmp.EQ, _var("t2")),
                    )
                ),
            ),
        ),
    ],
)
def test_composite_actions_parse_to_their_trees(text: str, expected: CAct) -> None:
    assert _mission(text) == expected


def test_labels_and_positions_do_not_take_part_in_equality() -> None:
    labelled = _mission("top: [t, t2] (a: [u, u2] land())")
    assert labelled.label == "top"
    assert labelled.children()[0].label == "a"
    assert (labelled.pos.line, labelled.pos.column) == (1, 12)
    assert labelled == _mission("[t, t2] ([u, u2] land())")


def test_a_file_keeps_its_items_in_order(tmp_path: Path) -> None:
    file = tmp_path / "f.talf"
    file.write_text(
        "world revinge\nagents uav0, uav1\narea A = polygon((0, 0), (1, 0), (1, 1))\n"
        "point P = H1 at 20\npoint Q = (1, -2, 3)\npath R = (P, Q)\nopen S\n"
        "constraint c = t <= t2\n[t, t2] x(a) ~> [t, t2] land()\nmission m: [t, t2] land()\n"
    )
    parsed = parse_file(file)
    assert parsed.tree is not None
    kinds = [type(i).__name__ for i in parsed.tree.items]
    assert kinds == [
        "WorldDecl",
        "AgentsDecl",
        "AreaDecl",
        "PointDecl",
        "PointDecl",
        "PathDecl",
        "OpenDecl",
        "ConstraintDef",
        "CompositeSpec",
        "Mission",
    ]
    assert parsed.tree.agents() == ("uav0", "uav1")
    assert parsed.tree.places() == {"A": "area", "P": "point", "Q": "point", "R": "path"}
    assert parsed.tree.open_names() == ("S",)
    assert parsed.tree.missions() == (Mission("m", CAct(T, ActionTerm("land", ()))),)


@pytest.mark.parametrize(
    ("text", "where", "reason"),
    [
        ("mission m: [t, t2]", "1:19", "unexpected end of file"),
        ("mission m: [t t2] land()", "1:15", "unexpected 't2'; expected one of: ','"),
        ("mission m: [t, t2] (\n  [a, b] land() ;\n)", "3:1", "unexpected ')'"),
        ("mission m: [t, t2] land() where", "1:32", "unexpected end of file"),
        ("mission m: [t, t2] land() where x ==", "1:36", "unexpected '='"),
        ("mission m: [t, t2] land(1e999)", "0:0", "bad value"),
        ("mission m: [t, t2] land() $", "1:27", "unexpected '$'"),
    ],
)
def test_syntax_errors_carry_file_line_column(text: str, where: str, reason: str) -> None:
    parsed = parse_text(text, "bad.talf")
    assert parsed.status is TalfStatus.SYNTAX_ERROR
    assert parsed.tree is None
    (diag,) = parsed.diagnostics
    assert f"{diag.pos.line}:{diag.pos.column}" == where
    assert str(diag).startswith(f"bad.talf:{where}: error T00")
    assert reason in diag.message


def test_an_unreadable_file_is_a_diagnostic(tmp_path: Path) -> None:
    parsed = parse_file(tmp_path / "missing.talf")
    assert parsed.status is TalfStatus.UNREADABLE
    assert "cannot read file" in parsed.diagnostics[0].message
