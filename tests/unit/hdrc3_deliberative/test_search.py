from __future__ import annotations

import itertools
import time

import pytest

from hdrc3_deliberative.control import ControlCompiler
from hdrc3_deliberative.generators import (
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    LogisticsSize,
    logistics_problem,
)
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import (
    Occurrence,
    PlanningPhase,
    PlanningProgress,
    PlanResult,
    PlanStatus,
)
from hdrc3_deliberative.search import CycleCheck, SearchConfig, TalPlanner
from hdrc3_deliberative.task import Task
from tests.unit.hdrc3_deliberative.fuel_domain import FUEL_DOMAIN, FUEL_PROBLEM


@pytest.fixture(scope="module")
def planner() -> TaskPlanner:
    return TaskPlanner()


def _task(planner: TaskPlanner, request: PlanRequest) -> Task:
    d, p, _ = planner.read(request)
    return planner.ground(d, p)


def _replay(task: Task, plan: tuple[Occurrence, ...]) -> int:
    """Independent check: apply the plan in start order, checking every precondition."""
    ops = {o.label: o for o in task.ops}
    bits, nums = task.init_bits, task.init_nums
    for occ in plan:
        op = ops[occ.label]
        assert bits & op.pre_pos == op.pre_pos and not bits & op.pre_neg, occ.label
        assert all(test(nums) for test in op.num_pre), occ.label
        assert occ.duration == pytest.approx(op.duration)
        bits = (bits & ~op.delete) | op.add
        values = list(nums)
        for eff in op.num_effects:
            delta = eff.value(nums)
            values[eff.index] = (
                delta
                if eff.op == ":="
                else values[eff.index] + (delta if eff.op == "+=" else -delta)
            )
        nums = tuple(values)
    return bits


def _check_definition_9_1(task: Task, result: PlanResult) -> None:
    plan = result.plan
    assert plan[0].start == 0.0  # (2)
    for i, occ in enumerate(plan[1:], start=1):
        assert occ.start >= plan[i - 1].start  # (3) in insertion order
        assert occ.start <= max(o.end for o in plan[:i])  # (4) no gap
    ops = {o.label: o for o in task.ops}
    for a, b in itertools.combinations(plan, 2):  # (1) overlapping occurrences do not interfere
        if a.start < b.end and b.start < a.end:
            oa, ob = ops[a.label], ops[b.label]
            assert not (oa.writes & (ob.reads | ob.writes)) and not (ob.writes & oa.reads)
            assert oa.agent is None or oa.agent != ob.agent  # TAL agents act one at a time
    final = _replay(task, plan)
    assert final & task.goal_pos == task.goal_pos


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_logistics_concurrent_plans_follow_definition_9_1(planner: TaskPlanner, seed: int) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(),
        logistics_problem(LogisticsSize(8, 3, 2), seed),
        LOGISTICS_CONTROL.read_text(),
    )
    result = planner.plan(request, timeout=10)
    assert result.status is PlanStatus.SOLVED
    _check_definition_9_1(_task(planner, request), result)
    assert result.makespan < len(result.plan)  # real concurrency with unit durations
    assert {o.agent for o in result.plan} <= {f"tru{i}" for i in range(1, 4)} | {"apn1", "apn2"}


def test_uav_scenario_concurrent_and_sequential(planner: TaskPlanner) -> None:
    request = PlanRequest(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text(), UAV_CONTROL.read_text())
    task = _task(planner, request)
    concurrent = planner.plan(request, timeout=10)
    sequential = planner.plan(request, timeout=10, sequential=True)
    assert concurrent.solved and sequential.solved
    _check_definition_9_1(task, concurrent)
    _check_definition_9_1(task, sequential)
    for prev, nxt in itertools.pairwise(sequential.plan):
        assert nxt.start == pytest.approx(prev.end)
    assert concurrent.makespan < 0.7 * sequential.makespan
    assert {o.agent for o in concurrent.plan} == {"heli1", "heli2"}


def test_search_is_deterministic(planner: TaskPlanner) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(),
        logistics_problem(LogisticsSize(6, 3, 1), 9),
        LOGISTICS_CONTROL.read_text(),
    )
    first = planner.plan(request, timeout=10)
    second = planner.plan(request, timeout=10)
    assert first.plan == second.plan and first.stats.nodes_expanded == second.stats.nodes_expanded


