from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_deliberative.generators import (
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    LogisticsSize,
    UavSize,
    logistics_problem,
    uav_problem,
)
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner, is_pddl
from hdrc3_deliberative.result import PlanStatus
from hdrc3_deliberative.validation import validate_pddl_plan


@pytest.fixture(scope="module")
def planner() -> TaskPlanner:
    return TaskPlanner()


@pytest.mark.parametrize(
    ("size", "seed", "control", "sequential"),
    [
        (LogisticsSize(3, 2, 1), 1, False, False),
        (LogisticsSize(4, 2, 1), 2, False, True),
        (LogisticsSize(10, 4, 2), 3, True, False),
        (LogisticsSize(10, 4, 2), 3, True, True),
        (LogisticsSize(20, 7, 2), 5, True, False),
        (LogisticsSize(12, 3, 2, locations_per_city=4), 6, True, False),
    ],
)
def test_logistics_plans_validate_with_unified_planning(
    planner: TaskPlanner, size: LogisticsSize, seed: int, control: bool, sequential: bool
) -> None:
    domain = LOGISTICS_DOMAIN.read_text()
    problem = logistics_problem(size, seed)
    request = PlanRequest(domain, problem, LOGISTICS_CONTROL.read_text() if control else "")
    result = planner.plan(request, timeout=20, sequential=sequential)
    assert result.status is PlanStatus.SOLVED
    outcome = validate_pddl_plan(domain, problem, result.plan)
    assert outcome.valid, outcome.reason
    if control and not sequential:
        assert {o.agent for o in result.plan} <= {f"tru{i}" for i in range(1, 8)} | {"apn1", "apn2"}


@pytest.mark.parametrize("seed", [1, 2])
def test_generated_uav_problems_solve(planner: TaskPlanner, seed: int) -> None:
    request = PlanRequest(
        UAV_DOMAIN.read_text(), uav_problem(UavSize(2, 3, 6, 1), seed), UAV_CONTROL.read_text()
    )
    result = planner.plan(request, timeout=10)
    assert result.solved
    assert len(result.plan) >= 6 * 3  # every box: pick up, fly, drop


def test_uav_scenario_solves_quickly(planner: TaskPlanner) -> None:
    request = PlanRequest(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text(), UAV_CONTROL.read_text())
    result = planner.plan(request, timeout=10)
    assert result.solved
    assert result.stats.search_seconds < 2.0
    delivered = {(o.args[1], o.args[2]) for o in result.plan if o.name == "drop-box"}
    assert ("med3", "body3") in delivered and ("food4", "body4") in delivered


@pytest.mark.parametrize(
    ("domain", "problem", "control", "fragment"),
    [
        (
            "(define (domain x)",
            "(define (problem p) (:domain x))",
            "",
            "<domain>:1:19: unexpected end of file",
        ),
        (
            LOGISTICS_DOMAIN.read_text(),
            "problem p for logistics\nobject a: nothing",
            "",
            "undefined type 'nothing'",
        ),
        (
            UAV_DOMAIN.read_text(),
            UAV_SCENARIO.read_text(),
            "rule r: [t] at(heli9, supply1)",
            "'heli9'",
        ),
        (UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text(), "prefer teleport", "'teleport'"),
    ],
)
def test_bad_input_is_a_result(
    planner: TaskPlanner, domain: str, problem: str, control: str, fragment: str
) -> None:
    result = planner.plan(PlanRequest(domain, problem, control), timeout=5)
    assert result.status is PlanStatus.INVALID_INPUT
    assert fragment in result.reason


def test_unreadable_file_raises_input_error(tmp_path: Path) -> None:
    from hdrc3_deliberative.errors import PlanningInputError

    with pytest.raises(PlanningInputError, match="cannot read file"):
        PlanRequest.from_files(tmp_path / "missing.pddl", tmp_path / "p.pddl")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("; comment\n(define (domain d))", True),
        ("domain d", False),
        ("\n\n  (define", True),
        ("# x\n(", False),
    ],
)
def test_format_detection(text: str, expected: bool) -> None:
    assert is_pddl(text) is expected
