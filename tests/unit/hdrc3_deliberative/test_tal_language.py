from __future__ import annotations

import pytest

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.generators import LOGISTICS_CONTROL, UAV_CONTROL, UAV_DOMAIN, UAV_SCENARIO
from hdrc3_deliberative.model import (
    Atom,
    AtomEffect,
    BinOp,
    Comparison,
    EffectTime,
    Equality,
    FAnd,
    FAtom,
    FCompare,
    FEq,
    FImplies,
    FNot,
    FQuant,
    FuncTerm,
    Num,
    NumEffect,
    RuleKind,
    Term,
    TimeRef,
)
from hdrc3_deliberative.tal_language import TalReader


@pytest.fixture(scope="module")
def reader() -> TalReader:
    return TalReader()


def test_fly_to_of_section_9_1_is_expressible(reader: TalReader) -> None:
    domain = reader.read_domain(UAV_DOMAIN.read_text(), "domain.tal")
    fly = next(op for op in domain.operators if op.name == "fly-to")
    assert fly.agent == "h"
    assert isinstance(fly.duration, FuncTerm) and fly.duration.atom.pred == "flight-time"
    fuel_test = next(c for c in fly.pre if isinstance(c, Comparison))
    assert fuel_test.op == ">="
    assert any(isinstance(c, Equality) and not c.positive for c in fly.pre)
    start = [e for e in fly.effects if e.time is EffectTime.START]
    assert len(start) == 1 and isinstance(start[0], AtomEffect)
    assert start[0].literal.atom.pred == "hovering" and not start[0].literal.positive
    fuel = [e for e in fly.effects if isinstance(e, NumEffect)]
    assert fuel[0].op == "-=" and fuel[0].time is EffectTime.END
    assert "fuel" in domain.resources
    assert domain.types["food-box"] == "box"


def test_prevail_conditions_are_read(reader: TalReader) -> None:
    domain = reader.read_domain(UAV_DOMAIN.read_text())
    put = next(op for op in domain.operators if op.name == "put-on-carrier")
    assert [c.atom.pred for c in put.prevail] == ["at"]  # type: ignore[union-attr]


def test_problem_objects_positions_and_values(reader: TalReader) -> None:
    problem = reader.read_problem(UAV_SCENARIO.read_text())
    assert problem.domain == "uav-logistics"
    assert problem.positions["body1"] == (320.0, 140.0, 0.0)
    values = {(a.pred, a.args[0].name): v for a, v in problem.init_values}
    assert values[("fuel", "heli1")] == 3000.0
    assert len(problem.goal) == 8


def test_control_rule_time_markers(reader: TalReader) -> None:
    spec = reader.read_control(
        "rule r: forall p: package, a: airplane, l: place .\n"
        "  [t] not in(p, a) and at(p, l) and [t+1] in(p, a) -> goal(at(p, l))\n"
        "final f: true\nprefer x, y\nagents truck"
    )
    rule = spec.rules[0]
    assert isinstance(rule.formula, FQuant) and rule.formula.universal
    body = rule.formula.body
    assert isinstance(body, FImplies) and isinstance(body.left, FAnd)
    inner = body.left.args
    # [t] binds the negation only; the untimed atom defaults to t; [t+1] marks the last one
    assert isinstance(inner[0], FAnd)
    neg, at = inner[0].args
    assert isinstance(neg, FNot) and isinstance(neg.arg, FAtom) and neg.arg.time is TimeRef.NOW
    assert isinstance(at, FAtom) and at.time is None
    assert isinstance(inner[1], FAtom) and inner[1].time is TimeRef.NEXT
    assert spec.rules[1].kind is RuleKind.FINAL
    assert spec.prefer == ("x", "y") and spec.agent_types == ("truck",)


@pytest.mark.parametrize("path", [LOGISTICS_CONTROL, UAV_CONTROL])
def test_shipped_control_files_parse(reader: TalReader, path: object) -> None:
    spec = reader.read_control(path.read_text(), str(path))  # type: ignore[attr-defined]
    assert len(spec.rules) >= 6


@pytest.mark.parametrize(
    ("kind", "text", "position", "message"),
    [
        ("domain", "domain d\noperator x(a: t)\n  pre p(a\nend", "4:1", "expected"),
        ("domain", "domain d\ntype a\nfoo", "3:1", "unexpected 'foo'"),
        ("domain", "domain d\noperator x() effect [t] p() end", "2:21", "unexpected '[t]'"),
        ("control", "rule r: forall x: a . [t] p(x) ->", "1:34", "unexpected end of file"),
        ("control", "rule r: p(x) < < q(x)", "1:16", "unexpected '<'"),
        ("control", "rule r: x < y", "1:11", "expected '=' or '!=' between objects"),
        ("control", "rule r: fuel(a) > x", "1:17", "'x' is an object, not a number"),
        ("control", "operator x() end", "1:1", "not allowed in a control file"),
        ("problem", "problem p for d\ninit f(a) < 3", "2:11", "expected '='"),
        ("domain", "type a", "1:1", "missing 'domain NAME'"),
    ],
)
def test_syntax_errors(
    reader: TalReader, kind: str, text: str, position: str, message: str
) -> None:
    read = {
        "domain": reader.read_domain,
        "problem": reader.read_problem,
        "control": reader.read_control,
    }[kind]
    with pytest.raises(PlanningInputError) as err:
        read(text, "x.tal")
    assert str(err.value).startswith(f"x.tal:{position}:"), str(err.value)
    assert message in str(err.value)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("rule r: fuel(a) >= 3", FCompare(">=", FuncTerm(Atom("fuel", (Term("a"),))), Num(3.0))),
        (
            "rule r: [t+1] fuel(a) < cap(a) - 1",
            FCompare(
                "<",
                FuncTerm(Atom("fuel", (Term("a"),))),
                BinOp("-", FuncTerm(Atom("cap", (Term("a"),))), Num(1.0)),
                TimeRef.NEXT,
            ),
        ),
        ("rule r: a != b", FEq(Term("a"), Term("b"), False)),
    ],
)
def test_control_comparisons(reader: TalReader, text: str, expected: object) -> None:
    """Two bare names compare objects; anything with a function term or number is numeric."""
    rule = reader.read_control(text, "c.tal").rules[0]
    assert rule.formula == expected
