"""Hash-consed ground formula nodes: the representation that progression works on.

Every node is created through a :class:`NodeTable`, which returns the *same object* for
structurally identical compiled formulas (hash-consing); residuals can be interned too (see
:class:`NodeTable`). Identical sub-formulas are therefore one object and compare by identity;
progression memoises its result on the node per state, so a sub-formula shared by several
monitors (or appearing twice in one) is progressed once per state, and the residuals it yields
stay shared in the following states.

The constructors simplify as Definition 9.3 prescribes (``not true = false``, ``false and a =
false``, ``true and a = a``, ...) and additionally flatten nested conjunctions/disjunctions, drop
duplicates, and merge tense operands of one connective that differ only in their upper bound
(the chapter's ``eventually[0,t] phi and eventually[0,t'] phi = eventually[0,min(t,t')] phi`` and
its three siblings for ``or`` and ``always``).

Time: the intervals of compiled formulas are *relative* to the state at which the node is
progressed (a lower bound below zero is stored as zero because no state can arrive in the
past). Progression turns a pending tense node into one with *absolute* bounds (ms on the
stream's clock), so a residual need not be rebuilt with shifted intervals at every state: it
stays the same object until something in it changes. Absolute nodes print relative to a given
time (:func:`to_formula`).
"""

from __future__ import annotations

import contextlib
import enum
import math
from collections.abc import Callable, Iterable, Iterator, Mapping

from hdrc3_dyknow.formula import (
    Always,
    And,
    Atom,
    Comparison,
    Constant,
    Eventually,
    Formula,
    Interval,
    Not,
    Or,
    Until,
)
from hdrc3_dyknow.interpretation import FluentValue


class Kind(enum.IntEnum):
    """Node kinds; small ints so the progression loop dispatches with integer compares."""

    TRUE = 0
    FALSE = 1
    ATOM = 2
    COMPARE = 3
    NOT = 4
    AND = 5
    OR = 6
    ALWAYS = 7
    EVENTUALLY = 8
    UNTIL = 9


# The kinds as plain ints for the hot paths (IntEnum compares are slower).
_TRUE, _FALSE, _ATOM, _COMPARE, _NOT, _AND, _OR, _ALWAYS, _EVENTUALLY, _UNTIL = range(10)

CompareFunction = Callable[[Mapping[str, FluentValue], float], bool]
"""Compiled comparison: ``(values, time_ms) -> truth``; raises on missing fluents."""


class Node:
    """One interned formula node; build nodes only through :class:`NodeTable`.

    Only the attributes of the node's kind are set.

    Attributes:
        kind: What the node is (a :class:`Kind` value as plain int).
        key: ATOM: ground atom key; otherwise the interning key (None if not interned).
        first: Operand of NOT/ALWAYS/EVENTUALLY, left operand of UNTIL.
        second: Right operand of UNTIL (None for ALWAYS/EVENTUALLY).
        operands: Operands of AND/OR.
        lower: Lower interval bound (ms) of tense nodes: >= 0 if relative.
        upper: Upper interval bound (ms, may be inf) of tense nodes.
        absolute: Tense nodes: the bounds are times on the stream's clock, not relative to
            the state at which the node is progressed.
        compare: COMPARE: compiled comparison.
        source: ATOM/COMPARE: ground syntax tree, for printing residuals.
        memo, memo_key: Last progression result and the key of the step (state and delta
            class) it is for.

    """

    __slots__ = (
        "absolute",
        "compare",
        "first",
        "key",
        "kind",
        "lower",
        "memo",
        "memo_key",
        "operands",
        "second",
        "source",
        "upper",
    )

    kind: int
    key: object
    first: Node
    second: Node | None
    operands: tuple[Node, ...]
    lower: float
    upper: float
    absolute: bool
    compare: CompareFunction
    source: Formula
    memo: Node

    def __init__(self, kind: int, key: object) -> None:
        self.kind = kind
        self.key = key
        self.memo_key = 0  # progression memo: valid while equal to the step's memo key

    def children(self) -> tuple[Node, ...]:
        """Direct sub-nodes."""
        kind = self.kind
        if kind in (_AND, _OR):
            return self.operands
        if kind in (_NOT, _ALWAYS, _EVENTUALLY):
            return (self.first,)
        if kind == _UNTIL:
            assert self.second is not None
            return (self.first, self.second)
        return ()

    def __repr__(self) -> str:
        return f"Node({to_formula(self, 0.0)})"


