"""Grounding: domain + problem -> compact planning task of bitset-encoded ground operators.

Boolean fluent atoms are interned as bit positions of a Python int; numeric features are
indices into a tuple. Operators are instantiated by relaxed reachability (only instances whose
positive fluent preconditions can become true), static predicates are evaluated away, and
flight durations/costs come from the motion-plan-info hook.

Two stages, both written for hdrc3 (the task format is the planner's own):

* Reachability (``Grounder.ground``): a semi-naive fixpoint. Each round joins every
  operator's positive preconditions (static ones included: the fact index holds the static
  facts) against the reachable facts with the join plans of ``matching.py``, seeded by the
  facts first reached in the previous round; an instance never seen before is kept if its
  object (in)equalities hold and no negative static literal is in the initial state, and its
  add effects become reachable facts. Instances are parameter-value tuples.
* Encoding (``Grounder._encode``): atoms sorted and numbered, then each instance (in sorted
  order) becomes a ``GroundOp``. Each operator is compiled once into a ``_Schema``: every
  literal's arguments are positions in ``values + constants`` read by an ``itemgetter``, and
  each predicate has a table from argument tuples to bits, so an instance needs no binding
  dict (unless it has comparisons, prevail conditions, numeric effects or a non-constant
  duration) and no atom tuple for its preconditions. The agent token is written in the
  same pass.

The cyclic garbage collector is paused while grounding (``paused_gc``): the hundreds of
thousands of acyclic objects made would otherwise be walked by every generation-2 pass.

Grounding is interruptible: with a deadline it checks the clock every few hundred bindings
and raises :class:`GroundingTimeout` once the deadline has passed, so a planning timeout
covers grounding as well as search.
"""

from __future__ import annotations

import gc
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from operator import itemgetter

from hdrc3_deliberative.errors import GroundingTimeout, PlanningInputError
from hdrc3_deliberative.matching import FactIndex, JoinPlan, join_plan, match
from hdrc3_deliberative.model import (
    Atom,
    AtomEffect,
    BinOp,
    Comparison,
    Condition,
    Domain,
    EffectTime,
    Equality,
    FuncTerm,
    Literal,
    Num,
    NumEffect,
    NumExpr,
    Operator,
    Pos,
    Problem,
)
from hdrc3_deliberative.motion_plan_info import MotionPlanInfo, StraightLineMotionPlanInfo
from hdrc3_deliberative.names import FLIGHT_FUNCTIONS, NameChecker, TypeTable
from hdrc3_deliberative.task import GroundAtom, GroundOp, NumericEffect, NumFn, NumTest, Task

ArgsGetter = Callable[[tuple[str, ...]], tuple[str, ...]]  # parameter values -> atom arguments
_NONE: tuple[int, int, list[NumTest], int] = (0, 0, [], 0)  # no conditions
_COMPARE: dict[str, Callable[[float, float], bool]] = {
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b + 1e-9,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b - 1e-9,
    "=": lambda a, b: abs(a - b) <= 1e-9,
    "!=": lambda a, b: abs(a - b) > 1e-9,
}


def _fail(message: str, pos: Pos) -> PlanningInputError:
    return PlanningInputError(message, pos.source, pos.line, pos.column)


def _args_getter(atom: Atom, slot_of: dict[str, int]) -> ArgsGetter:
    """The arguments of ``atom`` from an instance's values (constants appended, see _Schema)."""
    slots = tuple(slot_of[t.name] for t in atom.args)
    if not slots:
        return lambda ext: ()
    if len(slots) == 1:
        only = slots[0]
        return lambda ext: (ext[only],)
    return itemgetter(*slots)


