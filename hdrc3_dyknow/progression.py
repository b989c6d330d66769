"""Formula progression (HDRC3 chapter 9.3.3, Definition 9.3) over states with irregular spacing.

``phi`` holds in ``[s0, s1, ...]`` iff ``Progress(phi, s0)`` holds in ``[s1, ...]``. Progressing a
monitor formula through each new state yields TRUE (satisfied whatever comes), FALSE (violated
whatever comes) or a residual formula that waits for the next state.

Time: the intervals of a formula are relative to the state it is first progressed through. At
a state ``delta`` ms after a tense node's anchor, its interval is shifted by ``delta``
(Definition 9.3 shifts by 1 for unit steps):

* ``phi until[a,b] psi``: ``b-delta < 0`` -> false; ``a-delta <= 0`` ->
  ``Progress(psi) or (Progress(phi) and phi until[a-delta,b-delta] psi)``; otherwise
  ``Progress(phi) and phi until[a-delta,b-delta] psi``;
* ``eventually`` and ``always`` are special-cased (``true until`` / ``not eventually not``);
* a rest whose upper bound is ``<= 0`` after the shift is dropped (true for ``always``, false
  otherwise): states strictly increase in time, so no later state can fall into its window.

Rather than shifting, the rest ``... [a-delta,b-delta] ...`` is kept with *absolute* bounds
(:mod:`residual`): anchor plus ``a`` and ``b``, compared with each state's time. A pending
obligation is then its own rest, and a residual in which nothing changed is returned as the
same object, so a waiting monitor allocates nothing. :meth:`ProgressionEngine.residual` prints
the intervals relative to the last state.

Operands of tense operators are evaluated at the current state. Compiled formulas are
hash-consed (:mod:`residual`) and each state memoises ``node -> result`` on the node, so
identical sub-formulas - within one formula or across all formulas of an engine - are
progressed once per state, and so are the residuals derived from them.

Performance: the Figure 28 formula progresses in well under 1 us per state when nothing is
pending and about 4-5 us in the worst case on this project's machines
(``bench/progression.py``). While progressing, the cyclic garbage collector is paused: the
short-lived nodes are acyclic and freed by reference counting, and collector passes over a
large heap cost more than the work.

End of a finite trace (:meth:`ProgressionEngine.close`): a trace that ends has no further
states, so pending ``eventually``/``until`` obligations are FALSE (strong) and pending ``always``
obligations are TRUE (weak). This is the semantics of :mod:`hdrc3_dyknow.evaluation`.

API for a stream reasoning coordinator::

    engine = ProgressionEngine()
    ident = engine.add(parser.parse("always speed(uav0) < 50"), Scope())
    for state in states:                    # State(time_ms, {"speed(uav0)": 12.0, ...})
        for ident, verdict in engine.update(state):   # monitors decided at this state
            ...
    engine.verdict(ident); engine.residual(ident); engine.close(ident)

A formula added between states starts at the next state. :class:`Progressor` wraps one formula
with ``reset()`` / ``update(state) -> Verdict``.
"""

from __future__ import annotations

import enum
import gc
import itertools
import math
import operator
from collections.abc import Callable, Mapping
from typing import cast

from hdrc3_base.errors import Hdrc3Error
from hdrc3_dyknow.formula import Formula
from hdrc3_dyknow.grounding import Scope, compile_formula
from hdrc3_dyknow.interpretation import (
    FluentTypeError,
    FluentValue,
    State,
    StateOrderError,
    UnknownFluentError,
)
from hdrc3_dyknow.residual import Kind, Node, NodeTable, to_formula

# Node kinds as plain ints: the progression loop compares them millions of times per second.
_TRUE, _FALSE, _ATOM, _COMPARE, _NOT, _AND, _OR, _ALWAYS, _EVENTUALLY, _UNTIL = range(10)


class Verdict(enum.Enum):
    """Status of a monitor formula after the states seen so far."""

    UNDECIDED = "undecided"
    TRUE = "true"
    FALSE = "false"


class NoStateError(Hdrc3Error):
    """A monitor was closed before any state was progressed through it."""


class UnknownMonitorError(Hdrc3Error):
    """An engine was asked about a monitor id it does not hold."""


