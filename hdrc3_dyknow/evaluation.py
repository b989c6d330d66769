"""Direct evaluation of monitor formulas over a complete finite trace (reference semantics).

This evaluator follows the definitions of chapter 9.3 literally and shares no code with
progression apart from identifier resolution (:class:`~hdrc3_dyknow.grounding.Scope`), so property
tests can compare the two.

Semantics at state ``i`` of a finite trace ``s_0 .. s_n`` with times ``t_0 < ... < t_n``:

* ``phi until[a,b] psi``: some ``j >= i`` with ``t_j - t_i`` in ``[a,b]`` satisfies ``psi`` and
  every ``k`` with ``i <= k < j`` satisfies ``phi``;
* ``eventually[a,b] phi``: some ``j >= i`` with ``t_j - t_i`` in ``[a,b]`` satisfies ``phi``;
* ``always[a,b] phi``: every ``j >= i`` with ``t_j - t_i`` in ``[a,b]`` satisfies ``phi``;
* quantifiers range over the scope's finite domains; connectives are classical.

End-of-trace convention: the trace is complete - no state follows ``s_n``. Hence an eventuality
whose window reaches past the end is FALSE unless met within the trace (strong), and an ``always``
whose window reaches past the end only constrains the states present (weak). Progression followed
by :meth:`~hdrc3_dyknow.progression.ProgressionEngine.close` yields exactly this verdict, and
every TRUE/FALSE that progression decides on a prefix is this verdict for every extension.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence

from hdrc3_dyknow.formula import (
    Always,
    And,
    Arithmetic,
    Atom,
    Comparison,
    Constant,
    Eventually,
    FluentTerm,
    Formula,
    Implies,
    Negative,
    Not,
    Number,
    Or,
    Quantified,
    Quantifier,
    Term,
    Until,
)
from hdrc3_dyknow.grounding import (
    GroundingError,
    Scope,
    compare_values,
    evaluate_arithmetic,
)
from hdrc3_dyknow.interpretation import (
    FluentTypeError,
    FluentValue,
    State,
    StateOrderError,
    UnknownFluentError,
)


def evaluate(formula: Formula, trace: Sequence[State], scope: Scope | None = None) -> bool:
    """Truth of ``formula`` at the first state of the complete trace ``trace``.

    Raises:
        StateOrderError: The trace is empty or its times do not strictly increase.
        UnknownFluentError: A needed fluent is missing from a state.
        GroundingError: Unknown sort, or a variable used as a boolean fluent.

    """
    if not trace:
        raise StateOrderError("cannot evaluate a formula over an empty trace")
    for before, after in itertools.pairwise(trace):
        if after.time_ms <= before.time_ms:
            raise StateOrderError(
                f"state at {after.time_ms:g} ms does not follow the state at {before.time_ms:g} ms"
            )
    return _Evaluator(trace, scope or Scope()).holds(formula, 0, {})


class _Evaluator:
    def __init__(self, trace: Sequence[State], scope: Scope) -> None:
        self._trace = trace
        self._scope = scope
        self._objects = scope.objects()

    def holds(self, formula: Formula, i: int, env: Mapping[str, str]) -> bool:
        if isinstance(formula, Constant):
            return formula.value
        if isinstance(formula, Atom):
            return self._atom(formula.fluent, i, env)
        if isinstance(formula, Comparison):
            text = str(formula)
            left = self._value(formula.left, i, env)
            right = self._value(formula.right, i, env)
            return compare_values(formula.op, left, right, text)
        if isinstance(formula, Not):
            return not self.holds(formula.operand, i, env)
        if isinstance(formula, And):
            return all(self.holds(op, i, env) for op in formula.operands)
        if isinstance(formula, Or):
            return any(self.holds(op, i, env) for op in formula.operands)
        if isinstance(formula, Implies):
            return not self.holds(formula.left, i, env) or self.holds(formula.right, i, env)
        if isinstance(formula, Always):
            return all(self.holds(formula.body, j, env) for j in self._window(formula, i))
        if isinstance(formula, Eventually):
            return any(self.holds(formula.body, j, env) for j in self._window(formula, i))
        if isinstance(formula, Until):
            for j in self._window(formula, i):
                if self.holds(formula.right, j, env) and all(
                    self.holds(formula.left, k, env) for k in range(i, j)
                ):
                    return True
            return False
        return self._quantified(formula, i, env)

    def _quantified(self, formula: Quantified, i: int, env: Mapping[str, str]) -> bool:
        instances = (
            self.holds(formula.body, i, {**env, formula.variable: obj})
            for obj in self._scope.domain(formula.sort)
        )
        return all(instances) if formula.quantifier == Quantifier.FORALL else any(instances)

    def _window(self, formula: Always | Eventually | Until, i: int) -> list[int]:
        start = self._trace[i].time_ms
        bounds = formula.interval
        return [
            j
            for j in range(i, len(self._trace))
            if bounds.lower <= self._trace[j].time_ms - start <= bounds.upper
        ]

    def _atom(self, fluent: FluentTerm, i: int, env: Mapping[str, str]) -> bool:
        if not fluent.args and (fluent.name in env or fluent.name in self._scope.bindings):
            raise GroundingError(f"variable {fluent.name!r} used as a boolean fluent")
        value = self._lookup(self._key(fluent, i, env), i)
        if isinstance(value, str):
            raise FluentTypeError(f"boolean fluent {fluent} has the object value {value!r}")
        return bool(value)

    def _key(self, fluent: FluentTerm, i: int, env: Mapping[str, str]) -> str:
        state = self._trace[i]
        return self._scope.fluent_key(fluent, env, state.values, state.time_ms)

    def _lookup(self, key: str, i: int) -> FluentValue:
        state = self._trace[i]
        try:
            return state.values[key]
        except KeyError:
            raise UnknownFluentError(key, state.time_ms) from None

    def _value(self, term: Term, i: int, env: Mapping[str, str]) -> FluentValue:
        if isinstance(term, Number):
            return term.value
        if isinstance(term, FluentTerm):
            constant = self._scope.object_constant(term, env, self._objects)
            if constant is not None:
                return constant
            return self._lookup(self._key(term, i, env), i)
        if isinstance(term, Negative):
            value = self._value(term.operand, i, env)
            if isinstance(value, str):
                raise FluentTypeError(f"arithmetic on an object name in {term}")
            return -value
        assert isinstance(term, Arithmetic)
        left = self._value(term.left, i, env)
        right = self._value(term.right, i, env)
        return evaluate_arithmetic(term.op, left, right, str(term))