class _Schema:
    """An operator compiled once for instantiation from tuples of parameter values.

    Every atom's arguments become positions in ``values + consts`` (the operator's parameter
    values, then the constants its atoms name), read by a C-level ``itemgetter``: instances
    need no binding dict unless a comparison, prevail condition, numeric effect or
    non-constant duration reads the parameters (``needs_env``).
    """

    def __init__(self, op: Operator, static_preds: frozenset[str]) -> None:
        self.op = op
        self.names = tuple(p.name for p in op.params)
        slot_of = {name: i for i, name in enumerate(self.names)}
        consts: list[str] = []
        atoms = [c.atom for c in op.pre if isinstance(c, Literal)]
        atoms += [e.literal.atom for e in op.effects if isinstance(e, AtomEffect)]
        terms = [t.name for a in atoms for t in a.args]
        terms += [n for c in op.pre if isinstance(c, Equality) for n in (c.left.name, c.right.name)]
        for name in terms:
            if name not in slot_of:
                slot_of[name] = len(self.names) + len(consts)
                consts.append(name)
        self.consts = tuple(consts)
        # positive static literals are matched by the join (the fact index holds the static
        # facts), so only equalities and negative static literals remain to be checked
        self.equalities = tuple(
            (slot_of[c.left.name], slot_of[c.right.name], c.positive)
            for c in op.pre
            if isinstance(c, Equality)
        )
        self.static_neg = tuple(
            (c.atom.pred, _args_getter(c.atom, slot_of))
            for c in op.pre
            if isinstance(c, Literal) and not c.positive and c.atom.pred in static_preds
        )
        self.reach_adds = tuple(
            (e.literal.atom.pred, _args_getter(e.literal.atom, slot_of))
            for e in op.effects
            if isinstance(e, AtomEffect) and e.literal.positive
        )
        self.fluent_pre = tuple(
            (c.atom.pred, _args_getter(c.atom, slot_of), c.positive)
            for c in op.pre
            if isinstance(c, Literal) and c.atom.pred not in static_preds
        )
        self.effects = tuple(
            (
                e.literal.atom.pred,
                _args_getter(e.literal.atom, slot_of),
                e.literal.positive,
                e.time is EffectTime.START,
            )
            for e in op.effects
            if isinstance(e, AtomEffect)
        )
        self.start_effects = any(start for *_, start in self.effects)
        self.comparisons = tuple(c for c in op.pre if isinstance(c, Comparison))
        self.numeric = tuple(e for e in op.effects if isinstance(e, NumEffect))
        self.agent_slot = None if op.agent is None else slot_of[op.agent]
        self.needs_env = bool(
            self.comparisons or op.prevail or self.numeric or not isinstance(op.duration, Num)
        )

    def tables(self, bits_by_pred: dict[str, dict[tuple[str, ...], int]]) -> _Tables:
        """The literal templates with each predicate's (arguments -> bit) table resolved."""
        return _Tables(
            pre=tuple(
                (bits_by_pred.get(pred, {}), get, positive)
                for pred, get, positive in self.fluent_pre
            ),
            effects=tuple(
                (pred, bits_by_pred.get(pred, {}), get, positive, start)
                for pred, get, positive, start in self.effects
            ),
        )


@dataclass(frozen=True)
class _Tables:
    """A schema's literal templates bound to the bit tables of one encoding."""

    pre: tuple[tuple[dict[tuple[str, ...], int], ArgsGetter, bool], ...]
    effects: tuple[
        tuple[str, dict[tuple[str, ...], int], ArgsGetter, bool, bool],
        ...,
    ]


