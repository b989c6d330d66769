"""Pruning constraints compiled from control rules, as used by the search (Algorithm 3).

:class:`ControlProgram` holds the initial, incremental (per operator schema) and final
constraints produced by :class:`hdrc3_deliberative.control.ControlCompiler`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from hdrc3_deliberative.model import Atom, AtomEffect, NumEffect, Param, RuleKind
from hdrc3_deliberative.task import GroundOp, Task

Env = dict[str, str]
Eval = Callable[[Env, int, int], bool]


@dataclass
class NumberState:
    """Numeric states ``[t]`` and ``[t+1]`` the comparisons of control formulas read.

    Rule closures take only the boolean states; :class:`ControlProgram` stores the numeric
    states here before an evaluation, and a comparison sets ``read`` (such verdicts are not
    memoised under the boolean atoms alone).
    """

    states: list[tuple[float, ...]] = field(default_factory=lambda: [(), ()])
    read: bool = False

    def set(self, before: tuple[float, ...], after: tuple[float, ...]) -> None:
        """Numeric state at ``t`` and at ``t+1``; clears ``read``."""
        self.states[0] = before
        self.states[1] = after
        self.read = False


@dataclass(frozen=True)
class Trigger:
    """The rule is violated only by actions that add (``on_add``) or delete a ``pred`` atom."""

    pred: str
    on_add: bool
    atom: Atom


@dataclass(frozen=True)
class CompiledRule:
    """One control rule compiled against a task."""

    name: str
    kind: RuleKind
    full: Callable[[int, int], bool]
    trigger: Trigger | None
    triggered_body: Eval | None
    outer: tuple[Param, ...]
    fluent_preds: frozenset[str]
    outer_types: tuple[tuple[str, str], ...] = ()


class ControlProgram:
    """The compiled pruning constraints of a control specification."""

    def __init__(
        self,
        task: Task,
        rules: tuple[CompiledRule, ...],
        reads: list[int],
        numbers: NumberState | None = None,
    ) -> None:
        self.task = task
        self.rules = rules
        self._reads = reads
        self.numbers = numbers or NumberState()
        self._memo: dict[int, list[tuple[int, int, str | None]]] = {}
        self._type_sets = {t: frozenset(objs) for t, objs in task.objects_by_type.items()}
        self._incremental: dict[str, tuple[CompiledRule, ...]] = {}
        for op in task.domain.operators:
            adds = {
                e.literal.atom.pred
                for e in op.effects
                if isinstance(e, AtomEffect) and e.literal.positive
            }
            dels = {
                e.literal.atom.pred
                for e in op.effects
                if isinstance(e, AtomEffect) and not e.literal.positive
            }
            dels |= {e.target.pred for e in op.effects if isinstance(e, NumEffect)}
            selected = []
            for rule in rules:
                if rule.kind is not RuleKind.ALWAYS:
                    continue
                if rule.trigger is not None:
                    if rule.trigger.pred in (adds if rule.trigger.on_add else dels):
                        selected.append(rule)
                elif rule.fluent_preds & (adds | dels):
                    selected.append(rule)
            self._incremental[op.name] = tuple(selected)

    def incremental_rules(self, schema: str) -> tuple[CompiledRule, ...]:
        """Rules an occurrence of operator ``schema`` must be checked against."""
        return self._incremental.get(schema, ())

    def initial_violation(self, state: int, nums: tuple[float, ...] = ()) -> str | None:
        """Name of a rule the initial state violates (initial constraint), else None."""
        self.numbers.set(nums, nums)
        violated = None
        for rule in self.rules:
            if (
                rule.kind is RuleKind.ALWAYS
                and rule.trigger is None
                and not rule.full(state, state)
            ):
                violated = rule.name
                break
        self._reads.clear()
        return violated

    def step_violation(
        self,
        op: GroundOp,
        before: int,
        after: int,
        nums_before: tuple[float, ...] = (),
        nums_after: tuple[float, ...] = (),
    ) -> str | None:
        """Incremental constraints of ``op`` on the transition it causes.

        Evaluation is deterministic and ``after`` follows from ``before`` and ``op``, so the
        verdict depends only on the fluent atoms the evaluation read: it is memoised per
        operator under those atoms' values (depth-first search re-checks the same operators
        at many consecutive nodes). Verdicts that read a numeric comparison are not memoised.
        """
        entries = self._memo.setdefault(op.index, [])
        for read_mask, values, verdict in entries:
            if before & read_mask == values:
                return verdict
        self._reads.clear()
        self.numbers.set(nums_before, nums_after)
        verdict = self._step_violation(op, before, after)
        read_mask = op.add | op.delete  # the transition itself
        for mask in self._reads:
            read_mask |= mask
        self._reads.clear()
        if self.numbers.read:
            return verdict
        if len(entries) >= 4:
            entries.pop(0)
        entries.append((read_mask, before & read_mask, verdict))
        return verdict

    def _step_violation(self, op: GroundOp, before: int, after: int) -> str | None:
        for rule in self._incremental.get(op.name, ()):
            if rule.trigger is None:
                if not rule.full(before, after):
                    return rule.name
                states = self.numbers.states
                saved, states[0] = states[0], states[1]  # the new state paired with itself
                holds = rule.full(after, after)
                states[0] = saved
                if not holds:
                    return rule.name
                continue
            assert rule.triggered_body is not None
            trig = rule.trigger
            outer_types = dict(rule.outer_types)
            for pred, args in op.add_atoms if trig.on_add else op.del_atoms:
                if pred != trig.pred:
                    continue
                env: Env = {}
                ok = True
                for term, value in zip(trig.atom.args, args, strict=True):
                    if term.name in outer_types:
                        if env.setdefault(
                            term.name, value
                        ) != value or value not in self._type_sets.get(outer_types[term.name], ()):
                            ok = False
                            break
                    elif term.name != value:
                        ok = False
                        break
                if ok and not rule.triggered_body(env, before, after):
                    return rule.name
        return None

    def final_violation(self, state: int, nums: tuple[float, ...] = ()) -> str | None:
        """Final constraints: final rules hold in the end state."""
        self.numbers.set(nums, nums)
        violated = None
        for rule in self.rules:
            if rule.kind is RuleKind.FINAL and not rule.full(state, state):
                violated = rule.name
                break
        self._reads.clear()
        return violated
