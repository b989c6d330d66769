"""Direct finite-trace evaluation, and progression checked against it with hypothesis."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hdrc3_dyknow.evaluation import evaluate
from hdrc3_dyknow.formula import (
    Always,
    And,
    Atom,
    CompareOp,
    Comparison,
    Constant,
    Eventually,
    FluentTerm,
    Formula,
    Implies,
    Interval,
    Not,
    Number,
    Or,
    Quantified,
    Quantifier,
    Until,
)
from hdrc3_dyknow.formula_parser import FormulaParser
from hdrc3_dyknow.grounding import Scope
from hdrc3_dyknow.interpretation import State, StateOrderError, UnknownFluentError
from hdrc3_dyknow.progression import ProgressionEngine, Progressor, Verdict
from hdrc3_dyknow.residual import NodeTable

PARSER = FormulaParser()
SCOPE = Scope(domains={"S": ("a", "b")})


def trace_of(times: list[float], **columns: list[object]) -> list[State]:
    return [
        State(time, {name: values[i] for name, values in columns.items()})  # type: ignore[misc]
        for i, time in enumerate(times)
    ]


@pytest.mark.parametrize(
    ("text", "times", "p", "expected"),
    [
        ("always p", [0, 100, 200], [True, True, True], True),
        ("always p", [0, 100, 200], [True, False, True], False),
        ("always[100,100] p", [0, 100, 200], [False, True, False], True),
        ("always[101,199] p", [0, 100, 200], [False, False, False], True),  # no state in window
        ("eventually[0,150] p", [0, 100, 200], [False, False, True], False),
        ("eventually[0,200] p", [0, 100, 200], [False, False, True], True),  # closed upper edge
        ("eventually[5,3] p", [0, 1, 2, 3, 4, 5], [True] * 6, False),  # empty interval
        ("always[5,3] p", [0, 1, 2, 3, 4, 5], [False] * 6, True),
        ("eventually p", [0, 100], [False, False], False),  # strong end of trace
        ("p until[0,100] not p", [0, 100, 200], [True, True, False], False),
        ("p until[0,200] not p", [0, 100, 200], [True, True, False], True),
        ("p until not p", [0, 7, 300], [False, True, True], True),  # psi at once: phi unneeded
    ],
)
def test_evaluate_operator_table(
    text: str, times: list[float], p: list[bool], expected: bool
) -> None:
    assert evaluate(PARSER.parse(text), trace_of(times, p=p)) is expected


def test_nested_fluent_terms_agree_between_evaluation_and_progression() -> None:
    """``wind(at(av))`` reads the wind of whatever location ``at(av)`` names in each state."""
    formula = PARSER.parse("always (wind(at(av)) < 10 or gusty(at(av)))")
    trace = [
        State(0, {"at(av)": "d1", "wind(d1)": 5.0, "wind(d2)": 15.0, "gusty(d1)": False,
                  "gusty(d2)": True}),
        State(100, {"at(av)": "d2", "wind(d1)": 5.0, "wind(d2)": 15.0, "gusty(d1)": False,
                    "gusty(d2)": True}),
        State(200, {"at(av)": "d2", "wind(d1)": 5.0, "wind(d2)": 15.0, "gusty(d1)": False,
                    "gusty(d2)": False}),
    ]  # fmt: skip
    for end, expected in ((2, True), (3, False)):
        assert evaluate(formula, trace[:end]) is expected
        progressor = Progressor(formula)
        verdicts = [progressor.update(state) for state in trace[:end]]
        assert (verdicts[-1] is not Verdict.FALSE) is expected


def test_evaluate_rejects_bad_traces() -> None:
    with pytest.raises(StateOrderError):
        evaluate(PARSER.parse("p"), [])
    with pytest.raises(StateOrderError):
        evaluate(PARSER.parse("p"), trace_of([5, 5], p=[True, True]))
    with pytest.raises(UnknownFluentError, match="'q'"):
        evaluate(PARSER.parse("q"), trace_of([0], p=[True]))


# ---- progression against the direct evaluator ---------------------------------------------

BOUNDS = [0.0, 40.0, 100.0, 150.0, 300.0]
ATOMS: list[Formula] = [
    Atom(FluentTerm("p")),
    Atom(FluentTerm("q")),
    Atom(FluentTerm("r", ("v",))),
    Comparison(CompareOp.GT, FluentTerm("x"), Number(0.5)),
    Constant(True),
    Constant(False),
]
intervals = st.builds(
    Interval,
    st.sampled_from(BOUNDS),
    st.sampled_from([*BOUNDS, math.inf]),
)


def _extend(children: st.SearchStrategy[Formula]) -> st.SearchStrategy[Formula]:
    pairs = st.tuples(children, children)
    return st.one_of(
        children.map(Not),
        pairs.map(lambda ab: And(ab)),
        pairs.map(lambda ab: Or(ab)),
        pairs.map(lambda ab: Implies(*ab)),
        st.builds(Always, intervals, children),
        st.builds(Eventually, intervals, children),
        st.builds(Until, intervals, children, children),
        st.builds(Quantified, st.sampled_from(Quantifier), st.just("v"), st.just("S"), children),
    )


formulas = st.recursive(st.sampled_from(ATOMS), _extend, max_leaves=8)


@st.composite
def traces(draw: st.DrawFn) -> list[State]:
    gaps = draw(st.lists(st.integers(1, 160), min_size=0, max_size=7))
    times = [0.0]
    for gap in gaps:
        times.append(times[-1] + gap)
    states = []
    for time in times:
        values = {key: draw(st.booleans()) for key in ("p", "q", "r(a)", "r(b)", "r(v)")} | {
            "x": draw(st.sampled_from([0.0, 1.0]))
        }
        states.append(State(time, values))
    return states


def check_against_evaluator(formula: Formula, trace: list[State], intern: bool) -> None:
    engine = ProgressionEngine(NodeTable(intern_residuals=intern))
    ident = engine.add(formula, SCOPE)
    final = evaluate(formula, trace, SCOPE)
    for k, state in enumerate(trace, start=1):
        engine.update(state)
        # Closing the residual is the verdict on the prefix as a complete trace ...
        assert engine.close(ident) == evaluate(formula, trace[:k], SCOPE)
        # ... and a decided verdict holds for every extension, here the full trace.
        verdict = engine.verdict(ident)
        if verdict != Verdict.UNDECIDED:
            assert (verdict == Verdict.TRUE) == final


@given(formulas, traces(), st.booleans())
def test_progression_agrees_with_direct_evaluation(
    formula: Formula, trace: list[State], intern: bool
) -> None:
    check_against_evaluator(formula, trace, intern)


@given(formulas)
def test_printed_formulas_parse_back(formula: Formula) -> None:
    assert PARSER.parse(str(formula)) == formula


# Monitor-shaped formulas: repeated obligations make the tense merging rules fire.
TEMPLATES = [
    "always(not p implies eventually[0,{a}] always[0,{b}] p)",
    "always(p implies eventually[{c},{a}] q)",
    "always(p implies always[0,{a}] q)",
    "always(not p implies eventually[0,{a}] always[{c},{b}] p) or eventually[0,{b}] q",
    "always(p implies (q until[0,{a}] r(a)))",
    "eventually(p and always[0,{a}] not q)",
]
monitor_formulas = st.builds(
    lambda template, a, b, c: PARSER.parse(template.format(a=a, b=b, c=c)),
    st.sampled_from(TEMPLATES),
    st.integers(0, 400),
    st.integers(0, 400),
    st.integers(0, 100),
)


@st.composite
def long_traces(draw: st.DrawFn) -> list[State]:
    gaps = draw(st.lists(st.integers(1, 160), min_size=3, max_size=16))
    times = [0.0]
    for gap in gaps:
        times.append(times[-1] + gap)
    keys = ("p", "q", "r(a)")
    return [State(time, {key: draw(st.booleans()) for key in keys}) for time in times]


@given(monitor_formulas, long_traces(), st.booleans())
def test_progression_of_monitor_formulas_agrees(
    formula: Formula, trace: list[State], intern: bool
) -> None:
    check_against_evaluator(formula, trace, intern)