class Grounder:
    """Builds a :class:`Task`; one instance per (domain, problem)."""

    def __init__(
        self,
        domain: Domain,
        problem: Problem,
        motion: MotionPlanInfo | None = None,
        deadline: float = float("inf"),
        clock: Callable[[], float] = time.perf_counter,
    ) -> None:
        self.deadline = deadline
        self.clock = clock
        self._ticks = 0
        self.domain = domain
        self.problem = problem
        self.motion = motion or StraightLineMotionPlanInfo()
        self.types = TypeTable(domain, problem)
        if problem.domain != domain.name:
            raise _fail(
                f"problem is for domain '{problem.domain}', not '{domain.name}'",
                Pos(problem.source, 1, 1),
            )
        NameChecker(domain, problem, self.types).check()
        effect_preds = {
            e.literal.atom.pred
            for op in domain.operators
            for e in op.effects
            if isinstance(e, AtomEffect)
        }
        self.static_preds = frozenset(domain.predicates) - effect_preds
        num_targets = {
            e.target.pred for op in domain.operators for e in op.effects if isinstance(e, NumEffect)
        }
        self.fluent_funcs = frozenset(num_targets)
        self.static_values: dict[GroundAtom, float] = {}
        self.init_num_values: dict[GroundAtom, float] = {}
        for atom, value in problem.init_values:
            key = (atom.pred, tuple(t.name for t in atom.args))
            (self.init_num_values if atom.pred in num_targets else self.static_values)[key] = value
        self._n_atoms = 0
        self._getters: dict[int, Callable[[dict[str, str]], GroundAtom]] = {}
        self._compiled_conds: dict[
            int, list[tuple[Condition, Callable[[dict[str, str]], GroundAtom] | None]]
        ] = {}
        self._type_members: dict[str, frozenset[str]] = {}
        self.static_facts: set[GroundAtom] = set()
        self.init_fluents: set[GroundAtom] = set()
        for atom in problem.init:
            key = (atom.pred, tuple(t.name for t in atom.args))
            (self.static_facts if atom.pred in self.static_preds else self.init_fluents).add(key)

    def _position(self, obj: str) -> tuple[float, float, float]:
        if obj not in self.problem.positions:
            raise _fail(
                f"object '{obj}' has no position '@ (x, y, z)' for flight queries",
                Pos(self.problem.source),
            )
        return self.problem.positions[obj]

    def _num(
        self, expr: NumExpr, env: dict[str, str], num_index: dict[GroundAtom, int]
    ) -> NumFn | float | None:
        """Compile to a constant (float), a closure over the numeric state, or None (undefined)."""
        if isinstance(expr, Num):
            return expr.value
        if isinstance(expr, FuncTerm):
            args = tuple(env.get(t.name, t.name) for t in expr.atom.args)
            if expr.atom.pred in FLIGHT_FUNCTIONS:
                info = self.motion.query(args[0], self._position(args[1]), self._position(args[2]))
                if not info.feasible:
                    return None
                return info.duration if expr.atom.pred == "flight-time" else info.cost
            key = (expr.atom.pred, args)
            if expr.atom.pred in self.fluent_funcs:
                if key not in num_index:
                    raise _fail(
                        f"no initial value for numeric feature {key[0]}({', '.join(key[1])})",
                        expr.atom.pos,
                    )
                idx = num_index[key]
                return lambda nums: nums[idx]
            return self.static_values.get(key)
        left = self._num(expr.left, env, num_index)
        right = self._num(expr.right, env, num_index)
        if left is None or right is None:
            return None
        op = expr.op
        if isinstance(left, float) and isinstance(right, float):
            return _arith(op, left, right)
        lf = _as_fn(left)
        rf = _as_fn(right)
        return lambda nums: _arith(op, lf(nums), rf(nums))

    def _tick(self) -> None:
        """Raise GroundingTimeout when the deadline has passed (checked every 256 calls)."""
        self._ticks += 1
        if self._ticks & 255 == 0 and self.clock() > self.deadline:
            raise GroundingTimeout("grounding did not finish before the deadline")

    def _members(self, tname: str) -> frozenset[str]:
        """Objects of a type (cached)."""
        found = self._type_members.get(tname)
        if found is None:
            found = frozenset(self.types.objects.get(tname, ()))
            self._type_members[tname] = found
        return found

    def _ga(self, atom: Atom, env: dict[str, str]) -> GroundAtom:
        """Ground an atom under a binding; per-atom getters avoid re-reading its terms."""
        getter = self._getters.get(id(atom))
        if getter is None:
            getter = _atom_getter(atom)
            self._getters[id(atom)] = getter
        return getter(env)

    def _num_reads(
        self, expr: NumExpr, env: dict[str, str], num_index: dict[GroundAtom, int]
    ) -> int:
        """Mask of the numeric fluents an expression reads."""
        if isinstance(expr, BinOp):
            return self._num_reads(expr.left, env, num_index) | self._num_reads(
                expr.right, env, num_index
            )
        if isinstance(expr, FuncTerm) and expr.atom.pred in self.fluent_funcs:
            key = self._ga(expr.atom, env)
            if key in num_index:
                return 1 << (self._n_atoms + num_index[key])
        return 0

    def ground(self) -> Task:
        """Instantiate reachable operators and encode everything as bitsets.

        Semi-naive relaxed reachability: the first round matches every operator against the
        initial facts; each later round matches, for every positive precondition, only the
        facts first reached in the previous round (joined with all facts).
        """
        with paused_gc():
            return self._ground()

    def _ground(self) -> Task:
        facts = FactIndex()
        for pred, args in sorted(self.static_facts | self.init_fluents):
            facts.add(pred, args)
        reached = set(self.init_fluents)
        instances: dict[tuple[str, tuple[str, ...]], tuple[_Schema, tuple[str, ...]]] = {}
        plans: dict[tuple[str, int], JoinPlan] = {}
        schemas = [_Schema(op, self.static_preds) for op in self.domain.operators]
        static_facts = self.static_facts
        delta: dict[str, list[tuple[str, ...]]] | None = None  # None: first, full round
        while delta is None or delta:
            new_delta: dict[str, list[tuple[str, ...]]] = {}
            for schema in schemas:
                op = schema.op
                members = [self._members(p.type) for p in op.params]
                objects = [self.types.objects.get(p.type, ()) for p in op.params]
                found: list[tuple[str, ...]] = []
                if delta is None:
                    plan = plans.get((op.name, -1)) or join_plan(op, None)
                    plans[(op.name, -1)] = plan
                    found = match(plan, facts, members, objects, self._tick)
                else:
                    for i, c in enumerate(op.pre):
                        if isinstance(c, Literal) and c.positive and c.atom.pred in delta:
                            plan = plans.get((op.name, i)) or join_plan(op, c.atom)
                            plans[(op.name, i)] = plan
                            found += match(
                                plan, facts, members, objects, self._tick, delta[c.atom.pred]
                            )
                consts, equalities, static_neg = schema.consts, schema.equalities, schema.static_neg
                for values in found:
                    key = (op.name, values)
                    if key in instances:
                        continue
                    ext = values + consts if consts else values
                    if equalities and any(
                        (ext[a] == ext[b]) != positive for a, b, positive in equalities
                    ):
                        continue
                    if static_neg and any(
                        (pred, get(ext)) in static_facts for pred, get in static_neg
                    ):
                        continue
                    instances[key] = (schema, values)
                    for pred, get in schema.reach_adds:
                        atom = (pred, get(ext))
                        if atom not in reached:
                            reached.add(atom)
                            facts.add(pred, atom[1])
                            new_delta.setdefault(pred, []).append(atom[1])
            delta = new_delta
        return self._encode(instances, reached)

    def _encode(
        self,
        instances: dict[tuple[str, tuple[str, ...]], tuple[_Schema, tuple[str, ...]]],
        reached: set[GroundAtom],
    ) -> Task:
        goal_atoms = {_ground_atom(c.atom, {}) for c in self.problem.goal if isinstance(c, Literal)}
        atoms = sorted(reached | {a for a in goal_atoms if a[0] not in self.static_preds})
        atom_bit = {a: i for i, a in enumerate(atoms)}
        num_index: dict[GroundAtom, int] = {}
        for key in sorted(self.init_num_values):
            num_index[key] = len(num_index)
        self._n_atoms = len(atoms)
        agents = sorted(
            {
                values[schema.agent_slot]
                for schema, values in instances.values()
                if schema.agent_slot is not None
            }
        )
        n_atoms, n_nums = len(atoms), len(num_index)
        # agents are exclusive: each action of an agent writes that agent's token
        agent_token = {a: 1 << (n_atoms + n_nums + i) for i, a in enumerate(agents)}
        bits_by_pred: dict[str, dict[tuple[str, ...], int]] = {}
        for atom, bit in atom_bit.items():
            bits_by_pred.setdefault(atom[0], {})[atom[1]] = bit
        tables: dict[int, _Tables] = {}
        ops: list[GroundOp] = []
        for key in sorted(instances):
            schema, values = instances[key]
            self._tick()
            found = tables.get(id(schema))
            if found is None:
                found = tables[id(schema)] = schema.tables(bits_by_pred)
            ground = self._ground_op(
                len(ops), schema, values, found, atom_bit, num_index, agent_token
            )
            if ground is not None:
                ops.append(ground)
        init_bits = 0
        for atom in self.init_fluents:
            init_bits |= 1 << atom_bit[atom]
        missing = [k for k in num_index if k not in self.init_num_values]
        if missing:
            pred, args = missing[0]
            raise _fail(
                f"no initial value for numeric feature {pred}({', '.join(args)})",
                Pos(self.problem.source),
            )
        init_nums = tuple(self.init_num_values[k] for k in num_index)
        goal_pos = goal_neg = 0
        goal_num: list[NumTest] = []
        for cond in self.problem.goal:
            if isinstance(cond, Literal):
                atom = _ground_atom(cond.atom, {})
                if atom[0] in self.static_preds:
                    if (atom in self.static_facts) != cond.positive:
                        goal_pos |= 1 << len(atoms)  # an unreachable bit: goal is false
                    continue
                if cond.positive:
                    goal_pos |= 1 << atom_bit[atom]
                else:
                    goal_neg |= 1 << atom_bit[atom]
            elif isinstance(cond, Comparison):
                test = self._compare(cond, {}, num_index)
                if test is None:
                    goal_pos |= 1 << len(atoms)
                else:
                    goal_num.append(test)
            elif (cond.left.name == cond.right.name) != cond.positive:
                goal_pos |= 1 << len(atoms)
        resource_indices = tuple(i for k, i in num_index.items() if k[0] in self.domain.resources)
        read = self._read_functions()
        inert = tuple(i for k, i in num_index.items() if k[0] not in read)
        by_pred: dict[str, dict[tuple[str, ...], int]] = {}
        for atom, bit in atom_bit.items():
            by_pred.setdefault(atom[0], {})[atom[1]] = 1 << bit
        return Task(
            domain=self.domain,
            problem=self.problem,
            atoms=atoms,
            atom_bit=atom_bit,
            num_features=list(num_index),
            num_index=num_index,
            init_bits=init_bits,
            init_nums=init_nums,
            goal_pos=goal_pos,
            goal_neg=goal_neg,
            goal_num=tuple(goal_num),
            goal_atoms=frozenset(goal_atoms),
            static_facts=frozenset(self.static_facts),
            static_preds=self.static_preds,
            objects_by_type=dict(self.types.objects),
            ops=ops,
            resource_indices=resource_indices,
            by_pred=by_pred,
            inert_nums=inert,
            static_values=dict(self.static_values),
        )

    def _read_functions(self) -> frozenset[str]:
        """Functions whose values some condition, duration or effect value reads.

        The others (``total-cost``, ``total-fuel-used``) only accumulate plan metrics: they
        cannot change which plans are valid, so the cycle check ignores them.
        """
        exprs: list[NumExpr] = []
        conds = [*self.problem.goal]
        for op in self.domain.operators:
            conds.extend(op.pre + op.prevail)
            exprs.append(op.duration)
            exprs.extend(e.value for e in op.effects if isinstance(e, NumEffect))
        for cond in conds:
            if isinstance(cond, Comparison):
                exprs.extend((cond.left, cond.right))
        found: set[str] = set()
        while exprs:
            expr = exprs.pop()
            if isinstance(expr, BinOp):
                exprs.extend((expr.left, expr.right))
            elif isinstance(expr, FuncTerm):
                found.add(expr.atom.pred)
        return frozenset(found)

    def _compare(
        self, cond: Comparison, env: dict[str, str], num_index: dict[GroundAtom, int]
    ) -> NumTest | None:
        left = self._num(cond.left, env, num_index)
        right = self._num(cond.right, env, num_index)
        if left is None or right is None:
            return None
        cmp = _COMPARE[cond.op]
        lf, rf = _as_fn(left), _as_fn(right)
        return lambda nums: cmp(lf(nums), rf(nums))

    def _conds(
        self,
        conds: tuple[Condition, ...],
        env: dict[str, str],
        atom_bit: dict[GroundAtom, int],
        num_index: dict[GroundAtom, int],
    ) -> tuple[int, int, list[NumTest], int] | None:
        """(positive mask, negative mask, numeric tests, read mask) or None if unsatisfiable."""
        pos = neg = reads = 0
        tests: list[NumTest] = []
        static_preds, static_facts = self.static_preds, self.static_facts
        for cond, getter in self._compiled(conds):
            if getter is not None:
                atom = getter(env)
                positive = cond.positive  # type: ignore[union-attr]
                if atom[0] in static_preds:
                    if (atom in static_facts) != positive:
                        return None
                    continue
                bit = atom_bit.get(atom)
                if bit is None:
                    if positive:
                        return None
                    continue
                if positive:
                    pos |= 1 << bit
                else:
                    neg |= 1 << bit
            elif isinstance(cond, Equality):
                if (
                    env.get(cond.left.name, cond.left.name)
                    == env.get(cond.right.name, cond.right.name)
                ) != cond.positive:
                    return None
            else:
                assert isinstance(cond, Comparison)
                test = self._compare(cond, env, num_index)
                if test is None:
                    return None
                tests.append(test)
                reads |= self._num_reads(cond.left, env, num_index)
                reads |= self._num_reads(cond.right, env, num_index)
        return pos, neg, tests, reads | pos | neg

    def _compiled(
        self, conds: tuple[Condition, ...]
    ) -> list[tuple[Condition, Callable[[dict[str, str]], GroundAtom] | None]]:
        """Conditions with an atom getter for literals (cached per condition tuple)."""
        found = self._compiled_conds.get(id(conds))
        if found is None:
            found = [(c, _atom_getter(c.atom) if isinstance(c, Literal) else None) for c in conds]
            self._compiled_conds[id(conds)] = found
        return found

    def _ground_op(
        self,
        index: int,
        schema: _Schema,
        values: tuple[str, ...],
        tables: _Tables,
        atom_bit: dict[GroundAtom, int],
        num_index: dict[GroundAtom, int],
        agent_token: dict[str, int],
    ) -> GroundOp | None:
        """Encode one reachable instance (``values`` of ``schema``'s parameters).

        Static literals and object (in)equalities were checked when the instance was found,
        so the precondition needs only its fluent literals and comparisons.
        """
        op = schema.op
        ext = values + schema.consts if schema.consts else values
        env = dict(zip(schema.names, values, strict=True)) if schema.needs_env else {}
        pre: tuple[int, int, list[NumTest], int] | None
        pos = neg = 0
        pre_bits: list[int] = []
        for table, get, positive in tables.pre:
            bit = table.get(get(ext))
            if bit is None:
                if positive:
                    pos = -1
                    break
            elif positive:
                pos |= 1 << bit
                pre_bits.append(bit)
            else:
                neg |= 1 << bit
        if pos < 0:
            pre = None
        elif schema.comparisons:
            rest = self._conds(schema.comparisons, env, atom_bit, num_index)
            pre = None if rest is None else (pos, neg, rest[2], rest[3] | pos | neg)
        else:
            pre = (pos, neg, [], pos | neg if neg else pos)
        prevail = self._conds(op.prevail, env, atom_bit, num_index) if op.prevail else _NONE
        duration = (
            op.duration.value
            if isinstance(op.duration, Num)
            else self._num(op.duration, env, num_index)
        )
        if pre is None or prevail is None or duration is None or callable(duration):
            return None
        if duration <= 0:
            raise _fail(f"operator '{op.name}' has non-positive duration {duration}", op.pos)
        writes = 0
        add_bits: dict[int, bool] = {}  # bit -> added at the start; insertion-ordered
        del_bits: dict[int, bool] = {}
        add_atoms: list[GroundAtom] = []
        del_atoms: list[GroundAtom] = []
        num_effects: list[NumericEffect] = []
        reads = pre[3]
        for pred, table, get, positive, at_start in tables.effects:
            args = get(ext)
            bit = table.get(args)
            if bit is None:
                continue  # deleting an atom that can never be true
            if positive:
                add_bits[bit] = at_start
                del_bits.pop(bit, None)
                add_atoms.append((pred, args))
            else:
                del_bits[bit] = at_start
                del_atoms.append((pred, args))
        for eff in schema.numeric:
            target = self._ga(eff.target, env)
            if target not in num_index:
                raise _fail(
                    f"no initial value for numeric feature {target[0]}({', '.join(target[1])})",
                    eff.target.pos,
                )
            value = self._num(eff.value, env, num_index)
            if value is None:
                return None
            reads |= self._num_reads(eff.value, env, num_index)
            num_effects.append(NumericEffect(num_index[target], eff.op, _as_fn(value), eff.time))
            writes |= 1 << (self._n_atoms + num_index[target])
        for bit in add_bits:
            del_bits.pop(bit, None)  # an atom both added and deleted ends up true
        add = _mask(add_bits)
        delete = _mask(del_bits)
        start_add = start_delete = 0
        if schema.start_effects:
            start_add = _mask([b for b, start in add_bits.items() if start])
            start_delete = _mask([b for b, start in del_bits.items() if start])
        writes = (writes | add | delete) if writes else add | delete
        agent = None
        if schema.agent_slot is not None:
            agent = values[schema.agent_slot]
            writes |= agent_token[agent]
        return GroundOp(
            index=index,
            name=op.name,
            args=values,
            agent=agent,
            duration=float(duration),
            pre_pos=pre[0],
            pre_neg=pre[1],
            add=add,
            delete=delete,
            start_add=start_add,
            start_delete=start_delete,
            num_pre=tuple(pre[2]),
            num_effects=tuple(num_effects),
            prevail_pos=prevail[0],
            prevail_neg=prevail[1],
            prevail_num=tuple(prevail[2]),
            reads=reads,
            writes=writes,
            add_atoms=tuple(add_atoms),
            del_atoms=tuple(del_atoms),
            pre_bits=tuple(sorted(set(pre_bits))),
        )