class NodeTable:
    """Interning table and simplifying constructors of :class:`Node`.

    One table is shared by all formulas of a progression engine. Nodes built while compiling
    formulas (inside :meth:`compiling`) are interned for good, so identical templates - within a
    formula or across formulas - are one object.

    Residuals built by progression need no table to stay shared: each state's memo maps a node
    to one result, so everything derived from one node remains one object from state to state.
    Interning them as well only unifies residuals that became equal by different routes (e.g.
    ``eventually[500,1500] p`` added at 0 ms and ``eventually[0,1000] p`` added at 500 ms), and
    costs about a quarter of the progression time in the Figure 28 benchmark (hashing keys into
    a large dictionary). It is therefore optional: with ``intern_residuals=True`` they are
    interned per state, and :meth:`advance`, called after each state, forgets them, which
    bounds the table without a garbage-collection pass. A forgotten node stays valid for its
    holders.

    Args:
        intern_residuals: Also hash-cons the residual nodes built during each state.

    """

    def __init__(self, intern_residuals: bool = False) -> None:
        self._stamp = 0
        self._now = -math.inf
        self._intern_residuals = intern_residuals
        self._kept: dict[object, Node] = {}
        # Where new nodes are interned: the kept nodes while compiling, the current state's
        # residuals, or nowhere (None).
        self._nodes: dict[object, Node] | None = {} if intern_residuals else None
        self.true = Node(_TRUE, _TRUE)
        self.false = Node(_FALSE, _FALSE)

    def __len__(self) -> int:
        """Number of interned nodes (kept ones plus the current state's residuals)."""
        return len(self._kept) + (len(self._nodes) if self._nodes is not None else 0)

    @contextlib.contextmanager
    def compiling(self) -> Iterator[None]:
        """Within the block, nodes are interned for good (used to compile formulas)."""
        current: dict[object, Node] | None = self._nodes
        self._nodes = self._kept
        try:
            yield
        finally:
            self._nodes = current

    @property
    def interning(self) -> bool:
        """Whether new nodes are interned now (always while compiling, else on request)."""
        return self._nodes is not None

    def stamp(self, time_ms: float) -> int:
        """A new stamp identifying one progression step at ``time_ms``.

        Nodes memoise results per stamp. Residuals built from now on hold only for later
        states, so absolute lower bounds up to ``time_ms`` are equivalent when merging.
        """
        self._stamp += 1
        self._now = time_ms
        return self._stamp

    def advance(self) -> None:
        """Forget the residual nodes interned since the previous call."""
        if self._intern_residuals:
            self._nodes = {}

    def atom(self, key: str, source: Formula) -> Node:
        """Boolean fluent with ground atom key ``key`` (always interned)."""
        nodes = self._kept if self._nodes is None else self._nodes
        node = nodes.get(key) or self._kept.get(key)
        if node is None:
            node = nodes[key] = Node(_ATOM, key)
            node.source = source
        return node

    def comparison(self, compare: CompareFunction, source: Comparison | Atom) -> Node:
        """Compiled ground comparison, interned (always) by its printed ground form.

        Also a boolean fluent with nested arguments, whose key depends on the state.
        """
        key = (_COMPARE, str(source))
        nodes = self._kept if self._nodes is None else self._nodes
        node = nodes.get(key) or self._kept.get(key)
        if node is None:
            node = nodes[key] = Node(_COMPARE, key)
            node.compare = compare
            node.source = source
        return node

    def _new(self, kind: int, key: object) -> Node:
        """A node of ``kind``, registered under ``key`` when interning; attributes set by caller."""
        nodes = self._nodes
        if nodes is None:
            return Node(kind, None)
        node = nodes[key] = Node(kind, key)
        return node

    def negation(self, operand: Node) -> Node:
        """``not operand``, simplified."""
        kind = operand.kind
        if kind == _TRUE:
            return self.false
        if kind == _FALSE:
            return self.true
        if kind == _NOT:
            return operand.first
        key = (_NOT, operand)
        node = self._nodes.get(key) if self._nodes is not None else None
        if node is None:
            node = self._new(_NOT, key)
            node.first = operand
        return node

    def conjunction(self, operands: Iterable[Node]) -> Node:
        """``a and b and ...``, simplified; the empty conjunction is true."""
        return self._junction(_AND, operands, self.false, self.true)

    def disjunction(self, operands: Iterable[Node]) -> Node:
        """``a or b or ...``, simplified; the empty disjunction is false."""
        return self._junction(_OR, operands, self.true, self.false)

    def both(self, left: Node, right: Node) -> Node:
        """``left and right`` (fast path of :meth:`conjunction`)."""
        if left is right or right is self.true:
            return left
        if left is self.true:
            return right
        if left is self.false or right is self.false:
            return self.false
        return self.pair(_AND, left, right, self.false, self.true)

    def either(self, left: Node, right: Node) -> Node:
        """``left or right`` (fast path of :meth:`disjunction`)."""
        if left is right or right is self.false:
            return left
        if left is self.false:
            return right
        if left is self.true or right is self.true:
            return self.true
        return self.pair(_OR, left, right, self.true, self.false)

    def pair(self, kind: int, left: Node, right: Node, absorbing: Node, neutral: Node) -> Node:
        """Junction of ``kind`` over two operands that are neither constants nor identical.

        The caller has handled the absorbing and neutral element (fast path of :meth:`both`
        and :meth:`either`).
        """
        left_kind = left.kind
        right_kind = right.kind
        if (
            left_kind == kind
            or right_kind == kind
            or (left_kind == right_kind and left_kind in (_ALWAYS, _EVENTUALLY))
        ):
            return self._junction(kind, (left, right), absorbing, neutral)
        nodes = self._nodes
        if nodes is None:
            node = Node(kind, None)
        else:
            key = (kind, (left, right))
            found = nodes.get(key)
            if found is not None:
                return found
            node = nodes[key] = Node(kind, key)
        node.operands = (left, right)
        return node

    def absorbs(self, kind: int, keeper: Node, node: Node) -> bool:
        """Whether the junction of ``kind`` over ``keeper`` and ``node`` simplifies to ``keeper``.

        True if they are one node, or tense nodes that merge (see :meth:`conjunction`) into
        ``keeper`` or into an equivalent node.
        """
        if node is keeper:
            return True
        tense = node.kind
        if tense not in (_ALWAYS, _EVENTUALLY) or keeper.kind != tense:
            return False
        if not _same_start(keeper, node, self._now):
            return False
        return node.upper == keeper.upper or (node.upper > keeper.upper) != _keeps_larger(
            kind, tense
        )

    def always(self, lower: float, upper: float, body: Node) -> Node:
        """``always[lower, upper] body``; ``lower`` below zero is clamped to zero."""
        if lower > upper or upper < 0 or body is self.true:
            return self.true
        return self.tense(_ALWAYS, lower if lower > 0 else 0.0, upper, body, None)

    def eventually(self, lower: float, upper: float, body: Node) -> Node:
        """``eventually[lower, upper] body``; ``lower`` below zero is clamped to zero."""
        if lower > upper or upper < 0 or body is self.false:
            return self.false
        return self.tense(_EVENTUALLY, lower if lower > 0 else 0.0, upper, body, None)

    def until(self, lower: float, upper: float, left: Node, right: Node) -> Node:
        """``left until[lower, upper] right``; ``lower`` below zero is clamped to zero."""
        if lower > upper or upper < 0 or right is self.false:
            return self.false
        return self.tense(_UNTIL, lower if lower > 0 else 0.0, upper, left, right)

    def tense(
        self,
        kind: int,
        lower: float,
        upper: float,
        first: Node,
        second: Node | None,
        absolute: bool = False,
    ) -> Node:
        """Tense node; a relative ``lower`` must already be clamped, the interval non-empty."""
        nodes = self._nodes
        if nodes is None:
            node = Node(kind, None)
        else:
            key = (kind, lower, upper, first, second, absolute)
            found = nodes.get(key)
            if found is not None:
                return found
            node = nodes[key] = Node(kind, key)
        node.lower = lower
        node.upper = upper
        node.first = first
        node.second = second
        node.absolute = absolute
        return node

    def _junction(
        self, kind: int, operands: Iterable[Node], absorbing: Node, neutral: Node
    ) -> Node:
        flat: list[Node] = []
        for operand in operands:
            if operand is absorbing:
                return absorbing
            if operand is neutral:
                continue
            for part in operand.operands if operand.kind == kind else (operand,):
                if part not in flat:
                    part_kind = part.kind
                    if part_kind in (_ALWAYS, _EVENTUALLY):
                        _merge_tense(kind, flat, part, self._now)
                    else:
                        flat.append(part)
        if len(flat) < 2:
            return flat[0] if flat else neutral
        members = tuple(flat)
        key = (kind, members)
        node = self._nodes.get(key) if self._nodes is not None else None
        if node is None:
            node = self._new(kind, key)
            node.operands = members
        return node


