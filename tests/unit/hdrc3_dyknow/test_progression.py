"""Progression (Definition 9.3) against hand-computed verdicts, state by state."""

from __future__ import annotations

import pytest

from hdrc3_dyknow.evaluation import evaluate
from hdrc3_dyknow.formula_parser import FormulaParser
from hdrc3_dyknow.grounding import GroundingError, Scope
from hdrc3_dyknow.interpretation import (
    FluentTypeError,
    FluentValue,
    State,
    StateOrderError,
    UnknownFluentError,
)
from hdrc3_dyknow.progression import ProgressionEngine, Progressor, UnknownMonitorError, Verdict

PARSER = FormulaParser()
LETTER = {"U": Verdict.UNDECIDED, "T": Verdict.TRUE, "F": Verdict.FALSE}
OBLIGATION = "always(not p implies eventually[0,1000] always[0,999] p)"
OBLIGATION_RESIDUAL = "always (p or eventually[0,1000] always[0,999] p)"
AV = Scope(domains={"AV": ("uav0", "uav1")})


def verdicts(text: str, states: list[State], scope: Scope | None = None) -> str:
    progressor = Progressor(PARSER.parse(text), scope)
    letters = {verdict: letter for letter, verdict in LETTER.items()}
    return "".join(letters[progressor.update(state)] for state in states)


def bool_trace(times: list[float], p: str, q: str | None = None) -> list[State]:
    """States at ``times`` with p (and q) given as strings of T/F."""
    states = []
    for i, time in enumerate(times):
        values: dict[str, FluentValue] = {"p": p[i] == "T"}
        if q is not None:
            values["q"] = q[i] == "T"
        states.append(State(time, values))
    return states


@pytest.mark.parametrize(
    ("text", "times", "p", "expected"),
    [
        ("p", [0], "T", "T"),
        ("not p", [0], "T", "F"),
        ("true", [0], "F", "T"),
        ("false", [0], "T", "F"),
        ("always p", [0, 100, 200], "TTF", "UUF"),
        ("eventually p", [0, 100, 200], "FFT", "UUT"),
        ("eventually[0,1000] p", [0, 500], "FT", "UT"),
        ("eventually[0,1000] p", [0, 1000], "FT", "UT"),  # closed upper edge
        ("eventually[0,1000] p", [0, 1000], "FF", "UF"),  # window over, no later state counts
        ("eventually[0,1000] p", [0, 900, 1001], "FFT", "UUF"),  # decided by a later state
        ("always[0,1000] p", [0, 1000, 1001], "TTF", "UTT"),
        ("always[0,1000] p", [0, 999, 1001], "TTF", "UUT"),
        ("always[500,1000] p", [0, 400, 600, 1000], "FFTT", "UUUT"),
        ("always[500,1000] p", [0, 400, 600, 1000], "FFTF", "UUUF"),
        ("eventually[100,200] p", [0, 150], "TT", "UT"),
        ("eventually[100,200] p", [0, 250], "TT", "UF"),  # irregular gap skips the window
        ("eventually[100,200] p", [0, 99, 100], "TTF", "UUU"),  # lower edge inclusive
        ("eventually[5,3] p", [0, 4], "TT", "FF"),  # empty interval
        ("always[5,3] p", [0, 4], "FF", "TT"),
        ("always eventually[0,100] p", [0, 100, 150, 300], "FTFF", "UUUF"),
        ("not eventually[0,100] p", [0, 50, 101], "FFT", "UUT"),
        ("eventually[0,100] p or always[0,50] not p", [0, 60], "FT", "UT"),
        ("eventually[0,100] p and always[0,50] not p", [0, 40, 60], "FFT", "UUT"),
        (OBLIGATION, [0, 100, 200], "TTT", "UUU"),
        # Irregular sampling: the attempt started at 30 ms covers [30, 1029] and succeeds.
        (OBLIGATION, [0, 30, 700, 1650, 1700], "FTTTT", "UUUUU"),
        # No 1000 ms stretch of p can start within 1000 ms of 0: violated at 1100.
        (OBLIGATION, [0, 30, 700, 1100], "FTFF", "UUUF"),
        (OBLIGATION, [0, 100, *range(200, 1100, 100)], "FF" + "T" * 9, "U" * 11),
        (OBLIGATION, [0, 100, *range(200, 1100, 100), 1100], "FF" + "T" * 9 + "F", "U" * 11 + "F"),
    ],
)
def test_single_fluent_table(text: str, times: list[float], p: str, expected: str) -> None:
    assert verdicts(text, bool_trace(times, p)) == expected


