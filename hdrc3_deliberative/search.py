"""Concurrent TALplanner search (Algorithm 3, Definition 9.1 of the chapter).

A search node is ``<C, S, tau0, tmax, p>``: queued constraints, (global) visited states, the
latest invocation time, the latest end time and the plan. Successors add one occurrence
``[rho, rho'] o(c)`` with ``tau0 <= rho <= tmax`` (Def. 9.1 (3), (4)); ``rho`` is the earliest
such time at which ``o`` does not interfere with an action still running (Def. 9.1 (1)), plus,
in domains with prevail conditions, the later change points up to ``tmax``:

* an occurrence *occludes* the features it writes over ``[rho, rho')``; no other occurrence may
  read or write them while it runs, and every action of an agent writes that agent's token, so
  an agent performs one action at a time;
* hence the features an action reads are stable from ``rho`` on, its preconditions are
  evaluated in the final state of the current plan, and sorting the plan by start time gives a
  valid sequential plan (which is what the PDDL validator checks).

Incremental control constraints are evaluated on the transition each new occurrence causes in
this sequential refinement; prevail conditions are queued and decided once the timeline up to
the end of their interval is fixed (``tau0 >= rho'``) or, for the solution test, under complete
knowledge. Search is depth first with lazy successor evaluation: a successor is built and its
queued constraints are checked only when it is popped (lines 7-11).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

from hdrc3_deliberative.model import EffectTime
from hdrc3_deliberative.pruning import ControlProgram
from hdrc3_deliberative.result import (
    PROGRESS_PERIOD_S,
    Occurrence,
    PlanningPhase,
    PlanningProgress,
    PlanResult,
    PlanStatus,
    ProgressHook,
    Statistics,
)
from hdrc3_deliberative.task import GroundOp, Task


@dataclass(frozen=True)
class SearchConfig:
    """Search options.

    Attributes:
        timeout: Wall-clock budget of the search in seconds.
        sequential: Start every action when the previous one has ended.
        cycle_check: Prune nodes whose final state is no better than a visited one.
        prefer: Operator names in preferred order for successor ordering (ties).

    """

    timeout: float = 10.0
    sequential: bool = False
    cycle_check: bool = True
    prefer: tuple[str, ...] = ()


@dataclass(frozen=True)
class _Running:
    end: float
    reads: int
    writes: int


@dataclass(frozen=True)
class _Prevail:
    op: GroundOp
    start: float
    end: float


class _Node:
    __slots__ = (
        "bits",
        "depth",
        "nums",
        "op",
        "parent",
        "queue",
        "run_rw",
        "run_writes",
        "running",
        "start",
        "tau0",
        "tmax",
    )

    def __init__(
        self,
        bits: int,
        nums: tuple[float, ...],
        tau0: float,
        tmax: float,
        running: tuple[_Running, ...],
        queue: tuple[_Prevail, ...],
        parent: _Node | None,
        op: GroundOp | None,
        start: float,
        depth: int,
    ) -> None:
        self.bits = bits
        self.nums = nums
        self.tau0 = tau0
        self.tmax = tmax
        self.running = running
        # union masks of the running actions: the common no-conflict case needs no loop
        self.run_writes = 0
        self.run_rw = 0
        for run in running:
            if run.end > tau0:
                self.run_writes |= run.writes
                self.run_rw |= run.reads | run.writes
        self.queue = queue
        self.parent = parent
        self.op = op
        self.start = start
        self.depth = depth


def _apply_nums(
    op: GroundOp, nums: tuple[float, ...], when: EffectTime | None = None
) -> tuple[float, ...]:
    if not op.num_effects:
        return nums
    values = list(nums)
    for eff in op.num_effects:
        if when is not None and eff.time is not when:
            continue
        amount = eff.value(nums)
        if eff.op == ":=":
            values[eff.index] = amount
        elif eff.op == "+=":
            values[eff.index] += amount
        else:
            values[eff.index] -= amount
    return tuple(values)


class TalPlanner:
    """Depth-first concurrent TALplanner over a ground task and compiled control rules."""

    def __init__(
        self,
        task: Task,
        control: ControlProgram | None,
        config: SearchConfig,
        clock: Callable[[], float] = time.perf_counter,
        progress: ProgressHook | None = None,
        started: float | None = None,
    ) -> None:
        """Index the operators by their rarest precondition.

        ``progress`` hears the effort about every PROGRESS_PERIOD_S of the search, with the time
        elapsed since ``started`` on ``clock`` (None: since :meth:`solve` began).
        """
        self.task = task
        self.control = control
        self.config = config
        self._clock = clock
        self._progress = progress
        self._started = started
        self._rank = {name: i for i, name in enumerate(config.prefer)}
        self._index: dict[int, list[GroundOp]] = {}
        self._unindexed: list[GroundOp] = []
        counts: dict[int, int] = {}
        pre_bits = [_bits(op.pre_pos) for op in task.ops]
        for bits in pre_bits:
            for bit in bits:
                counts[bit] = counts.get(bit, 0) + 1
        for op, bits in zip(task.ops, pre_bits, strict=True):
            if not bits:
                self._unindexed.append(op)
                continue
            rarest = min(bits, key=lambda b: (counts[b], b))
            self._index.setdefault(rarest, []).append(op)
        self._index_mask = sum(1 << b for b in self._index)
        self._op_rank = [self._rank.get(op.name, len(self._rank)) for op in task.ops]
        self._has_prevail = any(
            op.prevail_pos or op.prevail_neg or op.prevail_num for op in task.ops
        )
        res = set(task.resource_indices)
        self._res = tuple(sorted(res))
        ignored = res | set(task.inert_nums)  # metric-only features cannot matter later
        self._plain = tuple(i for i in range(len(task.init_nums)) if i not in ignored)

    # --- successors (Definition 9.1) ------------------------------------------------------

    def _applicable(self, node: _Node) -> list[GroundOp]:
        bits, nums = node.bits, node.nums
        result = []
        candidates = bits & self._index_mask
        ops_lists = [self._unindexed]
        while candidates:
            low = candidates & -candidates
            ops_lists.append(self._index[low.bit_length() - 1])
            candidates ^= low
        for ops in ops_lists:
            for op in ops:
                if bits & op.pre_pos != op.pre_pos or bits & op.pre_neg:
                    continue
                if op.num_pre and not all(test(nums) for test in op.num_pre):
                    continue
                result.append(op)
        return result

    def _start_time(self, node: _Node, op: GroundOp) -> float:
        if self.config.sequential:
            return node.tmax
        start = node.tau0
        if not (op.writes & node.run_rw or op.reads & node.run_writes):
            return start
        for run in node.running:
            if run.end > start and (op.writes & (run.reads | run.writes) or op.reads & run.writes):
                start = run.end
        return start

    def _start_times(self, node: _Node, op: GroundOp) -> list[float]:
        """Earliest non-interfering start; with prevail conditions also later change points.

        Delaying an action only matters for prevail conditions (preconditions are read in the
        final state and effects do not depend on time), so the later candidates of Def. 9.1
        (4), the end times of running actions up to ``tmax``, are added only then.
        """
        earliest = self._start_time(node, op)
        if not self._has_prevail or self.config.sequential:
            return [earliest]
        later = sorted({r.end for r in node.running if r.end > earliest})
        return [earliest, *later]

    def _child(self, parent: _Node, op: GroundOp, start: float) -> _Node:
        end = start + op.duration
        running = tuple(
            sorted(
                (*(r for r in parent.running if r.end > start), _Running(end, op.reads, op.writes)),
                key=lambda r: r.end,
            )
        )
        queue = parent.queue
        if op.prevail_pos or op.prevail_neg or op.prevail_num:
            queue = (*queue, _Prevail(op, start, end))
        return _Node(
            (parent.bits & ~op.delete) | op.add,
            _apply_nums(op, parent.nums),
            start,
            max(parent.tmax, end),
            running,
            queue,
            parent,
            op,
            start,
            parent.depth + 1,
        )

    # --- queued constraints (lines 9-11) --------------------------------------------------

    def _timeline(self, node: _Node) -> list[tuple[float, int, tuple[float, ...]]]:
        """States at every change point of the plan's timeline, ascending in time."""
        occurrences = []
        cursor: _Node | None = node
        while cursor is not None and cursor.op is not None:
            occurrences.append((cursor.start, cursor.depth, cursor.op))
            cursor = cursor.parent
        events = []
        for start, depth, op in occurrences:
            events.append((start + op.duration, 0, depth, op, EffectTime.END))
            if (
                op.start_add
                or op.start_delete
                or any(e.time is EffectTime.START for e in op.num_effects)
            ):
                events.append((start, 1, depth, op, EffectTime.START))
        events.sort(key=lambda e: (e[0], e[1], e[2]))
        bits, nums = self.task.init_bits, self.task.init_nums
        states = [(0.0, bits, nums)]
        for when, _, _, op, kind in events:
            if kind is EffectTime.START:
                bits = (bits & ~op.start_delete) | op.start_add
            else:
                end_delete = op.delete & ~op.start_delete
                end_add = op.add & ~op.start_add
                bits = (bits & ~end_delete) | end_add
            nums = _apply_nums(op, nums, kind)
            if states[-1][0] == when:
                states[-1] = (when, bits, nums)
            else:
                states.append((when, bits, nums))
        return states

    @staticmethod
    def _prevail_holds(p: _Prevail, bits: int, nums: tuple[float, ...]) -> bool:
        op = p.op
        return (
            bits & op.prevail_pos == op.prevail_pos
            and not bits & op.prevail_neg
            and all(test(nums) for test in op.prevail_num)
        )

    def _check_queue(self, node: _Node, complete: bool) -> tuple[bool, tuple[_Prevail, ...]]:
        """(violated?, remaining queue). ``complete`` assumes no further actions (line 12)."""
        if not node.queue:
            return False, ()
        states = self._timeline(node)
        known = float("inf") if complete else node.tau0
        remaining = []
        for p in node.queue:
            for i, (when, bits, nums) in enumerate(states):
                # state i holds on [when, next change); it overlaps [p.start, p.end)
                following = states[i + 1][0] if i + 1 < len(states) else float("inf")
                if when >= p.end or following <= p.start or when >= known:
                    continue
                if not self._prevail_holds(p, bits, nums):
                    return True, ()
            if p.end > known:
                remaining.append(p)
        return False, tuple(remaining)

    # --- the search loop ------------------------------------------------------------------

    @staticmethod
    def _pending_key(node: _Node) -> tuple[object, ...]:
        """Undecided prevail conditions and what can still decide them, relative to tau0.

        Two nodes with the same state but differently timed undecided conditions (or running
        actions that will change the state during them) have different futures, so the cycle
        check must tell them apart; without pending conditions the state alone is the key.
        """
        if not node.queue:
            return ()
        tau0 = node.tau0
        pending = sorted((p.op.index, max(p.start - tau0, 0.0), p.end - tau0) for p in node.queue)
        running = sorted((r.end - tau0, r.writes) for r in node.running if r.end > tau0)
        return (tuple(pending), tuple(running))

    def _goal(self, node: _Node) -> bool:
        task = self.task
        return (
            node.bits & task.goal_pos == task.goal_pos
            and not node.bits & task.goal_neg
            and all(test(node.nums) for test in task.goal_num)
        )

    def _successors(self, node: _Node) -> list[tuple[_Node, GroundOp, float]]:
        """Children as stack entries, best last: by start, ``prefer`` rank, goal gain, index."""
        goal = self.task.goal_pos
        bits = node.bits
        tau0, run_rw, run_writes = node.tau0, node.run_rw, node.run_writes
        rank = self._op_rank
        keyed = []
        for op in self._applicable(node):
            gain = 0
            if op.add & goal or op.delete & goal:
                gain = (op.add & goal & ~bits).bit_count() - (op.delete & goal & bits).bit_count()
            if (
                self._has_prevail
                or self.config.sequential
                or op.writes & run_rw
                or op.reads & run_writes
            ):
                for start in self._start_times(node, op):
                    keyed.append((start, rank[op.index], -gain, op.index, op))
            else:  # common case: no conflict with a running action, start at tau0
                keyed.append((tau0, rank[op.index], -gain, op.index, op))
        keyed.sort(key=lambda k: k[:4], reverse=True)
        return [(node, k[4], k[0]) for k in keyed]

    def solve(self) -> PlanResult:
        """Run Algorithm 3 until a plan is found, the space is exhausted, or time runs out."""
        t0 = self._clock()
        deadline = t0 + self.config.timeout
        task = self.task
        expanded = generated = pruned_control = pruned_cycle = 0

        def stats() -> Statistics:
            return Statistics(
                nodes_expanded=expanded,
                nodes_generated=generated,
                pruned_by_control=pruned_control,
                pruned_by_cycle=pruned_cycle,
                ground_operators=len(task.ops),
                ground_atoms=len(task.atoms),
                search_seconds=self._clock() - t0,
            )

        root = _Node(task.init_bits, task.init_nums, 0.0, 0.0, (), (), None, None, 0.0, 0)
        if self.control is not None:
            violated = self.control.initial_violation(root.bits, root.nums)
            if violated is not None:
                return PlanResult(
                    PlanStatus.UNSOLVABLE_PROVEN,
                    (),
                    stats(),
                    f"initial state violates control rule '{violated}'",
                )
        visited: dict[tuple[object, ...], list[tuple[float, ...]]] = {}
        stack: list[tuple[_Node, GroundOp | None, float]] = [(root, None, 0.0)]
        iterations = 0
        started = t0 if self._started is None else self._started
        reported = -math.inf
        while stack:
            iterations += 1
            if iterations & 63 == 0:
                now = self._clock()
                if now > deadline:
                    reason = f"no plan within {self.config.timeout:g} s"
                    return PlanResult(PlanStatus.TIMEOUT, (), stats(), reason)
                if self._progress is not None and now - reported >= PROGRESS_PERIOD_S:
                    reported = now
                    searching = PlanningPhase.SEARCHING
                    self._progress(PlanningProgress(searching, stats(), now - started))
            parent, op, start = stack.pop()
            if op is None:
                node = parent
            else:
                generated += 1
                # incremental control constraints first: most popped successors fail them
                after = (parent.bits & ~op.delete) | op.add
                if (
                    self.control is not None
                    and self.control.step_violation(
                        op, parent.bits, after, parent.nums, _apply_nums(op, parent.nums)
                    )
                    is not None
                ):
                    pruned_control += 1
                    continue
                node = self._child(parent, op, start)
            violated_queue, remaining = self._check_queue(node, complete=False)
            if violated_queue:
                pruned_control += 1
                continue
            node.queue = remaining
            if self.config.cycle_check:
                plain = tuple(node.nums[i] for i in self._plain)
                key = (node.bits, plain, self._pending_key(node))
                res = tuple(node.nums[i] for i in self._res)
                seen = visited.setdefault(key, [])
                if any(all(a >= b for a, b in zip(old, res, strict=True)) for old in seen):
                    pruned_cycle += 1
                    continue
                seen.append(res)
            if self._goal(node):
                final_ok = (
                    self.control is None
                    or self.control.final_violation(node.bits, node.nums) is None
                )
                if final_ok and not self._check_queue(node, complete=True)[0]:
                    return PlanResult(PlanStatus.SOLVED, self._extract(node), stats())
            expanded += 1
            stack.extend(self._successors(node))
        reason = "search space exhausted" + (
            " under the control rules" if self.control is not None and self.control.rules else ""
        )
        return PlanResult(PlanStatus.UNSOLVABLE_PROVEN, (), stats(), reason)

    @staticmethod
    def _extract(node: _Node) -> tuple[Occurrence, ...]:
        """The plan in insertion order (by Def. 9.1 (3) also ordered by start time)."""
        items = []
        cursor: _Node | None = node
        while cursor is not None and cursor.op is not None:
            op = cursor.op
            items.append(
                Occurrence(cursor.start, cursor.start + op.duration, op.name, op.args, op.agent)
            )
            cursor = cursor.parent
        return tuple(reversed(items))


def _bits(mask: int) -> list[int]:
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return out