class ProgressionEngine:
    """Progresses many monitor formulas over one shared stream of states.

    Args:
        table: Node table to intern into (a fresh one by default).

    """

    def __init__(self, table: NodeTable | None = None) -> None:
        self._table = table if table is not None else NodeTable()
        self._formulas: dict[int, Node] = {}
        self._active: dict[int, Node] = {}  # undecided monitors and their residuals
        self._fresh: dict[int, Node] = {}  # added since the last state, not yet progressed
        self._decided: dict[int, Verdict] = {}
        self._next_id = 0
        self._time: float | None = None

    @property
    def table(self) -> NodeTable:
        """The node table shared by this engine's formulas."""
        return self._table

    @property
    def time_ms(self) -> float | None:
        """Time of the last state progressed, or None before the first."""
        return self._time

    def add(self, formula: Formula, scope: Scope | None = None) -> int:
        """Ground and add ``formula``; it is first progressed through the next state.

        Returns:
            The monitor id.

        Raises:
            GroundingError: The formula refers to an unknown sort.

        """
        with self._table.compiling():
            node = compile_formula(self._table, formula, scope or Scope())
        ident = self._next_id
        self._next_id += 1
        self._formulas[ident] = node
        self._fresh[ident] = node
        return ident

    def remove(self, ident: int) -> None:
        """Stop and forget monitor ``ident``."""
        self._check(ident)
        for holder in (self._formulas, self._active, self._fresh, self._decided):
            holder.pop(ident, None)

    def reset(self) -> None:
        """Restart every monitor from its formula and forget the time of the last state."""
        self._active.clear()
        self._decided.clear()
        self._fresh = dict(self._formulas)
        self._time = None

    def update(self, state: State) -> list[tuple[int, Verdict]]:
        """Progress every undecided monitor through ``state``.

        Returns:
            ``(id, verdict)`` of the monitors that became TRUE or FALSE at this state.

        Raises:
            StateOrderError: ``state.time_ms`` is not after the previous state's time.
            UnknownFluentError: A formula needs a fluent the state lacks (monitors keep the
                residual they had before this state).
            FluentTypeError: A fluent's value has the wrong type for its use.

        """
        time_ms = float(state.time_ms)
        if not math.isfinite(time_ms):
            raise StateOrderError(f"state time {state.time_ms!r} is not a finite number")
        if self._time is not None and time_ms <= self._time:
            raise StateOrderError(
                f"state at {time_ms:g} ms does not follow the previous state at {self._time:g} ms"
            )
        step = _Step(self._table, state.values, time_ms)
        progress = step.progress
        active: dict[int, Node] = {}
        finished: list[tuple[int, Node]] = []
        # Progression allocates many short-lived, acyclic nodes that reference counting frees;
        # cyclic-GC passes over the whole heap would cost more than the progression itself.
        collecting = gc.isenabled()
        gc.disable()
        try:
            # Fresh formulas are relative, so they start at this state like the residuals.
            for ident, node in itertools.chain(self._active.items(), self._fresh.items()):
                node = progress(node)
                if node.kind > _FALSE:
                    active[ident] = node
                else:
                    finished.append((ident, node))
        finally:
            if collecting:
                gc.enable()
        # Commit only after every monitor progressed: an error leaves the engine unchanged.
        self._time = time_ms
        self._fresh = {}
        self._active = active
        self._table.advance()
        decided = [
            (ident, Verdict.TRUE if node.kind == _TRUE else Verdict.FALSE)
            for ident, node in finished
        ]
        self._decided.update(decided)
        return decided

    def verdict(self, ident: int) -> Verdict:
        """Current verdict of monitor ``ident``."""
        self._check(ident)
        return self._decided.get(ident, Verdict.UNDECIDED)

    def residual(self, ident: int) -> Formula:
        """What monitor ``ident`` still has to check (``true``/``false`` once decided).

        Intervals are relative to the time of the last state.
        """
        self._check(ident)
        if ident in self._decided:
            return to_formula(
                self._table.true if self._decided[ident] == Verdict.TRUE else self._table.false
            )
        if ident in self._fresh:
            return to_formula(self._fresh[ident])
        assert self._time is not None
        return to_formula(self._active[ident], self._time)

    def close(self, ident: int) -> bool:
        """Verdict of monitor ``ident`` if the trace ends now (see the module docstring)."""
        self._check(ident)
        if ident in self._decided:
            return self._decided[ident] == Verdict.TRUE
        if ident in self._fresh:
            # No state at all: every tense obligation is still pending.
            return _close(self._fresh[ident], {})
        return _close(self._active[ident], {})

    def residual_size(self) -> int:
        """Number of distinct nodes in all residuals (a measure of the monitoring load)."""
        seen: set[int] = set()
        stack = [*self._active.values(), *self._fresh.values()]
        while stack:
            node = stack.pop()
            if id(node) not in seen:
                seen.add(id(node))
                stack.extend(node.children())
        return len(seen)

    def _check(self, ident: int) -> None:
        if ident not in self._formulas:
            raise UnknownMonitorError(f"no monitor with id {ident}")