def _mask(bits: Iterable[int]) -> int:
    """The int with exactly the given bits set (one big-int allocation per bit at most)."""
    out = 0
    for bit in bits:
        out |= 1 << bit
    return out


def _atom_getter(atom: Atom) -> Callable[[dict[str, str]], GroundAtom]:
    names = tuple(t.name for t in atom.args)
    pred = atom.pred
    if len(names) == 1:
        only = names[0]
        return lambda env: (pred, (env.get(only, only),))
    if len(names) == 2:
        first, second = names
        return lambda env: (pred, (env.get(first, first), env.get(second, second)))
    return lambda env: (pred, tuple(env.get(n, n) for n in names))


def _ground_atom(atom: Atom, env: dict[str, str]) -> GroundAtom:
    return (atom.pred, tuple(env.get(t.name, t.name) for t in atom.args))


def _arith(op: str, a: float, b: float) -> float:
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    return a / b if b else float("inf")


def _as_fn(value: NumFn | float) -> NumFn:
    if callable(value):
        return value
    constant = float(value)
    return lambda nums: constant


@contextmanager
def paused_gc() -> Iterator[None]:
    """Pause the cyclic garbage collector for a block (restores the previous state).

    Grounding and search allocate hundreds of thousands of acyclic objects (operators, masks,
    nodes) that reference counting frees; every generation-2 pass of the cyclic collector
    walks all of them, which cost more than the grounding itself on the larger benchmark
    problems (Depots: about 40 % of the grounding CPU time).
    """
    collecting = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if collecting:
            gc.enable()
