from __future__ import annotations

import pytest

from hdrc3_deliberative.mission_syntax import Cmp
from hdrc3_tst.finite import FiniteModel, LinearConstraint, SolveStatus, SymbolConstraint


def model(linear: list[LinearConstraint], symbolic: list[SymbolConstraint] = ()) -> FiniteModel:  # type: ignore[assignment]
    return FiniteModel(
        numeric={"a", "b"},
        domains={"p": ("uav0", "uav1"), "q": ("uav0", "uav1"), "none": ()},
        linear=list(linear),
        symbolic=list(symbolic),
    )


def lin(terms: tuple[tuple[float, str], ...], op: Cmp, k: float, label: str) -> LinearConstraint:
    return LinearConstraint(terms, op, k, label)


@pytest.mark.parametrize(
    ("linear", "symbolic", "conflict"),
    [
        # one variable: the tightest bounds of each side
        ([lin(((1, "a"),), Cmp.LE, 5, "a<=5"), lin(((1, "a"),), Cmp.LE, 3, "a<=3"),
          lin(((1, "a"),), Cmp.GT, 3, "a>3")], [], ("a<=3", "a>3")),
        ([lin(((-2, "a"),), Cmp.GE, -4, "a<=2"), lin(((1, "a"),), Cmp.GE, 2.5, "a>=2.5")], [],
         ("a<=2", "a>=2.5")),
        # two variables: CP-SAT names a sufficient set
        ([lin(((1, "a"), (1, "b")), Cmp.LE, 10, "a+b<=10"), lin(((1, "a"),), Cmp.GE, 6, "a>=6"),
          lin(((1, "b"),), Cmp.GE, 6, "b>=6"), lin(((1, "b"),), Cmp.LE, 100, "b<=100")], [],
         ("a+b<=10", "a>=6", "b>=6")),
        # names
        ([], [SymbolConstraint("p", Cmp.EQ, ("uav0",), None, "p=uav0"),
              SymbolConstraint("p", Cmp.NE, ("uav0",), None, "p!=uav0")], ("p!=uav0", "p=uav0")),
        ([], [SymbolConstraint("p", Cmp.EQ, ("uav0",), None, "p=uav0"),
              SymbolConstraint("q", Cmp.EQ, ("uav0",), None, "q=uav0"),
              SymbolConstraint("p", Cmp.NE, (), "q", "p!=q")], ("p!=q", "p=uav0", "q=uav0")),
        ([], [SymbolConstraint("none", Cmp.EQ, ("uav0",), None, "none=uav0")],
         ("none has no possible value", "none=uav0")),
    ],
)  # fmt: skip
def test_conflicts_are_named(
    linear: list[LinearConstraint], symbolic: list[SymbolConstraint], conflict: tuple[str, ...]
) -> None:
    result = model(linear, symbolic).solve()
    assert result.status is SolveStatus.INCONSISTENT
    assert tuple(sorted(result.conflict)) == conflict


def test_a_consistent_model_has_a_witness_that_satisfies_it() -> None:
    result = model(
        [lin(((1, "a"), (-1, "b")), Cmp.GT, 2, "a-b>2"), lin(((1, "b"),), Cmp.GE, 1.5, "b>=1.5")],
        [SymbolConstraint("p", Cmp.EQ, ("uav0", "uav1"), None, "p in"),
         SymbolConstraint("q", Cmp.NE, (), "p", "q!=p")],
    ).solve()  # fmt: skip
    assert result.status is SolveStatus.CONSISTENT
    w = result.witness
    assert float(w["a"]) - float(w["b"]) > 2 and float(w["b"]) >= 1.5
    assert w["p"] != w["q"]


def test_a_name_without_values_and_without_constraints_stays_open() -> None:
    assert model([]).solve().status is SolveStatus.CONSISTENT


def test_strict_inequalities_resolve_to_one_step_of_the_scale() -> None:
    result = model(
        [lin(((1, "a"),), Cmp.GT, 2, "a>2"), lin(((1, "a"),), Cmp.LT, 2.002, "a<2.002")]
    ).solve()
    assert result.status is SolveStatus.CONSISTENT and result.witness["a"] == pytest.approx(2.001)