PREVAIL_DOMAIN = """domain lamp
type person, janitor
predicate lamp-on()
predicate done(p: person)
operator read(p: person)
  agent p
  duration 10
  prevail lamp-on()
  effect [t'] done(p)
end
operator switch-off(j: janitor)
  agent j
  duration 2
  pre lamp-on()
  effect [t'] not lamp-on()
end
"""
PREVAIL_PROBLEM = (
    "problem p for lamp\nobject x: person\nobject j: janitor\ninit lamp-on()\n"
    "goal done(x) and not lamp-on()\n"
)


@pytest.mark.parametrize("with_prevail", [True, False])
def test_prevail_condition_is_kept_over_the_whole_interval(
    planner: TaskPlanner, with_prevail: bool
) -> None:
    domain = PREVAIL_DOMAIN if with_prevail else PREVAIL_DOMAIN.replace("  prevail lamp-on()\n", "")
    result = planner.plan(PlanRequest(domain, PREVAIL_PROBLEM), timeout=5)
    assert result.solved
    read = next(o for o in result.plan if o.name == "read")
    off = next(o for o in result.plan if o.name == "switch-off")
    assert len(result.plan) == 2
    if with_prevail:
        assert off.end > read.end  # the lamp stays on while x reads
        assert off.start == read.end  # a later start point of Def. 9.1 (4)
        assert result.stats.pruned_by_control > 0
    else:
        assert off.end < read.end  # without the prevail condition the earliest schedule overlaps


RESOURCE_DOMAIN = """domain shuttle
type spot
type craft
predicate at(c: craft, s: spot)
predicate road(a: spot, b: spot)
predicate found(c: craft)
KIND fuel(c: craft)
operator hop(c: craft, a: spot, b: spot)
  agent c
  pre at(c, a) and road(a, b) and fuel(c) >= 1
  effect [t'] not at(c, a), at(c, b), fuel(c) -= 1
end
"""
RESOURCE_PROBLEM = """problem p for shuttle
object a, b, c: spot
object s: craft
init at(s, a), road(a, b), road(b, a), road(b, c), road(c, a), fuel(s) = 40
goal found(s)
"""


def test_better_or_equal_accounts_for_resources(planner: TaskPlanner) -> None:
    as_resource = planner.plan(
        PlanRequest(RESOURCE_DOMAIN.replace("KIND", "resource"), RESOURCE_PROBLEM), timeout=10
    )
    as_function = planner.plan(
        PlanRequest(RESOURCE_DOMAIN.replace("KIND", "function"), RESOURCE_PROBLEM), timeout=10
    )
    assert as_resource.status is PlanStatus.UNSOLVABLE_PROVEN
    assert as_function.status is PlanStatus.UNSOLVABLE_PROVEN
    # with fuel as a resource, coming back to a place with less fuel is no better: pruned
    assert as_resource.stats.nodes_expanded <= 3
    assert as_function.stats.nodes_expanded > 10 * as_resource.stats.nodes_expanded
    assert as_resource.stats.pruned_by_cycle > 0


def test_unsolvable_problem_is_proven(planner: TaskPlanner) -> None:
    problem = logistics_problem(LogisticsSize(2, 2, 1), 1).replace("(in-city apt2 cit2)", "")
    result = planner.plan(
        PlanRequest(LOGISTICS_DOMAIN.read_text(), problem, LOGISTICS_CONTROL.read_text()),
        timeout=10,
    )
    assert result.status in (PlanStatus.UNSOLVABLE_PROVEN, PlanStatus.SOLVED)
    unreachable = problem.replace("(:goal (and", "(:goal (and (in obj1 tru2) (in obj1 tru1)")
    result = planner.plan(PlanRequest(LOGISTICS_DOMAIN.read_text(), unreachable), timeout=10)
    assert result.status is PlanStatus.UNSOLVABLE_PROVEN
    assert "exhausted" in result.reason


def test_timeout_with_injected_clock(planner: TaskPlanner) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(), logistics_problem(LogisticsSize(12, 4, 2), 1)
    )
    task = _task(planner, request)
    ticks = itertools.count()
    search = TalPlanner(task, None, SearchConfig(timeout=5.0), clock=lambda: float(next(ticks)))
    result = search.solve()
    assert result.status is PlanStatus.TIMEOUT
    assert result.stats.nodes_expanded < 64 * 6


