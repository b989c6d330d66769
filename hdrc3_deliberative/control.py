"""Compilation of TAL control formulas into initial, incremental and final pruning constraints.

A control rule ``forall t . phi([t], [t+1])`` is compiled to Python closures over bitset states.
Following Algorithm 3 of the chapter, each rule yields

* an *initial* constraint, checked once in the initial state,
* *incremental* constraints per operator schema, instantiated with the arguments of each new
  action occurrence and checked on the transition the action causes, and
* a *final* constraint, checked in the state where the plan ends.

Rules whose antecedent names an explicit change of an atom (``[t] not p and [t+1] p``,
``[t] p and [t+1] not p``, or ``[t] p ... -> [t+1] p``) are *triggered*: they can only be violated
by an action that adds (deletes) a matching atom, so their incremental constraint binds the
rule's variables from that action's effects instead of enumerating all instances.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import (
    ROOT_TYPE,
    Atom,
    BinOp,
    ControlRule,
    ControlSpec,
    FAnd,
    FAtom,
    FCompare,
    FConst,
    FEq,
    FGoal,
    FImplies,
    FNot,
    FOr,
    Formula,
    FQuant,
    Num,
    NumExpr,
    Param,
    Pos,
    RuleKind,
    TimeRef,
)
from hdrc3_deliberative.pruning import (
    CompiledRule,
    ControlProgram,
    Env,
    Eval,
    NumberState,
    Trigger,
)
from hdrc3_deliberative.steps import map_relations
from hdrc3_deliberative.task import Task

Args = tuple[str, ...]
NumEval = Callable[[Env, tuple[float, ...]], float | None]
_COMPARE: dict[str, Callable[[float, float], bool]] = {
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b + 1e-9,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b - 1e-9,
    "=": lambda a, b: abs(a - b) <= 1e-9,
    "!=": lambda a, b: abs(a - b) > 1e-9,
}
_ARITH: dict[str, Callable[[float, float], float]] = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b if b else float("inf"),
}


def _conjuncts(formula: Formula) -> list[Formula]:
    if isinstance(formula, FAnd):
        return [c for arg in formula.args for c in _conjuncts(arg)]
    return [formula]


def _functions(expr: NumExpr) -> set[str]:
    """Names of the functions a numeric expression reads."""
    if isinstance(expr, BinOp):
        return _functions(expr.left) | _functions(expr.right)
    if isinstance(expr, Num):
        return set()
    return {expr.atom.pred}


def _next_literal(formula: Formula) -> tuple[Atom, bool] | None:
    """(atom, positive) of ``atom[t+1]`` or ``not atom[t+1]``; None for anything else."""
    if isinstance(formula, FAtom) and formula.time is TimeRef.NEXT:
        return formula.atom, True
    arg = formula.arg if isinstance(formula, FNot) else None
    if isinstance(arg, FAtom) and arg.time is TimeRef.NEXT:
        return arg.atom, False
    return None


def _find_trigger(
    rule: ControlRule, static: frozenset[str]
) -> tuple[tuple[Param, ...], Trigger, Formula] | None:
    formula = rule.formula
    if not (
        isinstance(formula, FQuant) and formula.universal and isinstance(formula.body, FImplies)
    ):
        return None
    outer = formula.variables
    antecedent = _conjuncts(formula.body.left)
    consequent = formula.body.right
    names = {p.name for p in outer}

    def covered(atom: Atom) -> bool:
        return atom.pred not in static and all(t.name in names for t in atom.args)

    now_pos = {c.atom: c for c in antecedent if isinstance(c, FAtom) and c.time is not TimeRef.NEXT}
    now_neg = {
        c.arg.atom: c
        for c in antecedent
        if isinstance(c, FNot) and isinstance(c.arg, FAtom) and c.arg.time is not TimeRef.NEXT
    }
    # An atom becoming true (false) at t+1 in the antecedent, or one that must not flip
    # in the consequent, is a change the rule watches: its trigger is that change.
    for c in antecedent:
        literal = _next_literal(c)
        if literal is not None:
            atom, positive = literal
            if atom in (now_neg if positive else now_pos) and covered(atom):
                return outer, Trigger(atom.pred, positive, atom), formula.body
    literal = _next_literal(consequent)
    if literal is not None:
        atom, positive = literal
        if atom in (now_pos if positive else now_neg) and covered(atom):
            return outer, Trigger(atom.pred, not positive, atom), formula.body
    return None


class ControlCompiler:
    """Compiles the rules of a ControlSpec against a ground task (validating names)."""

    def __init__(self, task: Task, spec: ControlSpec) -> None:
        task, self._maps = map_relations(task, spec.steps)
        self.task = task
        self.spec = spec
        self._types = {ROOT_TYPE, *task.domain.types}
        self._type_sets = {t: frozenset(objs) for t, objs in task.objects_by_type.items()}
        self._objects = self._type_sets.get(ROOT_TYPE, frozenset())
        self._index: dict[
            tuple[str, str], tuple[list[Args], dict[tuple[int, str], list[Args]]]
        ] = {}
        goal_by_pred: dict[str, list[Args]] = {}
        for pred, args in sorted(task.goal_atoms):
            goal_by_pred.setdefault(pred, []).append(args)
        static_by_pred: dict[str, list[Args]] = {}
        for pred, args in sorted(task.static_facts):
            static_by_pred.setdefault(pred, []).append(args)
        self._universe = {
            "goal": goal_by_pred,
            "static": static_by_pred,
            "fluent": {p: sorted(table) for p, table in task.by_pred.items()},
        }
        self._pos = Pos(spec.source)
        self._true_cache: dict[str, Callable[[int, tuple[int, str] | None], list[Args]]] = {}
        # masks of the fluent atoms each evaluation reads (for ControlProgram's memo)
        self._reads: list[int] = []
        self.numbers = NumberState()

    # --- validation -----------------------------------------------------------------------

    def _fail(self, message: str, pos: Pos | None = None) -> PlanningInputError:
        p = pos or self._pos
        return PlanningInputError(message, p.source, p.line, p.column)

    def _check_atom(self, atom: Atom, bound: frozenset[str]) -> None:
        preds = self.task.domain.predicates
        if atom.pred in self._types and len(atom.args) == 1 and atom.pred not in preds:
            pass
        elif atom.pred not in preds:
            raise self._fail(f"undefined predicate '{atom.pred}' in control formula", atom.pos)
        elif len(preds[atom.pred]) != len(atom.args):
            raise self._fail(
                f"predicate '{atom.pred}' takes {len(preds[atom.pred])} arguments, "
                f"got {len(atom.args)}",
                atom.pos,
            )
        for term in atom.args:
            if term.name not in bound and term.name not in self._objects:
                raise self._fail(f"undefined object or variable '{term.name}'", atom.pos)

    # --- compilation ----------------------------------------------------------------------

    def compile(self) -> ControlProgram:
        """Compile every rule; raises PlanningInputError for undefined names."""
        compiled = []
        for agent_type in self.spec.agent_types:
            if agent_type not in self._types:
                raise self._fail(f"undefined agent type '{agent_type}'")
        known_ops = {op.name for op in self.task.domain.operators}
        for name in self.spec.prefer:
            if name not in known_ops:
                raise self._fail(f"'prefer' names undefined operator '{name}'")
        for rule in self.spec.rules:
            self._pos = rule.pos
            full_eval = self.comp(rule.formula, frozenset())
            trigger = (
                _find_trigger(rule, self.task.static_preds)
                if rule.kind is RuleKind.ALWAYS
                else None
            )
            body: Eval | None = None
            outer: tuple[Param, ...] = ()
            if trigger is not None:
                outer, trig, implication = trigger
                bound_by_trigger = frozenset(t.name for t in trig.atom.args)
                remaining = tuple(p for p in outer if p.name not in bound_by_trigger)
                if remaining:
                    body = self._quantified(remaining, implication, bound_by_trigger, True)
                else:
                    body = self.comp(implication, bound_by_trigger)
                trigger_value: Trigger | None = trig
            else:
                trigger_value = None
            compiled.append(
                CompiledRule(
                    rule.name,
                    rule.kind,
                    (lambda f: lambda s0, s1: f({}, s0, s1))(full_eval),
                    trigger_value,
                    body,
                    outer,
                    frozenset(self._fluent_preds(rule.formula)),
                    tuple((p.name, p.type) for p in outer),
                )
            )
        return ControlProgram(self.task, tuple(compiled), self._reads, self.numbers)

    def _fluent_preds(self, formula: Formula) -> set[str]:
        if isinstance(formula, FAtom):
            return set() if formula.atom.pred in self.task.static_preds else {formula.atom.pred}
        if isinstance(formula, FNot):
            return self._fluent_preds(formula.arg)
        if isinstance(formula, FAnd | FOr):
            return {p for a in formula.args for p in self._fluent_preds(a)}
        if isinstance(formula, FImplies):
            return self._fluent_preds(formula.left) | self._fluent_preds(formula.right)
        if isinstance(formula, FQuant):
            return self._fluent_preds(formula.body)
        if isinstance(formula, FCompare):
            return _functions(formula.left) | _functions(formula.right)
        return set()

    def _args(self, atom: Atom, bound: frozenset[str]) -> Callable[[Env], Args]:
        self._check_atom(atom, bound)
        spec = tuple((t.name in bound, t.name) for t in atom.args)
        if all(not is_var for is_var, _ in spec):
            constant = tuple(n for _, n in spec)
            return lambda env: constant
        if len(spec) == 1:
            only = spec[0][1]
            return lambda env: (env[only],)
        if len(spec) == 2 and spec[0][0] and spec[1][0]:
            a, b = spec[0][1], spec[1][1]
            return lambda env: (env[a], env[b])
        return lambda env: tuple(env[n] if is_var else n for is_var, n in spec)

    def comp(self, formula: Formula, bound: frozenset[str]) -> Eval:
        """Compile a formula into ``eval(env, s_t, s_t+1) -> bool``."""
        if isinstance(formula, FConst):
            value = formula.value
            return lambda env, s0, s1: value
        if isinstance(formula, FAtom):
            return self._atom(formula, bound)
        if isinstance(formula, FGoal):
            args_fn = self._args(formula.atom, bound)
            goals = self.task.goal_atoms
            gpred = formula.atom.pred
            return lambda env, s0, s1: (gpred, args_fn(env)) in goals
        if isinstance(formula, FEq):
            for term in (formula.left, formula.right):
                if term.name not in bound and term.name not in self._objects:
                    raise self._fail(f"undefined object or variable '{term.name}'")
            left = (formula.left.name in bound, formula.left.name)
            right = (formula.right.name in bound, formula.right.name)
            positive = formula.positive

            def eq(env: Env, s0: int, s1: int) -> bool:
                lv = env[left[1]] if left[0] else left[1]
                rv = env[right[1]] if right[0] else right[1]
                return (lv == rv) == positive

            return eq
        if isinstance(formula, FNot):
            inner = self.comp(formula.arg, bound)
            return lambda env, s0, s1: not inner(env, s0, s1)
        if isinstance(formula, FAnd):
            parts = tuple(self.comp(a, bound) for a in formula.args)
            return lambda env, s0, s1: all(p(env, s0, s1) for p in parts)
        if isinstance(formula, FOr):
            parts = tuple(self.comp(a, bound) for a in formula.args)
            return lambda env, s0, s1: any(p(env, s0, s1) for p in parts)
        if isinstance(formula, FImplies):
            left_fn = self.comp(formula.left, bound)
            right_fn = self.comp(formula.right, bound)
            return lambda env, s0, s1: not left_fn(env, s0, s1) or right_fn(env, s0, s1)
        if isinstance(formula, FCompare):
            return self._compare(formula, bound)
        return self._quant(formula, bound)

    def _compare(self, formula: FCompare, bound: frozenset[str]) -> Eval:
        """A numeric comparison read in the numeric state of its time (NumState)."""
        test = _COMPARE.get(formula.op)
        if test is None:
            raise self._fail(f"unknown comparison '{formula.op}'", formula.pos)
        left = self._num(formula.left, bound)
        right = self._num(formula.right, bound)
        numbers = self.numbers
        slot = 1 if formula.time is TimeRef.NEXT else 0

        def compare(env: Env, s0: int, s1: int) -> bool:
            numbers.read = True
            values = numbers.states[slot]
            a, b = left(env, values), right(env, values)
            return a is not None and b is not None and test(a, b)

        return compare

    def _num(self, expr: NumExpr, bound: frozenset[str]) -> NumEval:
        """Compile a numeric expression; None means undefined (the comparison is false)."""
        if isinstance(expr, Num):
            constant = expr.value
            return lambda env, values: constant
        if isinstance(expr, BinOp):
            left, right = self._num(expr.left, bound), self._num(expr.right, bound)
            op = _ARITH[expr.op]

            def arith(env: Env, values: tuple[float, ...]) -> float | None:
                a, b = left(env, values), right(env, values)
                return None if a is None or b is None else op(a, b)

            return arith
        atom = expr.atom
        functions = self.task.domain.functions
        if atom.pred not in functions:
            raise self._fail(f"undefined function '{atom.pred}' in control formula", atom.pos)
        if len(functions[atom.pred]) != len(atom.args):
            raise self._fail(
                f"function '{atom.pred}' takes {len(functions[atom.pred])} arguments, "
                f"got {len(atom.args)}",
                atom.pos,
            )
        for term in atom.args:
            if term.name not in bound and term.name not in self._objects:
                raise self._fail(f"undefined object or variable '{term.name}'", atom.pos)
        spec = tuple((t.name in bound, t.name) for t in atom.args)
        pred = atom.pred
        index = self.task.num_index
        static = self.task.static_values

        def value(env: Env, values: tuple[float, ...]) -> float | None:
            key = (pred, tuple(env[n] if is_var else n for is_var, n in spec))
            i = index.get(key)
            if i is not None:
                return values[i]
            return static.get(key)

        return value

    def _atom(self, formula: FAtom, bound: frozenset[str]) -> Eval:
        atom = formula.atom
        args_fn = self._args(atom, bound)
        pred = atom.pred
        if pred in self._types and pred not in self.task.domain.predicates:
            members = self._type_sets.get(pred, frozenset())
            return lambda env, s0, s1: args_fn(env)[0] in members
        test = self._maps.get(pred)
        if test is not None:
            return lambda env, s0, s1: test(args_fn(env))
        if pred in self.task.static_preds:
            facts = self.task.static_facts
            return lambda env, s0, s1: (pred, args_fn(env)) in facts
        table = self.task.by_pred.get(pred, {})
        reads = self._reads
        if formula.time is TimeRef.NEXT:

            def next_state(env: Env, s0: int, s1: int) -> bool:
                mask = table.get(args_fn(env), 0)
                reads.append(mask)
                return bool(s1 & mask)

            return next_state

        def this_state(env: Env, s0: int, s1: int) -> bool:
            mask = table.get(args_fn(env), 0)
            reads.append(mask)
            return bool(s0 & mask)

        return this_state

    def _quant(self, formula: FQuant, bound: frozenset[str]) -> Eval:
        for var in formula.variables:
            if var.type not in self._types:
                raise self._fail(f"undefined type '{var.type}' of variable '{var.name}'")
        return self._quantified(formula.variables, formula.body, bound, formula.universal)

    def _quantified(
        self,
        variables: tuple[Param, ...],
        body_formula: Formula,
        bound: frozenset[str],
        universal: bool,
    ) -> Eval:
        """Quantifier over ``variables``; instances falsifying a guard atom are skipped.

        The guard is the first positive atom (or goal) of the antecedent (universal) or of
        the body (existential) that mentions a quantified variable: instances where it is
        false cannot change the value, so candidates come from an index of that atom's
        universe (goal atoms, static facts, fluent atoms or type members).
        """
        names = tuple(v.name for v in variables)
        inner_bound = bound | frozenset(names)
        if universal:
            source = body_formula.left if isinstance(body_formula, FImplies) else None
        else:
            source = body_formula
        guard = None
        if source is not None:
            guard = next(
                (
                    c
                    for c in _conjuncts(source)
                    if isinstance(c, FAtom | FGoal)
                    and any(t.name in names for t in c.atom.args)
                    and c.atom.pred not in self._maps
                ),
                None,
            )
        head = variables
        if guard is not None:
            in_guard = {t.name for t in guard.atom.args}
            head = tuple(v for v in variables if v.name in in_guard)
        rest = tuple(v for v in variables if v not in head)
        if rest:
            # the guard binds only some variables: quantify those first and the others
            # inside, each group with its own guard (Q x, y . F == Q x . Q y . F)
            names = tuple(v.name for v in head)
            inner_bound = bound | frozenset(names)
            body = self._quantified(rest, body_formula, inner_bound, universal)
            variables = head
        else:
            body = self.comp(body_formula, inner_bound)
        if guard is not None and len(names) == 1:
            spec_names = [t.name for t in guard.atom.args]
            if spec_names.count(names[0]) == 1:
                return self._single(variables[0], guard, bound, body, universal)
        enum = self._enumerator(variables, guard, inner_bound)
        if universal:
            return lambda env, s0, s1: all(body(env, s0, s1) for _ in enum(env, s0, s1))
        return lambda env, s0, s1: any(body(env, s0, s1) for _ in enum(env, s0, s1))

    def _guard_source(self, guard: FAtom | FGoal) -> tuple[str, dict[Args, int] | None, bool]:
        kind = "goal" if isinstance(guard, FGoal) else "static"
        table: dict[Args, int] | None = None
        if isinstance(guard, FAtom) and guard.atom.pred not in self.task.static_preds:
            kind = "fluent"
            table = self.task.by_pred.get(guard.atom.pred, {})
        if guard.atom.pred in self._types and guard.atom.pred not in self.task.domain.predicates:
            kind, table = "type", None
        return kind, table, isinstance(guard, FAtom) and guard.time is TimeRef.NEXT

    def _single(
        self, var: Param, guard: FAtom | FGoal, bound: frozenset[str], body: Eval, universal: bool
    ) -> Eval:
        """Fast path: one quantified variable occurring once in the guard atom."""
        kind, table, guard_next = self._guard_source(guard)
        universe, index = self._universe_index(kind, guard.atom.pred)
        name = var.name
        members = self._type_sets.get(var.type, frozenset())
        position = next(i for i, t in enumerate(guard.atom.args) if t.name == name)
        consts = [
            (i, t.name)
            for i, t in enumerate(guard.atom.args)
            if t.name != name and t.name not in bound
        ]
        outers = [
            (i, t.name) for i, t in enumerate(guard.atom.args) if t.name != name and t.name in bound
        ]
        missing = object()

        true_atoms = self._true_atoms(guard.atom.pred) if table is not None else None

        def evaluate(env: Env, s0: int, s1: int) -> bool:
            fixed = consts + [(i, env[n]) for i, n in outers]
            state = s1 if guard_next else s0
            if true_atoms is not None:
                candidates = true_atoms(state, fixed[0] if fixed else None)
            else:
                candidates = index.get(fixed[0], []) if fixed else universe
            others = fixed[1:]
            saved = env.get(name, missing)
            result = universal
            for args in candidates:
                if others and any(args[i] != v for i, v in others):
                    continue
                value = args[position]
                if value not in members:
                    continue
                env[name] = value
                if body(env, s0, s1) != universal:
                    result = not universal
                    break
            if saved is missing:
                env.pop(name, None)
            else:
                env[name] = saved  # type: ignore[assignment]
            return result

        return evaluate

    def _enumerator(
        self,
        variables: tuple[Param, ...],
        guard: FAtom | FGoal | None,
        inner_bound: frozenset[str],
    ) -> Callable[[Env, int, int], Iterator[None]]:
        type_of = {v.name: v.type for v in variables}
        # a fluent guard also filters candidates by their truth in the state it is read in
        fluent_table: dict[Args, int] | None = None
        guard_next = False
        type_sets = self._type_sets
        objects = self.task.objects_by_type
        universe: list[Args] = []
        index: dict[tuple[int, str], list[Args]] = {}
        spec: tuple[tuple[bool, str], ...] = ()  # (is quantified variable, name)
        if guard is not None:
            kind, fluent_table, guard_next = self._guard_source(guard)
            universe, index = self._universe_index(kind, guard.atom.pred)
            spec = tuple((t.name in type_of, t.name) for t in guard.atom.args)
        bound_names = inner_bound - frozenset(type_of)
        true_atoms = (
            self._true_atoms(guard.atom.pred)
            if guard is not None and fluent_table is not None
            else None
        )
        all_names = tuple(type_of)

        def by_type(env: Env, todo: tuple[str, ...]) -> Iterator[None]:
            if not todo:
                yield None
                return
            name, tail = todo[0], todo[1:]
            for obj in objects.get(type_of[name], ()):
                env[name] = obj
                yield from by_type(env, tail)

        def enumerate_all(env: Env, s0: int, s1: int) -> Iterator[None]:
            saved = {n: env[n] for n in all_names if n in env}
            try:
                if guard is None:
                    yield from by_type(env, all_names)
                    return
                fixed: list[tuple[int, str]] = []
                free: list[tuple[int, str]] = []
                for i, (is_var, n) in enumerate(spec):
                    if not is_var:
                        fixed.append((i, env[n] if n in bound_names else n))
                    else:
                        free.append((i, n))
                guard_vars = {n for _, n in free}
                rest = tuple(n for n in all_names if n not in guard_vars)
                state = s1 if guard_next else s0
                if true_atoms is not None:
                    candidates = true_atoms(state, fixed[0] if fixed else None)
                else:
                    candidates = index.get(fixed[0], []) if fixed else universe
                for args in candidates:
                    if any(args[i] != value for i, value in fixed):
                        continue
                    assigned: dict[str, str] = {}
                    ok = True
                    for i, n in free:
                        value = args[i]
                        if assigned.setdefault(n, value) != value or value not in type_sets.get(
                            type_of[n], ()
                        ):
                            ok = False
                            break
                    if ok:
                        env.update(assigned)
                        yield from by_type(env, rest)
            finally:
                for n in all_names:
                    env.pop(n, None)
                env.update(saved)

        return enumerate_all

    def _true_atoms(self, pred: str) -> Callable[[int, tuple[int, str] | None], list[Args]]:
        """Arguments of the ``pred`` atoms true in a state, optionally with one fixed argument.

        Masks per (position, value) select the true atoms with a single AND, so the cost
        grows with the number of true atoms rather than with the atom universe.
        """
        if pred not in self._true_cache:
            table = self.task.by_pred.get(pred, {})
            masks: dict[tuple[int, str], int] = {}
            everything = 0
            for args, mask in table.items():
                everything |= mask
                for i, value in enumerate(args):
                    masks[(i, value)] = masks.get((i, value), 0) | mask
            atoms = self.task.atoms
            reads = self._reads

            def true_atoms(state: int, key: tuple[int, str] | None) -> list[Args]:
                selected = everything if key is None else masks.get(key, 0)
                reads.append(selected)
                hits = state & selected
                out = []
                while hits:
                    low = hits & -hits
                    out.append(atoms[low.bit_length() - 1][1])
                    hits ^= low
                return out

            self._true_cache[pred] = true_atoms
        return self._true_cache[pred]

    def _universe_index(
        self, kind: str, pred: str
    ) -> tuple[list[Args], dict[tuple[int, str], list[Args]]]:
        key = (kind, pred)
        if key not in self._index:
            universe: list[Args]
            if kind == "type":
                universe = [(o,) for o in self.task.objects_by_type.get(pred, ())]
            else:
                universe = self._universe[kind].get(pred, [])
            index: dict[tuple[int, str], list[Args]] = {}
            for args in universe:
                for i, value in enumerate(args):
                    index.setdefault((i, value), []).append(args)
            self._index[key] = (universe, index)
        return self._index[key]