def _merge_tense(kind: int, flat: list[Node], node: Node, now: float) -> None:
    """Add ALWAYS/EVENTUALLY ``node`` to ``flat``, merged with an operand of equal lower bound.

    With equal lower bound and body, the operand with the smaller window implies the other for
    EVENTUALLY and is implied by it for ALWAYS; a conjunction keeps the stronger, a disjunction
    the weaker operand, at the position of the first of the two. Junctions are short, so a
    linear scan beats building an index.
    """
    for index, other in enumerate(flat):
        if other.kind == node.kind and _same_start(other, node, now):
            if (node.upper > other.upper) == _keeps_larger(kind, node.kind):
                flat[index] = node
            return
    flat.append(node)


def _keeps_larger(kind: int, tense: int) -> bool:
    """Whether a junction of ``kind`` keeps the larger window of two ``tense`` operands."""
    return (tense == _ALWAYS) == (kind == _AND)


def _same_start(one: Node, two: Node, now: float) -> bool:
    """Whether tense nodes of one kind differ at most in their upper bound, after ``now``.

    Absolute lower bounds up to ``now`` are equal: no later state lies before them.
    """
    if one.first is not two.first or one.absolute is not two.absolute:
        return False
    if one.absolute:
        return max(one.lower, now) == max(two.lower, now)
    return one.lower == two.lower


def to_formula(node: Node, time_ms: float = 0.0) -> Formula:
    """The syntax tree of a ground node, absolute intervals relative to ``time_ms``."""
    kind = node.kind
    if kind == Kind.TRUE or kind == Kind.FALSE:
        return Constant(kind == Kind.TRUE)
    if kind == Kind.ATOM or kind == Kind.COMPARE:
        return node.source
    if kind == Kind.NOT:
        return Not(to_formula(node.first, time_ms))
    if kind == Kind.AND:
        return And(tuple(to_formula(operand, time_ms) for operand in node.operands))
    if kind == Kind.OR:
        return Or(tuple(to_formula(operand, time_ms) for operand in node.operands))
    if node.absolute:
        interval = Interval(max(node.lower - time_ms, 0.0), node.upper - time_ms)
    else:
        interval = Interval(node.lower, node.upper)
    # Operands of tense nodes are compiled formulas: relative, whatever the time.
    if kind == Kind.ALWAYS:
        return Always(interval, to_formula(node.first))
    if kind == Kind.EVENTUALLY:
        return Eventually(interval, to_formula(node.first))
    assert node.second is not None
    return Until(interval, to_formula(node.first), to_formula(node.second))
