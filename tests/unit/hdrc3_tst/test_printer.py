from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hdrc3_deliberative.mission_syntax import (
    AgentsDecl,
    AreaDecl,
    Cmp,
    Comparison,
    ConsRef,
    LinExpr,
    Membership,
    Name,
    Number,
    PathDecl,
    PointDecl,
    Term,
    WorldDecl,
)
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.errors import TstError
from hdrc3_tst.parser import ParseStatus, parse_file, parse_text
from hdrc3_tst.printer import file_text, number_text, tst_text
from hdrc3_tst.syntax import (
    ActionTask,
    CallTask,
    ConcurrentTask,
    Condition,
    ConsDef,
    ForeachTask,
    GoalTask,
    IfTask,
    SequenceTask,
    TstDef,
    TstFile,
    WhileTask,
)

EXAMPLES = sorted((Path(__file__).resolve().parents[3] / "examples" / "tst").glob("*.tst"))
KEYWORDS = {
    "world", "agents", "area", "point", "path", "polygon", "at", "with", "where", "and", "goal",
    "call", "sequence", "concurrent", "if", "then", "else", "while", "foreach", "do", "conc",
    "not", "in", "true",
}  # fmt: skip

_FIRST = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_"
names = st.builds(
    lambda first, rest: first + rest,
    st.sampled_from(_FIRST),
    st.text(_FIRST + "0123456789", max_size=5),
).filter(lambda n: n not in KEYWORDS)
numbers = st.floats(allow_nan=False, allow_infinity=False)
args = st.lists(st.one_of(names.map(Name), numbers.map(Number)), max_size=3).map(tuple)
terms = st.builds(Term, numbers, st.one_of(st.none(), names.map(Name)))
exprs = st.lists(terms, min_size=1, max_size=3).map(lambda t: LinExpr(tuple(t)))
constraints = st.one_of(
    st.builds(Comparison, exprs, st.sampled_from(Cmp), exprs),
    st.builds(
        Membership, names.map(Name), st.lists(names.map(Name), min_size=1, max_size=3).map(tuple)
    ),
    names.map(lambda n: ConsRef(Name(n))),
)
wheres = st.lists(constraints, max_size=2).map(tuple)
conditions = st.builds(Condition, names, args, st.booleans(), st.one_of(st.none(), names))
elementary = st.one_of(
    st.builds(ActionTask, st.one_of(names, st.sampled_from(sorted(ACTIONS))), args),
    st.builds(GoalTask, names, args),
    st.builds(CallTask, names, args),
)
params = st.lists(names, min_size=1, max_size=3).map(tuple)
var_lists = st.lists(names, max_size=2).map(tuple)


def tsts(depth: int, child: bool) -> st.SearchStrategy[TstDef]:
    leaf = st.builds(TstDef, names, params, var_lists, elementary, st.just(()) if child else wheres)
    if depth == 0:
        return leaf
    sub = tsts(depth - 1, True)
    kids = st.lists(sub, min_size=1, max_size=2).map(tuple)
    composite = st.one_of(
        kids.map(SequenceTask),
        kids.map(ConcurrentTask),
        st.builds(IfTask, conditions, sub, sub),
        st.builds(WhileTask, conditions, sub),
        st.builds(ForeachTask, st.lists(names, min_size=1, max_size=2).map(tuple), conditions, sub),
    )
    return st.one_of(leaf, st.builds(TstDef, names, params, var_lists, composite, wheres))


coords = st.floats(-1e4, 1e4, allow_nan=False)
items = st.one_of(
    tsts(2, False),
    st.builds(WorldDecl, names),
    st.builds(AgentsDecl, st.lists(names, min_size=1, max_size=3).map(tuple)),
    st.builds(
        AreaDecl, names, st.lists(st.tuples(coords, coords), min_size=1, max_size=4).map(tuple)
    ),
    st.builds(PointDecl, names, st.tuples(coords, coords, coords)),
    st.builds(lambda n, p, a: PointDecl(n, None, p, a), names, names, coords),
    st.builds(PathDecl, names, st.lists(names, min_size=1, max_size=3).map(tuple)),
    st.builds(ConsDef, names, wheres),
)


@given(st.lists(items, max_size=4).map(lambda i: TstFile(tuple(i))))
def test_printing_and_parsing_round_trips(tree: TstFile) -> None:
    text = file_text(tree)
    result = parse_text(text)
    assert result.status is ParseStatus.OK, (text, result.diagnostics)
    assert result.tree == tree


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_shipped_examples_round_trip(path: Path) -> None:
    tree = parse_file(path).tree
    assert tree is not None
    again = parse_text(file_text(tree)).tree
    assert again == tree
    assert file_text(again) == file_text(tree)


def test_example_6_2_prints_in_the_chapter_layout() -> None:
    tree = parse_file(Path(EXAMPLES[0]).parent / "example_6_2.tst").tree
    assert tree is not None
    assert tst_text(tree.tsts()[0]).splitlines() == [
        "tau0(TS0, TE0) = with TS1, TE1, TS4, TE4 sequence",
        "  tau1(TS1, TE1) = with TS2, TE2, TS3, TE3 concurrent",
        "    tau2(TS2, TE2) = scan-area(TS2, TE2, Speed2, AreaA);",
        "    tau3(TS3, TE3) = scan-area(TS3, TE3, Speed3, AreaB)",
        "  where cons_tau1;",
        "  tau4(TS4, TE4) = fly-to(TS4, TE4, Speed4, Dest4)",
        "where cons_tau0",
    ]


def test_a_composite_child_without_constraints_is_closed_by_where_true() -> None:
    inner = TstDef("b", ("T",), (), SequenceTask((TstDef("c", ("T",), (), ActionTask("x", ())),)))
    outer = TstDef(
        "a", ("T",), (), SequenceTask((inner, TstDef("d", ("T",), (), ActionTask("y", ()))))
    )
    text = tst_text(outer)
    assert "  where true;" in text
    assert parse_text(text).tree == TstFile((outer,))


def test_an_elementary_child_with_a_where_clause_cannot_be_printed() -> None:
    child = TstDef("c", ("T",), (), ActionTask("x", ()), (ConsRef(Name("k")),))
    with pytest.raises(TstError, match="elementary child"):
        tst_text(TstDef("a", ("T",), (), SequenceTask((child,))))


@pytest.mark.parametrize(
    ("value", "text"), [(3.0, "3"), (-2.0, "-2"), (0.5, "0.5"), (1e20, "1e+20"), (1e-7, "1e-07")]
)
def test_numbers_print_shortest(value: float, text: str) -> None:
    assert number_text(value) == text