@pytest.mark.parametrize(
    ("text", "times", "p", "q", "expected"),
    [
        ("p until[0,300] q", [0, 100, 250], "TTF", "FFT", "UUT"),
        ("p until[0,300] q", [0, 100, 250], "TFF", "FFT", "UFF"),
        ("p until[0,300] q", [0, 100, 301], "TTT", "FFT", "UUF"),
        ("p until[200,300] q", [0, 100, 200], "TTT", "TFT", "UUT"),  # q at 0 is too early
        ("p until[200,300] q", [0, 100, 200], "TFT", "TFT", "UFF"),  # p must hold before 200
        ("p until q", [0], "F", "T", "T"),  # psi at once: phi is not needed
        ("(p until q) until[0,10] p", [0, 5], "FT", "TF", "UT"),
    ],
)
def test_until_table(text: str, times: list[float], p: str, q: str, expected: str) -> None:
    assert verdicts(text, bool_trace(times, p, q)) == expected


@pytest.mark.parametrize(
    ("text", "rows", "expected"),
    [
        ("forall x in AV: always speed(x) < 50", [(10, 20), (30, 60)], "UF"),
        ("exists x in AV: always speed(x) < 50", [(10, 60), (30, 20)], "UU"),
        ("exists x in AV: always speed(x) < 50", [(70, 60)], "F"),
        ("exists x in AV: eventually[0,100] speed(x) > 50", [(10, 20), (10, 60)], "UT"),
        (
            "forall x in AV: x != uav0 implies always speed(x) <= 2 * speed(uav0)",
            [(10, 20), (10, 21)],
            "UF",
        ),
        ("always speed(uav0) - speed(uav1) / 2 >= -5", [(10, 30), (0, 11)], "UF"),
    ],
)
def test_quantifier_and_arithmetic_table(
    text: str, rows: list[tuple[float, float]], expected: str
) -> None:
    states = [
        State(100.0 * i, {"speed(uav0)": a, "speed(uav1)": b}) for i, (a, b) in enumerate(rows)
    ]
    assert verdicts(text, states, AV) == expected


def test_exec_flag_and_operator_bindings() -> None:
    scope = Scope(bindings={"av": "uav0"}, exec_flag="executing-climb(uav0)")
    states = [
        State(0, {"executing-climb(uav0)": True, "altitude(uav0)": 2.0}),
        State(40, {"executing-climb(uav0)": True, "altitude(uav0)": 7.5}),
    ]
    assert verdicts("EXEC until altitude(av) >= 7.0", states, scope) == "UT"
    dropped = [State(0, {"executing-climb(uav0)": False, "altitude(uav0)": 2.0})]
    assert verdicts("EXEC until altitude(av) >= 7.0", dropped, scope) == "F"


def test_unknown_fluent_names_symbol_and_leaves_engine_unchanged() -> None:
    engine = ProgressionEngine()
    ident = engine.add(PARSER.parse("always carrying(uav0, box1)"))
    with pytest.raises(UnknownFluentError, match=r"'carrying\(uav0,box1\)'") as caught:
        engine.update(State(0, {"carrying(uav0,box2)": True}))
    assert caught.value.symbol == "carrying(uav0,box1)"
    assert engine.time_ms is None
    assert engine.update(State(0, {"carrying(uav0,box1)": True})) == []
    assert engine.verdict(ident) == Verdict.UNDECIDED


@pytest.mark.parametrize(
    ("text", "values"),
    [("p", {"p": "uav0"}), ("speed(uav0) < 3", {"speed(uav0)": "fast"})],
)
def test_fluent_type_errors(text: str, values: dict[str, FluentValue]) -> None:
    with pytest.raises(FluentTypeError):
        Progressor(PARSER.parse(text)).update(State(0, values))


def test_states_must_strictly_increase_in_time() -> None:
    engine = ProgressionEngine()
    engine.add(PARSER.parse("always p"))
    engine.update(State(100, {"p": True}))
    for bad in (100, 50, float("nan")):
        with pytest.raises(StateOrderError):
            engine.update(State(bad, {"p": True}))


def test_unknown_sort_is_a_grounding_error() -> None:
    with pytest.raises(GroundingError, match="'BOX'"):
        ProgressionEngine().add(PARSER.parse("forall b in BOX: p(b)"), AV)


def test_engine_reports_decisions_and_residuals() -> None:
    engine = ProgressionEngine()
    safe = engine.add(PARSER.parse("always speed < 50"))
    reach = engine.add(PARSER.parse("eventually[0,1000] at_goal"))
    assert engine.update(State(0, {"speed": 10, "at_goal": False})) == []
    assert str(engine.residual(reach)) == "eventually[0,1000] at_goal"
    assert engine.update(State(300, {"speed": 10, "at_goal": True})) == [(reach, Verdict.TRUE)]
    late = engine.add(PARSER.parse("always speed < 20"))
    assert engine.update(State(400, {"speed": 30, "at_goal": True})) == [(late, Verdict.FALSE)]
    assert engine.verdict(safe) == Verdict.UNDECIDED
    assert str(engine.residual(late)) == "false"
    engine.remove(late)
    with pytest.raises(UnknownMonitorError):
        engine.verdict(late)