class Progressor:
    """One monitor formula with the reset()/update(state) protocol.

    Args:
        formula: The monitor formula.
        scope: Domains, bindings and ``EXEC`` flag for grounding it.

    """

    def __init__(self, formula: Formula, scope: Scope | None = None) -> None:
        self._engine = ProgressionEngine()
        self._ident = self._engine.add(formula, scope)

    def reset(self) -> None:
        """Start over from the original formula."""
        self._engine.reset()

    def update(self, state: State) -> Verdict:
        """Progress through ``state`` and return the verdict so far."""
        if self._engine.verdict(self._ident) == Verdict.UNDECIDED:
            self._engine.update(state)
        return self._engine.verdict(self._ident)

    @property
    def verdict(self) -> Verdict:
        """Verdict after the states seen so far."""
        return self._engine.verdict(self._ident)

    @property
    def residual(self) -> Formula:
        """What remains to be checked, relative to the time of the last state."""
        return self._engine.residual(self._ident)

    def close(self) -> bool:
        """Verdict if the trace ends now (pending eventualities fail, pending always hold)."""
        return self._engine.close(self._ident)


class _Step:
    """Progression of nodes through one state, memoised per node.

    This is the hot loop of monitoring, written for CPython speed: kinds are compared as ints,
    the tense rules are inlined and atoms under tense operators are read directly.
    """

    __slots__ = ("_interning", "_lookup", "_stamp", "_table", "_time", "_values")

    def __init__(self, table: NodeTable, values: Mapping[str, FluentValue], time_ms: float):
        self._table = table
        self._interning = table.interning
        self._values = values
        # Atoms test "value is True" inline with this; _truth is the slow path (keys are str).
        self._lookup = cast("Callable[[object], FluentValue | None]", values.get)
        self._time = time_ms
        self._stamp = table.stamp(time_ms)

    def progress(self, node: Node) -> Node:
        """``Progress(node, state)``; a node that progresses to itself is returned as is."""
        # The memo lives on the node: attribute access beats lookups in a dict of all nodes.
        stamp = self._stamp
        if node.memo_key == stamp:
            return node.memo
        table = self._table
        kind = node.kind
        if kind >= _ALWAYS:
            result = self._tense(node, kind)
        elif kind in (_AND, _OR):
            result = self._junction(node, kind)
        elif kind == _ATOM:
            holds = self._lookup(node.key) is True or self._truth(node)
            result = table.true if holds else table.false
        elif kind == _NOT:
            operand = self.progress(node.first)
            result = node if operand is node.first else table.negation(operand)
        elif kind == _COMPARE:
            result = table.true if node.compare(self._values, self._time) else table.false
        else:
            result = node
        node.memo_key = stamp
        node.memo = result
        return result

    def _junction(self, node: Node, kind: int) -> Node:
        """Progression of an AND/OR node: short-circuit on the absorbing element, in order."""
        table = self._table
        if kind == _AND:
            absorbing, neutral = table.false, table.true
        else:
            absorbing, neutral = table.true, table.false
        operands = node.operands
        first = operands[0]
        if first.kind == _ATOM:
            holds = self._lookup(first.key) is True or self._truth(first)
            result = table.true if holds else table.false
        else:
            result = self.progress(first)
        if result is absorbing:
            return result
        if len(operands) > 2:
            parts = [result]
            for operand in operands[1:]:
                part = self.progress(operand)
                if part is absorbing:
                    return part
                parts.append(part)
            if all(map(operator.is_, parts, operands)):
                return node
            return table.conjunction(parts) if kind == _AND else table.disjunction(parts)
        # Two operands (by far the most common): the neutral element applied inline.
        second = operands[1]
        other = self.progress(second)
        if other is absorbing or result is neutral:
            return other
        if other is neutral or other is result:
            return result
        if result is first:
            if other is second:
                return node
            if other.kind == kind and second in other.operands:
                # What progressing the second operand added may merge into the first (e.g. a
                # new attempt into the running one): then no junction need be built and merged.
                for part in other.operands:
                    if part is not second and not table.absorbs(kind, first, part):
                        break
                else:
                    return node
        result = table.pair(kind, result, other, absorbing, neutral)
        # Merging tense operands often rebuilds the residual it started from: keep that one.
        if result.kind == kind and result.operands == operands:
            return node
        return result

    def _tense(self, node: Node, kind: int) -> Node:
        """Progression of an ALWAYS/EVENTUALLY/UNTIL node (Definition 9.3).

        ``lower``/``upper`` are the interval relative to this state; the rest after this
        state has absolute bounds, so a pending absolute node is its own rest.
        """
        table = self._table
        time = self._time
        lower = node.lower
        upper = node.upper
        if node.absolute:
            lower -= time
            upper -= time
            if lower < 0:
                lower = 0.0
        body = node.first
        if upper <= 0:
            # No later state can fall into the window.
            rest = table.true if kind == _ALWAYS else table.false
        elif node.absolute or (lower == 0 and upper == math.inf):
            rest = node
        elif self._interning:
            rest = table.tense(kind, time + lower, time + upper, body, node.second, True)
        else:
            # Inlined NodeTable.tense without interning: this runs once per new obligation.
            rest = Node(kind, None)
            rest.lower = time + lower
            rest.upper = time + upper
            rest.first = body
            rest.second = node.second
            rest.absolute = True
        if upper < 0 or (lower > 0 and kind != _UNTIL):
            # Window over (Def. 9.3 line 13 and its always twin), or not yet open.
            return rest
        lookup = self._lookup
        if kind == _ALWAYS:
            if body.kind == _ATOM:
                holds = lookup(body.key) is True or self._truth(body)
                return rest if holds else table.false
            now = self.progress(body)
            return rest if now is table.true else table.both(now, rest)
        if kind == _EVENTUALLY:
            if body.kind == _ATOM:
                holds = lookup(body.key) is True or self._truth(body)
                return table.true if holds else rest
            if body.kind == _ALWAYS and body.lower == 0 < body.upper:
                inner = body.first
                if inner.kind == _ATOM:
                    # "always[0,b] atom" now is its rest while the atom holds.
                    holds = lookup(inner.key) is True or self._truth(inner)
                    if not holds:
                        return rest
                    attempt = self._start(body)
                    if rest is table.false:
                        return attempt
                    if self._interning:
                        return table.either(attempt, rest)
                    # Inlined NodeTable.either: the kinds differ and neither is a disjunction.
                    pending = Node(_OR, None)
                    pending.operands = (attempt, rest)
                    return pending
            now = self.progress(body)
            return rest if now is table.false else table.either(now, rest)
        right = node.second
        assert right is not None
        # Def. 9.3 lines 14-15: right may hold now only once the window is open.
        reached = self.progress(right) if lower == 0 else table.false
        if reached is table.true:
            return reached
        return table.either(reached, table.both(self.progress(body), rest))

    def _start(self, node: Node) -> Node:
        """Rest of relative ``always[0,b] phi`` (b > 0) whose body holds now: anchored now."""
        if node.upper == math.inf:
            return node
        time = self._time
        return self._table.tense(_ALWAYS, time, time + node.upper, node.first, None, True)

    def _truth(self, node: Node) -> bool:
        # Callers test "value is True" inline first; this is the slow path for everything else.
        key = node.key
        assert isinstance(key, str)
        try:
            value = self._values[key]
        except KeyError:
            raise UnknownFluentError(key, self._time) from None
        if value is True or value is False:
            return value
        if isinstance(value, str):
            raise FluentTypeError(
                f"boolean fluent {key!r} has the object value {value!r} at {self._time:g} ms"
            )
        return bool(value)


def _close(node: Node, memo: dict[Node, bool]) -> bool:
    """Truth of a residual if no further state arrives."""
    if node in memo:
        return memo[node]
    kind = node.kind
    if kind == Kind.TRUE or kind == Kind.ALWAYS:
        result = True
    elif kind == Kind.FALSE or kind == Kind.EVENTUALLY or kind == Kind.UNTIL:
        result = False
    elif kind == Kind.NOT:
        assert node.first is not None
        result = not _close(node.first, memo)
    elif kind == Kind.AND:
        result = all(_close(operand, memo) for operand in node.operands)
    elif kind == Kind.OR:
        result = any(_close(operand, memo) for operand in node.operands)
    else:
        # An atom outside any tense operator is only pending before the first state.
        raise NoStateError("a formula cannot be closed before its first state")
    memo[node] = result
    return result
