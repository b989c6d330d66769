from __future__ import annotations

import pytest

from hdrc3_hcsm.diagnostics import Severity
from hdrc3_hcsm.errors import ModelError
from hdrc3_hcsm.loader import LoadStatus, check_file, check_text, load_text
from hdrc3_hcsm.models import model_path

VALID = """model M on PFC;
computers PFC, DRC;
event Go-EV = 1 from DRC;
event Up-EV = 2 to DRC;
event Loc-EV = 3;
condition C-CO;
flag F-AC;
slot S-DO[4];
root Top;
automaton A Top {
    init I-ST;
    super Sup-ST = Leaf;
    A.1: I-ST -> Sup-ST on Go-EV [C-CO] / SET F-AC, SEND Up-EV to DRC, SEND Loc-EV;
    A.2: Sup-ST -> I-ST on exit;
}
automaton B Leaf {
    init L-ST; exit X-ST;
    B.1: L-ST -> X-ST on Loc-EV / GET S-DO, PUT S-DO;
}
"""


def test_valid_model_has_no_findings() -> None:
    result = check_text(VALID, "m.hcsm")
    assert result.status is LoadStatus.OK
    assert result.diagnostics == ()


# (case id, (old, new) replacement, expected code, expected line)
CASES = [
    ("missing init state", ("init L-ST;", "state L-ST;"), "E040", 16),
    ("two init states", ("init L-ST; exit X-ST;", "init L-ST; init L2-ST; exit X-ST;"), "E041", 17),
    ("unreachable state", ("exit X-ST;", "exit X-ST; state Lost-ST;"), "E045", 17),
    ("undefined event", ("on Loc-EV", "on Nope-EV"), "E023", 18),
    ("undefined condition", ("[C-CO]", "[C-CO AND D-CO]"), "E024", 13),
    ("undefined flag", ("SET F-AC", "SET G-AC"), "E025", 13),
    ("undefined slot", ("GET S-DO", "GET T-DO"), "E026", 18),
    ("undefined state", ("-> X-ST on", "-> Y-ST on"), "E022", 18),
    ("undefined computer", ("to DRC, SEND", "to PPC, SEND"), "E020", 13),
    ("undefined automaton", ("super Sup-ST = Leaf;", "super Sup-ST = Leaf2;"), "E021", 12),
    (
        "event without receiver",
        ("event Loc-EV = 3;", "event Loc-EV = 3; event Lost-EV = 9 from DRC;"),
        "E050",
        5,
    ),
    ("local send without receiver", ("on Loc-EV", "on Go-EV"), "E050", 5),
    ("duplicate event id", ("event Loc-EV = 3;", "event Loc-EV = 2;"), "E010", 5),
    ("duplicate state", ("exit X-ST;", "exit X-ST; state X-ST;"), "E010", 17),
    ("transition numbering", ("B.1:", "A.9:"), "E042", 18),
    (
        "exit trigger on a simple state",
        ("A.2: Sup-ST -> I-ST on exit;", "A.2: I-ST -> I-ST on exit;"),
        "E044",
        14,
    ),
    (
        "nesting cycle",
        ("init L-ST; exit X-ST;", "init L-ST; exit X-ST; super Z-ST = Top;"),
        "E030",
        10,
    ),
    ("target contradicts declaration", ("SEND Up-EV to DRC", "SEND Up-EV"), "E027", 13),
    ("missing header", ("model M on PFC;", ""), "E011", 1),
    ("reserved name", ("slot S-DO[4];", "slot S-DO[4]; slot cache;"), "E013", 8),
]


@pytest.mark.parametrize(("case", "edit", "code", "line"), CASES, ids=[c[0] for c in CASES])
def test_validation_errors(case: str, edit: tuple[str, str], code: str, line: int) -> None:
    assert edit[0] in VALID
    result = check_text(VALID.replace(edit[0], edit[1], 1), "m.hcsm")
    assert result.status is LoadStatus.INVALID
    hits = [d for d in result.diagnostics if d.code == code]
    assert hits, [str(d) for d in result.diagnostics]
    assert hits[0].severity is Severity.ERROR
    assert (hits[0].pos.file, hits[0].pos.line) == ("m.hcsm", line)
    assert hits[0].pos.column >= 1


def test_library_without_root_is_checked_with_a_warning() -> None:
    result = check_text(VALID.replace("root Top;", ""), "lib.hcsm")
    assert result.status is LoadStatus.OK
    assert [d.code for d in result.diagnostics] == ["W003"]
    with pytest.raises(ModelError, match="no 'root'"):
        load_text(VALID.replace("root Top;", ""), "lib.hcsm")


@pytest.mark.parametrize(
    ("text", "code", "words"),
    [
        ("", "E017", "empty model: the file declares nothing"),
        ("# a comment only\n\n", "E017", "empty model"),
        ("model M on PFC;\ncomputers PFC;\nevent A-EV = 1;\n", "E018", "model M declares no"),
        ("model M on PFC;\ncomputers PFC;\nroot Top;\n", "E018", "declares no automaton"),
    ],
)
def test_empty_models_and_models_without_automata_are_invalid(
    text: str, code: str, words: str
) -> None:
    result = check_text(text, "m.hcsm")
    assert result.status is LoadStatus.INVALID
    errors = [d for d in result.diagnostics if d.severity is Severity.ERROR]
    assert errors[0].code == code and words in errors[0].message


def test_a_declarations_only_library_stays_valid() -> None:
    result = check_text("computers PFC;\nevent A-EV = 1;\n", "lib.hcsm")
    assert result.status is LoadStatus.OK
    assert [d.code for d in result.diagnostics] == ["W003"]


def test_load_text_raises_with_every_error() -> None:
    with pytest.raises(ModelError, match=r"m.hcsm:16:\d+: error E040"):
        load_text(VALID.replace("init L-ST;", "state L-ST;"), "m.hcsm")


def test_shipped_models_are_valid() -> None:
    result = check_file(model_path("pfc_modes.hcsm"))
    assert result.status is LoadStatus.OK
    assert result.diagnostics == ()


PFC = """model P on PFC; computers PFC, DRC;
event Go-EV = 1 from DRC; event Up-EV = 2 to DRC;
automaton A P { init S-ST; A.1: S-ST -> S-ST on Go-EV / SEND Up-EV to DRC; }
root P;
"""
DRC = """model D on DRC; computers PFC, DRC;
event Go-EV = 1 to PFC; event Up-EV = 2 from PFC;
automaton A D { init S-ST; A.1: S-ST -> S-ST on Up-EV / SEND Go-EV to PFC; }
root D;
"""


@pytest.mark.parametrize(
    ("drc_edit", "codes"),
    [
        (("", ""), []),
        (("Go-EV = 1", "Go-EV = 7"), ["E060"]),
        (("Up-EV = 2", "Up-EV = 1"), ["E010", "E060", "E061"]),  # E010: duplicate id in drc
        (("Up-EV = 2 from PFC", "Up-EV = 2"), ["E062"]),
    ],
)
def test_system_event_ids_are_globally_unique(drc_edit: tuple[str, str], codes: list[str]) -> None:
    from hdrc3_hcsm.validation import validate, validate_system

    pfc = load_text(PFC, "pfc.hcsm")
    drc_text = DRC.replace(*drc_edit) if drc_edit[0] else DRC
    parsed = check_text(drc_text, "drc.hcsm").model
    assert parsed is not None
    found = [d.code for d in validate_system([pfc, parsed])]
    found += [d.code for d in validate(parsed) if d.severity is Severity.ERROR]
    assert sorted(found) == sorted(codes)
