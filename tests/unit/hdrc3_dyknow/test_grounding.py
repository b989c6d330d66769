"""Grounding: identifier resolution, EXEC, quantifier expansion and errors."""

from __future__ import annotations

import pytest

from hdrc3_dyknow.formula_parser import FormulaParser
from hdrc3_dyknow.grounding import GroundingError, Scope, compile_formula, quantified_sorts
from hdrc3_dyknow.residual import NodeTable, to_formula

PARSER = FormulaParser()
SCOPE = Scope(
    domains={"AV": ("uav0", "uav1"), "BOX": ("box1",)},
    bindings={"av": "uav0"},
    exec_flag="executing-pickup-box(uav0, box1)",
)


@pytest.mark.parametrize(
    ("text", "ground"),
    [
        ("carrying(av, box1)", "carrying(uav0, box1)"),  # binding, object as written
        ("carrying(av, box9)", "carrying(uav0, box9)"),
        ("EXEC", "executing-pickup-box(uav0, box1)"),
        ("forall x in AV: p(x)", "p(uav0) and p(uav1)"),
        ("exists x in AV: p(x)", "p(uav0) or p(uav1)"),
        ("forall x in AV: x != uav0 implies near(x, av)", "near(uav1, uav0)"),
        ("forall x in AV: x == x and 2 * 3 > 5", "true"),
        ("box1 < 3", "box1 < 3"),  # ill-typed: left for progression to report
        ("location(box1) == depot", "location(box1) == depot"),  # depot: a 0-ary fluent
        ("location(box1) == av", "location(box1) == uav0"),  # bound variable: an object
        (
            "forall b in BOX: exists x in AV: carrying(x, b)",
            "carrying(uav0, box1) or carrying(uav1, box1)",
        ),
        ("always forall x in AV: speed(x) < 3", "always (speed(uav0) < 3 and speed(uav1) < 3)"),
    ],
)
def test_ground_forms(text: str, ground: str) -> None:
    table = NodeTable()
    node = compile_formula(table, PARSER.parse(text), SCOPE)
    assert str(to_formula(node)) == ground


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("forall x in TRUCK: p(x)", "unknown sort 'TRUCK'"),
        ("forall x in AV: x", "variable 'x' used as a boolean fluent"),
        ("av", "variable 'av' used as a boolean fluent"),
    ],
)
def test_grounding_errors(text: str, message: str) -> None:
    with pytest.raises(GroundingError, match=message):
        compile_formula(NodeTable(), PARSER.parse(text), SCOPE)


def test_quantified_sorts() -> None:
    formula = PARSER.parse("always (forall x in AV: p(x)) until exists b in BOX: q(b) or r")
    assert quantified_sorts(formula) == {"AV", "BOX"}
