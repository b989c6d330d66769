"""The ground planning task: bitset-encoded atoms, ground operators, initial state, goal."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from hdrc3_deliberative.model import Domain, EffectTime, Problem

GroundAtom = tuple[str, tuple[str, ...]]
NumFn = Callable[[tuple[float, ...]], float]
NumTest = Callable[[tuple[float, ...]], bool]


@dataclass(frozen=True)
class NumericEffect:
    """Ground numeric effect on feature ``index``."""

    index: int
    op: str
    value: NumFn
    time: EffectTime


@dataclass(slots=True, eq=False)  # not frozen: tens of thousands are built per problem
class GroundOp:
    """A ground operator instance with bitmask preconditions and effects.

    ``reads``/``writes`` are masks over feature ids (atoms, then numeric features, then one
    token per agent) used for the concurrency (non-interference) check.
    """

    index: int
    name: str
    args: tuple[str, ...]
    agent: str | None
    duration: float
    pre_pos: int
    pre_neg: int
    add: int
    delete: int
    start_add: int
    start_delete: int
    num_pre: tuple[NumTest, ...]
    num_effects: tuple[NumericEffect, ...]
    prevail_pos: int
    prevail_neg: int
    prevail_num: tuple[NumTest, ...]
    reads: int
    writes: int
    add_atoms: tuple[GroundAtom, ...]
    del_atoms: tuple[GroundAtom, ...]
    pre_bits: tuple[int, ...] = ()  # the bits set in pre_pos, ascending (indexes the search)

    @property
    def label(self) -> str:
        """``(name arg1 arg2)`` as in PDDL plans."""
        return "(" + " ".join((self.name, *self.args)) + ")"


@dataclass
class Task:
    """A ground planning task."""

    domain: Domain
    problem: Problem
    atoms: list[GroundAtom]
    atom_bit: dict[GroundAtom, int]
    num_features: list[GroundAtom]
    num_index: dict[GroundAtom, int]
    init_bits: int
    init_nums: tuple[float, ...]
    goal_pos: int
    goal_neg: int
    goal_num: tuple[NumTest, ...]
    goal_atoms: frozenset[GroundAtom]
    static_facts: frozenset[GroundAtom]
    static_preds: frozenset[str]
    objects_by_type: dict[str, tuple[str, ...]]
    ops: list[GroundOp]
    resource_indices: tuple[int, ...]
    by_pred: dict[str, dict[tuple[str, ...], int]] = field(default_factory=dict)
    inert_nums: tuple[int, ...] = ()  # numeric features nothing reads (plan metrics)
    static_values: dict[GroundAtom, float] = field(default_factory=dict)  # static functions

    def mask_of(self, atom: GroundAtom) -> int:
        """Bit mask of a fluent atom (0 if it can never be true)."""
        bit = self.atom_bit.get(atom)
        return 0 if bit is None else 1 << bit