def test_progress_is_reported_while_searching(planner: TaskPlanner) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(), logistics_problem(LogisticsSize(12, 4, 2), 1)
    )
    task = _task(planner, request)
    ticks = itertools.count()
    heard: list[PlanningProgress] = []
    search = TalPlanner(
        task,
        None,
        SearchConfig(timeout=5.0),
        clock=lambda: float(next(ticks)),
        progress=heard.append,
        started=-10.0,
    )
    assert search.solve().status is PlanStatus.TIMEOUT
    assert len(heard) >= 3 and {h.phase for h in heard} == {PlanningPhase.SEARCHING}
    expanded = [h.stats.nodes_expanded for h in heard]
    assert expanded == sorted(expanded) and expanded[-1] > expanded[0]
    assert heard[0].elapsed > 10.0  # since ``started``, not since the search began
    assert "expanded" in heard[-1].line()


def test_planning_reports_grounding_first(planner: TaskPlanner) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(), logistics_problem(LogisticsSize(3, 2, 1), 1)
    )
    heard: list[PlanningProgress] = []
    assert planner.plan(request, timeout=10, progress=heard.append).solved
    assert heard[0].phase is PlanningPhase.GROUNDING and heard[0].line().startswith("grounding")


def test_timeout_is_respected_in_wall_clock_time(planner: TaskPlanner) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(), logistics_problem(LogisticsSize(20, 6, 2), 1)
    )
    start = time.perf_counter()
    result = planner.plan(request, timeout=0.5)
    elapsed = time.perf_counter() - start
    assert result.status is PlanStatus.TIMEOUT
    assert elapsed < 3.0


def test_control_rules_prune_and_keep_search_linear(planner: TaskPlanner) -> None:
    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(),
        logistics_problem(LogisticsSize(15, 5, 2), 4),
        LOGISTICS_CONTROL.read_text(),
    )
    task = _task(planner, request)
    _, _, spec = planner.read(request)
    program = ControlCompiler(task, spec).compile()
    result = TalPlanner(task, program, SearchConfig(timeout=10, prefer=spec.prefer)).solve()
    assert result.solved
    assert result.stats.pruned_by_control > 0
    assert result.stats.nodes_expanded <= 1.2 * len(result.plan) + 1


# --- completeness of Algorithm 3 (issue 20) -------------------------------------------------

QUIET_DOMAIN = """domain quiet
type worker
predicate noisy()
predicate done()
predicate dirty()
operator chat(w: worker)
  agent w
  duration 3
  prevail not noisy()
  effect [t'] done(), noisy()
end
operator clean(w: worker)
  agent w
  duration 5
  prevail not noisy()
  effect [t'] done(), not dirty(), not noisy()
end
"""
QUIET_PROBLEM = (
    "problem q for quiet\nobject a, b: worker\ninit dirty()\ngoal done() and not dirty()\n"
)

SWAP_DOMAIN = """domain swap
type worker
predicate p()
predicate q()
predicate r()
operator mark(w: worker)
  agent w
  duration 3
  prevail q() and not r()
  effect [t'] not p(), not q()
end
operator raise(w: worker)
  agent w
  duration 3
  pre p() and not q()
  effect [t'] p(), q()
end
"""
SWAP_PROBLEM = "problem s for swap\nobject a: worker\ninit p()\ngoal not p()\n"


def _prevail_holds_on_timeline(task: Task, plan: tuple[Occurrence, ...]) -> bool:
    """Independent check: every prevail condition holds on the plan's timeline.

    The timeline applies start effects at the start and the rest at the end of each
    occurrence, in time order; a condition over ``[start, end)`` must hold in every state
    holding at some time in that interval.
    """
    ops = {o.label: o for o in task.ops}
    events = []
    for occ in plan:
        op = ops[occ.label]
        events.append((occ.start, 1, op.start_delete, op.start_add))
        events.append((occ.end, 0, op.delete & ~op.start_delete, op.add & ~op.start_add))
    events.sort(key=lambda e: (e[0], e[1]))
    bits, states = task.init_bits, [(0.0, task.init_bits)]
    for when, _, delete, add in events:
        bits = (bits & ~delete) | add
        states.append((when, bits))
    for occ in plan:
        op = ops[occ.label]
        for i, (when, state) in enumerate(states):
            following = states[i + 1][0] if i + 1 < len(states) else float("inf")
            overlaps = when < occ.end and following > occ.start and following > when
            if overlaps and (state & op.prevail_pos != op.prevail_pos or state & op.prevail_neg):
                return False
    return True


