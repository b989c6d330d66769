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
from hdrc3_deliberative.search import SearchConfig, TalPlanner
from hdrc3_deliberative.task import Task


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