def test_identical_subformulas_are_shared_across_formulas() -> None:
    one, two = ProgressionEngine(), ProgressionEngine()
    one.add(PARSER.parse(OBLIGATION))
    for _ in range(3):
        two.add(PARSER.parse(OBLIGATION))
    two.add(PARSER.parse("always(not p implies eventually[0,1000] always[0,999] p) and q"))
    for time, p in ((0, False), (100, True), (200, True)):
        state = State(time, {"p": p, "q": True})
        one.update(state)
        two.update(state)
        # Four monitors, one residual: the only extra node is none (q is decided away).
        assert two.residual_size() == one.residual_size()


def test_reset_restarts_from_the_formula() -> None:
    progressor = Progressor(PARSER.parse("eventually[0,100] p"))
    assert progressor.update(State(0, {"p": False})) == Verdict.UNDECIDED
    assert progressor.update(State(200, {"p": True})) == Verdict.FALSE
    assert progressor.update(State(300, {"p": True})) == Verdict.FALSE  # decided stays decided
    progressor.reset()
    assert progressor.update(State(0, {"p": True})) == Verdict.TRUE
    assert progressor.close() is True


def test_close_uses_the_end_of_trace_convention() -> None:
    progressor = Progressor(PARSER.parse("always[0,500] p and eventually[0,500] q"))
    progressor.update(State(0, {"p": True, "q": False}))
    assert progressor.verdict == Verdict.UNDECIDED
    assert progressor.close() is False  # the pending eventuality fails when the trace ends
    progressor.update(State(100, {"p": True, "q": True}))
    assert progressor.close() is True  # only the weak always remains


@pytest.mark.parametrize(
    ("text", "times", "p", "expected"),
    [
        ("eventually[0,1000] p", [0, 300], "FF", "eventually[0,700] p"),
        ("always[500,1000] p", [0, 200], "FF", "always[300,800] p"),
        ("always[500,1000] p", [0, 600], "FT", "always[0,400] p"),  # window open
        ("always[200,inf] p", [0, 150], "FT", "always[50,inf] p"),
        ("always[200,inf] p", [0, 150, 250], "FTT", "always p"),
        (
            OBLIGATION,
            [0, 100, 250],
            "FTT",
            "(always[0,849] p or eventually[0,750] always[0,999] p) and " + OBLIGATION_RESIDUAL,
        ),
        # The running attempt fails; the obligation (started at 0) is still pending.
        (
            OBLIGATION,
            [0, 100, 250],
            "FTF",
            "eventually[0,750] always[0,999] p and " + OBLIGATION_RESIDUAL,
        ),
        # A general body (not an atom) takes the general eventually rule.
        (
            "eventually[0,300] always[0,100] (p or p)",
            [0, 70],
            "TT",
            "always[0,30] p or eventually[0,230] always[0,100] p",
        ),
    ],
)
def test_residual_is_relative_to_the_last_state(
    text: str, times: list[float], p: str, expected: str
) -> None:
    progressor = Progressor(PARSER.parse(text))
    for state in bool_trace(times, p):
        progressor.update(state)
    assert str(progressor.residual) == expected


@pytest.mark.parametrize(
    ("text", "times", "p", "expected"),
    [
        # The attempt started in the window's last state covers [1000, 1999].
        (OBLIGATION, [0, 1000, 1999, 2000], "FTTT", "UUUU"),
        (OBLIGATION, [0, 1000, 1999], "FTF", "UUF"),
        (OBLIGATION, [0, 1001], "FT", "UF"),  # irregular gap skips the window's end
        # A later attempt replaces a failed one within the same window.
        (OBLIGATION, [0, 100, 200, 300, 1299, 1300], "FTFTTT", "UUUUUU"),
        (OBLIGATION, [0, 100, 200, 300, 1001], "FTFTF", "UUUUF"),
        # Nested eventually/always with a non-atomic body, edges inclusive.
        ("eventually[0,200] always[0,100] (p and p)", [0, 100, 200], "FTT", "UUT"),
        ("eventually[0,200] always[0,100] (p and p)", [0, 150, 201, 251], "FTTF", "UUUT"),
        ("eventually[0,200] always[0,100] (p and p)", [0, 150, 201], "FTF", "UUF"),
        ("eventually[0,200] always[100,100] p", [0, 50, 100], "TTT", "UUT"),
        ("eventually[0,200] always[100,100] p", [0, 50, 100], "TTF", "UUU"),
        ("always[0,100] eventually[0,50] p", [0, 30, 90, 140], "FTFT", "UUUT"),
        ("always[0,100] eventually[0,50] p", [0, 30, 90, 141], "FTFT", "UUUF"),
    ],
)
def test_nested_tense_shapes_with_irregular_sampling(
    text: str, times: list[float], p: str, expected: str
) -> None:
    states = bool_trace(times, p)
    assert verdicts(text, states) == expected
    for k in range(1, len(states) + 1):
        # Closing after each prefix agrees with the direct evaluator.
        progressor = Progressor(PARSER.parse(text))
        for state in states[:k]:
            progressor.update(state)
        assert progressor.close() == evaluate(PARSER.parse(text), states[:k], Scope())