@pytest.mark.parametrize(
    ("domain", "problem", "plan"),
    [
        (QUIET_DOMAIN, QUIET_PROBLEM, ["clean"]),
        (SWAP_DOMAIN, SWAP_PROBLEM, ["raise", "mark"]),
    ],
    ids=["doomed-twin", "pending-after-tau0"],
)
@pytest.mark.parametrize("mode", [CycleCheck.PATH, CycleCheck.PATH_CLOSED, CycleCheck.GLOBAL])
def test_cycle_check_keys_the_timeline_prevail_conditions_read(
    planner: TaskPlanner, domain: str, problem: str, plan: list[str], mode: CycleCheck
) -> None:
    """Plans the search before issue 20 missed (it reported UNSOLVABLE_PROVEN on both).

    Its visited map keyed a node by the final state, the pending prevail conditions and the
    running actions' end times and written features, relative to ``tau0``, but not by the
    states the timeline still passes through. In "doomed-twin" the depth-first search first
    reaches the final state of ``clean`` through ``chat; clean`` (``clean`` starts at 3 while
    ``noisy`` is true, so its prevail condition is doomed) and then prunes ``clean`` alone at
    0, whose key was the same. "pending-after-tau0" is the same defect with the plan's two
    actions of one agent. Now the key holds the timeline from ``tau0`` on (the features some
    prevail condition reads), so every mode finds the plans.
    """
    task = _task(planner, PlanRequest(domain, problem))
    result = TalPlanner(task, None, SearchConfig(timeout=5, cycle_check=mode)).solve()
    assert result.status is PlanStatus.SOLVED
    assert [o.name for o in result.plan] == plan
    _check_definition_9_1(task, result)
    assert _prevail_holds_on_timeline(task, result.plan)


@pytest.mark.parametrize(
    ("goal", "plan"),
    [
        ("at(s, b) and fuel(s) <= 38", ["jump"]),  # the goal wants less fuel
        ("landed(s)", ["jump", "land"]),  # a precondition wants less fuel
    ],
    ids=["goal", "precondition"],
)
@pytest.mark.parametrize(
    ("mode", "solved"),
    [(CycleCheck.PATH, True), (CycleCheck.PATH_CLOSED, True), (CycleCheck.GLOBAL, False)],
)
def test_better_or_equal_is_checked_along_the_path(
    planner: TaskPlanner, goal: str, plan: list[str], mode: CycleCheck, solved: bool
) -> None:
    """Algorithm 3 (line 14) compares with the states of the current path only.

    ``hop`` to ``b`` is tried first and leaves 39 fuel, a dead end; ``jump`` reaches ``b``
    with 38, which the goal or ``land`` needs. The global better-or-equal map of the search
    before issue 20 (``CycleCheck.GLOBAL``) prunes it because 39 >= 38 was seen on another
    branch, so it proves the problem unsolvable; along the path nothing prunes it.
    """
    task = _task(planner, PlanRequest(FUEL_DOMAIN, FUEL_PROBLEM.replace("GOAL", goal)))
    result = TalPlanner(task, None, SearchConfig(timeout=5, cycle_check=mode)).solve()
    if solved:
        assert result.status is PlanStatus.SOLVED
        assert [o.name for o in result.plan] == plan
        _check_definition_9_1(task, result)
    else:
        assert result.status is PlanStatus.UNSOLVABLE_PROVEN
        assert result.stats.pruned_by_cycle > 0


def test_search_leaves_no_cyclic_garbage(planner: TaskPlanner) -> None:
    """The planner pauses the cyclic GC through the search: the search must make no cycles."""
    import gc

    request = PlanRequest(
        LOGISTICS_DOMAIN.read_text(),
        logistics_problem(LogisticsSize(10, 4, 2), 1),
        LOGISTICS_CONTROL.read_text(),
    )
    d, p, spec = planner.read(request)
    task = planner.ground(d, p)
    program = ControlCompiler(task, spec).compile()
    was = gc.isenabled()
    gc.collect()
    gc.disable()
    try:
        result = TalPlanner(task, program, SearchConfig(timeout=60.0)).solve()
        assert result.status is PlanStatus.SOLVED and result.stats.nodes_expanded > 10
        assert gc.collect() == 0
    finally:
        if was:
            gc.enable()
