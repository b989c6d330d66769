"""Concurrent TALplanner search (Algorithm 3, Definition 9.1 of the chapter).

A search node is ``<C, S, tau0, tmax, p>``: queued constraints, visited states, the latest
invocation time, the latest end time and the plan. Successors add one occurrence
``[rho, rho'] o(c)`` at every admissible start ``tau0 <= rho <= tmax`` (Def. 9.1 (3), (4)) at
which ``o`` does not interfere with an action still running (Def. 9.1 (1)): the earliest
such time and the later ends of running actions (the timeline changes only there):

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

Without prevail conditions a later start cannot help: states, control verdicts and the goal
do not depend on times, and whatever follows a later start can follow the earliest one. So
there the later starts of a node are pushed as one marker below its earliest-start children
and generated only when all of those have failed. With prevail conditions all starts are
children at once, ordered by start.

The cycle check (line 14) compares a node with the states of the current path, where a state
with at least as much of every ``resource`` is better-or-equal (``CycleCheck.PATH``). The
default ``CycleCheck.PATH_CLOSED`` also prunes exact duplicates of any node visited before:
a node's extensions depend only on its key (final state, and with prevail conditions the
timeline from ``tau0`` on, pending conditions and running actions), and depth first a
visited non-ancestor's subtree is exhausted before a duplicate is popped, so no plan is lost;
without it a failing subtree is searched again under every schedule and order of its
actions (measured: pure ``PATH`` times out where ``PATH_CLOSED`` proves unsolvability in
milliseconds). ``CycleCheck.GLOBAL`` is the better-or-equal test against every visited node,
which loses plans when less of a resource can be needed (a goal or precondition bounding it
from above); it is opt-in.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

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


class CycleCheck(Enum):
    """Which visited states prune a node (Algorithm 3, line 14)."""

    PATH = "path"  # better-or-equal against the states on the current path only
    PATH_CLOSED = "path-closed"  # PATH, plus exact duplicates of any visited node
    GLOBAL = "global"  # better-or-equal against every visited node (may lose plans)
    OFF = "off"


@dataclass(frozen=True)
class SearchConfig:
    """Search options.

    Attributes:
        timeout: Wall-clock budget of the search in seconds.
        sequential: Start every action when the previous one has ended.
        cycle_check: Which visited states prune a node.
        prefer: Operator names in preferred order for successor ordering (ties).

    """

    timeout: float = 10.0
    sequential: bool = False
    cycle_check: CycleCheck = CycleCheck.PATH_CLOSED
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


_Key = tuple[object, ...]
_Resources = tuple[float, ...]


def _dominated(seen: list[_Resources], res: _Resources) -> bool:
    """Some visited state has at least as much of every resource (better-or-equal)."""
    return any(all(a >= b for a, b in zip(old, res, strict=True)) for old in seen)


class _Visited:
    """The visited states ``S`` of Algorithm 3 (line 14), as ``CycleCheck`` selects them.

    Depth first, the current path is the admitted node of each depth up to the parent of the
    node being checked, so it is a stack truncated to that node's depth.
    """

    def __init__(self, mode: CycleCheck) -> None:
        self.mode = mode
        self._path: list[tuple[_Key, _Resources]] = []
        self._on_path: dict[_Key, list[_Resources]] = {}
        self._closed: set[tuple[_Key, _Resources]] = set()
        self._seen: dict[_Key, list[_Resources]] = {}

    def admit(self, depth: int, key: _Key, res: _Resources) -> bool:
        """Record the node at ``depth`` and return True, or return False if it is pruned."""
        if self.mode is CycleCheck.GLOBAL:
            seen = self._seen.setdefault(key, [])
            if _dominated(seen, res):
                return False
            seen.append(res)
            return True
        path, on_path = self._path, self._on_path
        while len(path) > depth:  # leave the branches explored since
            old_key, old_res = path.pop()
            kept = on_path[old_key]
            kept.remove(old_res)
            if not kept:
                del on_path[old_key]
        if _dominated(on_path.get(key, []), res):
            return False
        if self.mode is CycleCheck.PATH_CLOSED:
            if (key, res) in self._closed:
                return False
            self._closed.add((key, res))
        path.append((key, res))
        on_path.setdefault(key, []).append(res)
        return True


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


_Entry = tuple[_Node, GroundOp | None, float]  # (parent, operator, start); None: later starts


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
        pre_bits = [op.pre_bits or _bits(op.pre_pos) for op in task.ops]
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
        # what prevail conditions read: the only part of the timeline that matters (_future_key)
        self._prevail_bits = 0
        for op in task.ops:
            self._prevail_bits |= op.prevail_pos | op.prevail_neg
        prevail_num = any(op.prevail_num for op in task.ops)
        self._prevail_nums = tuple(sorted(set(self._plain) | res)) if prevail_num else ()

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
        """The earliest start at which ``op`` does not interfere with a running action."""
        start = node.tau0
        if not (op.writes & node.run_rw or op.reads & node.run_writes):
            return start
        for run in node.running:
            if run.end > start and (op.writes & (run.reads | run.writes) or op.reads & run.writes):
                start = run.end
        return start

    @staticmethod
    def _later_starts(node: _Node, earliest: float) -> list[float]:
        """The admissible starts after ``earliest`` (Def. 9.1 (3), (4)).

        Any ``rho`` with ``tau0 <= rho <= tmax`` is admissible once no running action
        interferes; the timeline changes only where a running action ends (all end by
        ``tmax``), so those ends are the distinct later candidates.
        """
        return sorted({r.end for r in node.running if r.end > earliest})

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

    def _future_key(self, node: _Node) -> tuple[object, ...]:
        """What besides the final state decides the node's future, relative to ``tau0``.

        Without prevail conditions nothing does: preconditions are read in the final state,
        control formulas on the sequential refinement, and the actions that can follow one
        schedule can follow any other (later if need be), so two nodes with one final state
        have the same extensions up to timing. With prevail conditions, new and pending
        conditions are checked on the timeline from ``tau0`` on (only the features some prevail
        condition reads matter) and running actions delay new ones, so those belong to the key
        (which makes ``CycleCheck.PATH_CLOSED`` exact).
        """
        if not self._has_prevail:
            return ()
        tau0 = node.tau0
        mask, kept = self._prevail_bits, self._prevail_nums
        states = self._timeline(node)
        first = max(i for i, state in enumerate(states) if state[0] <= tau0)
        timeline = tuple(
            (max(when - tau0, 0.0), bits & mask, tuple(nums[i] for i in kept))
            for when, bits, nums in states[first:]
        )
        pending = sorted((p.op.index, max(p.start - tau0, 0.0), p.end - tau0) for p in node.queue)
        running = sorted((r.end - tau0, r.reads, r.writes) for r in node.running if r.end > tau0)
        return (timeline, tuple(pending), tuple(running))

    def _goal(self, node: _Node) -> bool:
        task = self.task
        return (
            node.bits & task.goal_pos == task.goal_pos
            and not node.bits & task.goal_neg
            and all(test(node.nums) for test in task.goal_num)
        )

    def _solution(self, node: _Node) -> bool:
        """Goal, final control and queued constraints under complete knowledge (line 15)."""
        return (
            self._goal(node)
            and (self.control is None or self.control.final_violation(node.bits, node.nums) is None)
            and not self._check_queue(node, complete=True)[0]
        )

    def _successors(self, node: _Node, later: bool) -> list[_Entry]:
        """Children as stack entries, best last: by start, ``prefer`` rank, goal gain, index.

        With prevail conditions every admissible start is a child at once. Without them a
        later start cannot help (see :meth:`_future_key`): ``later=False`` gives each
        operator at its earliest start, below them (popped after all of them) one marker
        entry that stands for the later starts, and ``later=True`` (the marker popped) gives
        those.
        """
        goal = self.task.goal_pos
        bits = node.bits
        tau0, run_rw, run_writes = node.tau0, node.run_rw, node.run_writes
        sequential = self.config.sequential
        rank = self._op_rank
        keyed: list[tuple[float, int, int, int, GroundOp]] = []
        for op in self._applicable(node):
            gain = 0
            if op.add & goal or op.delete & goal:
                gain = (op.add & goal & ~bits).bit_count() - (op.delete & goal & bits).bit_count()
            if sequential:
                start = node.tmax
            elif op.writes & run_rw or op.reads & run_writes:
                start = self._start_time(node, op)
            else:  # common case: no conflict with a running action, start at tau0
                start = tau0
            if later:
                starts = self._later_starts(node, start)
            elif self._has_prevail and not sequential:
                starts = [start, *self._later_starts(node, start)]
            else:
                starts = [start]
            keyed.extend((s, rank[op.index], -gain, op.index, op) for s in starts)
        keyed.sort(key=lambda k: k[:4], reverse=True)
        entries: list[_Entry] = [(node, k[4], k[0]) for k in keyed]
        if not (later or sequential or self._has_prevail) and node.running:
            entries.insert(0, (node, None, tau0))
        return entries

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
        visited = _Visited(self.config.cycle_check)
        plain, res_indices = self._plain, self._res
        root_key = (root.bits, tuple(root.nums[i] for i in plain), self._future_key(root))
        visited.admit(0, root_key, tuple(root.nums[i] for i in res_indices))
        if self._solution(root):
            return PlanResult(PlanStatus.SOLVED, (), stats())
        expanded += 1
        stack = self._successors(root, later=False)
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
            if op is None:  # every earliest start of parent failed: its later starts
                stack.extend(self._successors(parent, later=True))
                continue
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
            if visited.mode is not CycleCheck.OFF:
                key = (node.bits, tuple(node.nums[i] for i in plain), self._future_key(node))
                if not visited.admit(node.depth, key, tuple(node.nums[i] for i in res_indices)):
                    pruned_cycle += 1
                    continue
            if self._solution(node):
                return PlanResult(PlanStatus.SOLVED, self._extract(node), stats())
            expanded += 1
            stack.extend(self._successors(node, later=False))
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
