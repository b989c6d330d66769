from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hdrc3_hcsm.loader import LoadStatus, check_text
from hdrc3_hcsm.model import And, CondRef, Not, Or, SendAction, StateKind, guard_conditions
from hdrc3_hcsm.models import model_path
from hdrc3_hcsm.parser import DEFAULT_SLOT_SIZE, ParseStatus, parse_file, parse_text

SMALL = """
# comment
model M on PFC;
computers PFC, DRC;
event Go-EV = 5 from DRC;
event Up-EV = 6 to DRC;
condition C1-CO, C2-CO;
flag F-AC;
slot S-DO[16];
slot T-DO;
container Box = Leaf;
root Top;
automaton A Top {
    init I-ST;
    super Sup-ST = Box;
    A.1: I-ST -> Sup-ST on Go-EV [NOT C1-CO AND (C2-CO OR C1-CO)]
         / SET F-AC, SEND Up-EV data S-DO to DRC;
    A.2: Sup-ST -> I-ST on exit;
}
automaton B Leaf { init L-ST; exit X-ST; B.1: L-ST -> X-ST on pulse / GET S-DO, PUT T-DO; }
"""


def test_parses_every_construct() -> None:
    result = parse_text(SMALL, "small.hcsm")
    assert result.status is ParseStatus.OK
    m = result.model
    assert m is not None
    assert (m.name, m.computer, m.root) == ("M", "PFC", ("Top",))
    assert [(e.name, e.event_id, e.source, e.target) for e in m.events] == [
        ("Go-EV", 5, "DRC", None),
        ("Up-EV", 6, None, "DRC"),
    ]
    assert [(s.name, s.size) for s in m.slots] == [("S-DO", 16), ("T-DO", DEFAULT_SLOT_SIZE)]
    top = m.automata[0]
    assert [s.kind for s in top.states] == [StateKind.INIT, StateKind.SUPER]
    assert m.regions_of(top.states[1].regions) == ("Leaf",)
    t = top.transitions[0]
    assert isinstance(t.guard, And)
    first, second = t.guard.operands
    assert isinstance(first, Not) and isinstance(first.operand, CondRef)
    assert isinstance(second, Or) and [c.name for c in guard_conditions(second)] == [
        "C2-CO",
        "C1-CO",
    ]
    assert (first.operand.pos.line, first.operand.pos.column) == (16, 39)
    assert t.actions[1] == SendAction("Up-EV", "S-DO", "DRC", t.actions[1].pos)
    assert t.label() == (
        "A.1 Go-EV [(NOT C1-CO AND (C2-CO OR C1-CO))] / SET F-AC, SEND Up-EV data S-DO to DRC"
    )
    assert (t.pos.line, t.pos.column) == (16, 5)
    assert check_text(SMALL, "small.hcsm").status is LoadStatus.OK


@pytest.mark.parametrize(
    ("text", "line", "column", "expected"),
    [
        ("model M on ;", 1, 12, "NAME"),
        ("automaton a X { }", 1, 11, "LABEL"),
        ("automaton A X { init S-ST }", 1, 27, "';'"),
        ("automaton A X {\n  A.1: S -> T on E-EV [ ] ;\n}", 2, 25, "NAME"),
        ("event E-EV = x;", 1, 14, "INT"),
        ("model M on PFC; @", 1, 17, ""),
        ("automaton A X { init S; A.1: S -> S on E / FOO bar; }", 1, 44, "'SET'"),
    ],
)
def test_syntax_errors_point_at_the_offending_text(
    text: str, line: int, column: int, expected: str
) -> None:
    result = parse_text(text, "bad.hcsm")
    assert result.status is ParseStatus.SYNTAX_ERROR and result.model is None
    [diag] = result.diagnostics
    assert (diag.pos.file, diag.pos.line, diag.pos.column) == ("bad.hcsm", line, column)
    assert expected in diag.message
    assert str(diag).startswith(f"bad.hcsm:{line}:{column}: error E001")


def test_unreadable_file_is_a_diagnostic(tmp_path: object) -> None:
    result = parse_file("/nonexistent/x.hcsm")
    assert result.status is ParseStatus.UNREADABLE
    assert result.diagnostics[0].code == "E000"


def test_shipped_model_parses() -> None:
    assert parse_file(model_path("pfc_modes.hcsm")).status is ParseStatus.OK


TOKENS = st.sampled_from(
    [
        "model",
        "on",
        "automaton",
        "A",
        "A.1",
        ":",
        "->",
        "init",
        "exit",
        "super",
        "=",
        "|",
        ";",
        "{",
        "}",
        "[",
        "]",
        "(",
        ")",
        "/",
        ",",
        "AND",
        "OR",
        "NOT",
        "SET",
        "SEND",
        "GET",
        "PUT",
        "pulse",
        "event",
        "1",
        "X-ST",
        "E-EV",
        "C-CO",
        "data",
        "to",
        "from",
        "root",
        "slot",
        "#",
        "\n",
        "99999999999999999999999",
        "é",
        "\x00",
    ]
)


@given(st.lists(TOKENS, max_size=40).map(" ".join))
def test_fuzz_token_soup_never_crashes(text: str) -> None:
    result = check_text(text, "fuzz.hcsm")
    assert result.status in (LoadStatus.OK, LoadStatus.INVALID)
    assert all(d.pos.file == "fuzz.hcsm" for d in result.diagnostics)


@given(st.text(max_size=40))
def test_fuzz_include_paths_never_crash(path: str) -> None:
    escaped = path.replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ")
    result = check_text(f'include "{escaped}";', "/nonexistent-dir/fuzz.hcsm")
    assert result.status in (LoadStatus.OK, LoadStatus.INVALID)


@given(st.text(max_size=200))
def test_fuzz_arbitrary_text_never_crashes(text: str) -> None:
    result = check_text(text, "fuzz.hcsm")
    assert result.status in (LoadStatus.OK, LoadStatus.INVALID)


@given(st.integers(0, len(SMALL) - 1), st.integers(1, 30))
def test_fuzz_truncated_and_spliced_models_never_crash(cut: int, width: int) -> None:
    for text in (SMALL[:cut], SMALL[:cut] + SMALL[cut + width :]):
        result = check_text(text, "fuzz.hcsm")
        assert result.status in (LoadStatus.OK, LoadStatus.INVALID)
