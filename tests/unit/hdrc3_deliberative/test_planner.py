from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from hdrc3_deliberative.generators import (
    BLOCKS_CONTROL,
    BLOCKS_DOMAIN,
    DEPOTS_CONTROL,
    DEPOTS_DOMAIN,
    DRIVERLOG_CONTROL,
    DRIVERLOG_DOMAIN,
    DRIVERLOG_NUMERIC_DOMAIN,
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    ROVERS_CONTROL,
    ROVERS_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    ZENOTRAVEL_CONTROL,
    ZENOTRAVEL_DOMAIN,
    ZENOTRAVEL_NUMERIC_CONTROL,
    ZENOTRAVEL_NUMERIC_DOMAIN,
    DepotsSize,
    DriverLogSize,
    LogisticsSize,
    RoversSize,
    SatelliteSize,
    UavSize,
    ZenoSize,
    blocks_problem,
    depots_problem,
    driverlog_problem,
    logistics_problem,
    rovers_problem,
    satellite_problem,
    uav_problem,
    zenotravel_problem,
)
from hdrc3_deliberative.generators import (
    SATELLITE_CONTROL as SAT_CONTROL,
)
from hdrc3_deliberative.generators import (
    SATELLITE_DOMAIN as SAT_DOMAIN,
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


ZENO_DOMAIN = """(define (domain zeno) (:requirements :typing :fluents :durative-actions)
  (:types aircraft person city - object)
  (:predicates (at ?x - (either person aircraft) ?c - city) (in ?p - person ?a - aircraft))
  (:functions (fuel ?a - aircraft) (distance ?c1 - city ?c2 - city) (total-fuel-used))
  (:durative-action board :parameters (?p - person ?a - aircraft ?c - city)
    :duration (= ?duration 1)
    :condition (and (at start (at ?p ?c)) (over all (at ?a ?c)))
    :effect (and (at start (not (at ?p ?c))) (at end (in ?p ?a))))
  (:durative-action debark :parameters (?p - person ?a - aircraft ?c - city)
    :duration (= ?duration 1)
    :condition (and (at start (in ?p ?a)) (over all (at ?a ?c)))
    :effect (and (at start (not (in ?p ?a))) (at end (at ?p ?c))))
  (:durative-action fly :parameters (?a - aircraft ?c1 ?c2 - city)
    :duration (= ?duration (distance ?c1 ?c2))
    :condition (and (at start (at ?a ?c1)) (at start (>= (fuel ?a) (distance ?c1 ?c2))))
    :effect (and (at start (not (at ?a ?c1))) (at end (at ?a ?c2))
                 (at end (increase (total-fuel-used) (distance ?c1 ?c2)))
                 (at end (decrease (fuel ?a) (distance ?c1 ?c2))))))"""

ZENO_PROBLEM = """(define (problem z1) (:domain zeno)
  (:objects plane - aircraft ann bob - person a b c - city)
  (:init (at plane a) (at ann a) (at bob b) (= (fuel plane) 10) (= (total-fuel-used) 0)
    (= (distance a b) 3) (= (distance b a) 3) (= (distance a c) 4) (= (distance c a) 4)
    (= (distance b c) 5) (= (distance c b) 5))
  (:goal (and (at ann c) (at bob c))))"""


def test_numeric_durative_either_domain_solves(planner: TaskPlanner) -> None:
    result = planner.plan(PlanRequest(ZENO_DOMAIN, ZENO_PROBLEM), timeout=20)
    assert result.status is PlanStatus.SOLVED, result.reason
    # 3 + 5 = 8 fuel for a -> b -> c; a -> c -> b -> c needs 4 + 5 + 5 = 14 > 10
    flights = [o.args for o in result.plan if o.name == "fly"]
    assert flights[-1][2] == "c" and len(flights) <= 3
    durations = {o.name: o.duration for o in result.plan}
    assert durations["board"] == 1.0 and durations["debark"] == 1.0
    assert all(line.endswith("]") and ": (" in line for line in result.ipc_lines())


def test_fuel_precondition_makes_problem_unsolvable(planner: TaskPlanner) -> None:
    problem = ZENO_PROBLEM.replace("(= (fuel plane) 10)", "(= (fuel plane) 2)")
    result = planner.plan(PlanRequest(ZENO_DOMAIN, problem), timeout=20)
    assert result.status is PlanStatus.UNSOLVABLE_PROVEN


def test_domain_problem_mismatch_is_named(planner: TaskPlanner) -> None:
    problem = ZENO_PROBLEM.replace("(:domain zeno)", "(:domain depots)")
    result = planner.plan(PlanRequest(ZENO_DOMAIN, problem), timeout=5)
    assert result.status is PlanStatus.INVALID_INPUT
    assert "problem is for domain 'depots', not 'zeno'" in result.reason


@pytest.mark.parametrize(
    ("domain", "control", "problem", "max_length"),
    [
        (BLOCKS_DOMAIN, BLOCKS_CONTROL, blocks_problem(10, 1), 40),
        (BLOCKS_DOMAIN, BLOCKS_CONTROL, blocks_problem(10, 2), 40),
        (ZENOTRAVEL_DOMAIN, ZENOTRAVEL_CONTROL, zenotravel_problem(ZenoSize(5, 2, 5), 1), 40),
        (ZENOTRAVEL_DOMAIN, ZENOTRAVEL_CONTROL, zenotravel_problem(ZenoSize(6, 2, 6), 2), 40),
        (DEPOTS_DOMAIN, DEPOTS_CONTROL, depots_problem(DepotsSize(1, 2, 2, 3, 3, 6), 1), 40),
        (DEPOTS_DOMAIN, DEPOTS_CONTROL, depots_problem(DepotsSize(2, 2, 3, 5, 5, 10), 2), 60),
        (SAT_DOMAIN, SAT_CONTROL, satellite_problem(SatelliteSize(1, 1, 3, 3, 3), 1), 20),
        (SAT_DOMAIN, SAT_CONTROL, satellite_problem(SatelliteSize(3, 2, 3, 8, 8), 2), 40),
        (DRIVERLOG_DOMAIN, DRIVERLOG_CONTROL, driverlog_problem(DriverLogSize(3, 1, 2, 1), 1), 30),
        (DRIVERLOG_DOMAIN, DRIVERLOG_CONTROL, driverlog_problem(DriverLogSize(8, 3, 6, 2), 2), 80),
        (ROVERS_DOMAIN, ROVERS_CONTROL, rovers_problem(RoversSize(1, 4, 2, 1, 3), 1), 30),
        (ROVERS_DOMAIN, ROVERS_CONTROL, rovers_problem(RoversSize(3, 10, 4, 3, 8), 2), 120),
    ],
)
def test_shipped_domains_solve_with_their_control_rules(
    planner: TaskPlanner, domain: Path, control: Path, problem: str, max_length: int
) -> None:
    """Control rules steer the depth-first search straight to a valid plan (no backtracking)."""
    request = PlanRequest(domain.read_text(), problem, control.read_text())
    result = planner.plan(request, timeout=60)
    assert result.status is PlanStatus.SOLVED, result.reason
    assert len(result.plan) <= max_length
    assert result.stats.nodes_expanded <= 2 * len(result.plan) + 1
    outcome = validate_pddl_plan(domain.read_text(), problem, result.plan)
    assert outcome.valid, outcome.reason


# A problem in the layout of the IPC-2002 Depots files (domain name "Depot", capitalised types,
# tab-free), written for this test.
IPC_LAYOUT_DEPOT = """(define (problem depotprob1818) (:domain Depot)
(:objects
    depot0 - Depot
    distributor0 distributor1 - Distributor
    truck0 truck1 - Truck
    pallet0 pallet1 pallet2 - Pallet
    crate0 crate1 - Crate
    hoist0 hoist1 hoist2 - Hoist)
(:init
    (at pallet0 depot0)
    (clear crate1)
    (at pallet1 distributor0)
    (clear crate0)
    (at pallet2 distributor1)
    (clear pallet2)
    (at truck0 distributor1)
    (at truck1 depot0)
    (at hoist0 depot0)
    (available hoist0)
    (at hoist1 distributor0)
    (available hoist1)
    (at hoist2 distributor1)
    (available hoist2)
    (at crate0 distributor0)
    (on crate0 pallet1)
    (at crate1 depot0)
    (on crate1 pallet0)
)
(:goal (and
        (on crate0 pallet2)
        (on crate1 pallet1)
    )
))
"""


def test_depots_rules_read_the_competition_layout(planner: TaskPlanner) -> None:
    domain = DEPOTS_DOMAIN.read_text()
    result = planner.plan(PlanRequest(domain, IPC_LAYOUT_DEPOT, DEPOTS_CONTROL.read_text()), 30)
    assert result.status is PlanStatus.SOLVED, result.reason
    assert result.stats.nodes_expanded == len(result.plan)  # no backtracking
    assert validate_pddl_plan(domain, IPC_LAYOUT_DEPOT, result.plan).valid


@pytest.mark.parametrize(
    ("domain", "control", "problem"),
    [
        (DRIVERLOG_DOMAIN, DRIVERLOG_CONTROL, driverlog_problem(DriverLogSize(4, 2, 3, 2), 1)),
        (ROVERS_DOMAIN, ROVERS_CONTROL, rovers_problem(RoversSize(2, 6, 3, 2, 5), 1)),
    ],
)
def test_map_domain_rules_prune_wandering(
    planner: TaskPlanner, domain: Path, control: Path, problem: str
) -> None:
    """Without rules the depth-first search wanders the map; with them it heads for targets."""
    ruled = planner.plan(PlanRequest(domain.read_text(), problem, control.read_text()), 20)
    blind = planner.plan(PlanRequest(domain.read_text(), problem), 20)
    assert ruled.status is blind.status is PlanStatus.SOLVED
    assert 5 * len(ruled.plan) < len(blind.plan)
    assert 5 * ruled.stats.nodes_expanded < blind.stats.nodes_expanded


@pytest.mark.parametrize(
    ("size", "seed"), [(DriverLogSize(3, 1, 2, 1), 1), (DriverLogSize(8, 3, 6, 2), 2)]
)
def test_numeric_driverlog_solves_with_the_strips_rules(
    planner: TaskPlanner, size: DriverLogSize, seed: int
) -> None:
    """The numeric domain adds only metric sums: its plans are checked on the STRIPS twin.

    unified-planning's validator refuses the numeric problem (times are defined only for
    linked places: UNDEFINED_INITIAL_NUMERIC); the generator draws the STRIPS problem from
    the same random stream, so the same plan must be valid there.
    """
    problem = driverlog_problem(size, seed, numeric=True)
    request = PlanRequest(
        DRIVERLOG_NUMERIC_DOMAIN.read_text(), problem, DRIVERLOG_CONTROL.read_text()
    )
    result = planner.plan(request, timeout=30)
    assert result.status is PlanStatus.SOLVED, result.reason
    assert "(time-to-drive " in problem and "(:metric minimize" in problem
    strips = driverlog_problem(size, seed)
    outcome = validate_pddl_plan(DRIVERLOG_DOMAIN.read_text(), strips, result.plan)
    assert outcome.valid, outcome.reason


@pytest.mark.parametrize(("size", "seed"), [(ZenoSize(5, 2, 5), 1), (ZenoSize(6, 3, 6), 2)])
def test_numeric_zenotravel_solves_with_its_rules(
    planner: TaskPlanner, size: ZenoSize, seed: int
) -> None:
    """The numeric rules steer the search to a plan unified-planning validates (fuel too)."""
    domain = ZENOTRAVEL_NUMERIC_DOMAIN.read_text()
    problem = zenotravel_problem(size, seed, numeric=True)
    result = planner.plan(PlanRequest(domain, problem, ZENOTRAVEL_NUMERIC_CONTROL.read_text()), 30)
    assert result.status is PlanStatus.SOLVED, result.reason
    assert result.stats.nodes_expanded <= 2 * len(result.plan) + 1
    assert {o.agent for o in result.plan} <= {f"plane{i + 1}" for i in range(size.planes)}
    outcome = validate_pddl_plan(domain, problem, result.plan)
    assert outcome.valid, outcome.reason
    # the validator checks the fuel: the first flight is valid on a full tank, not on an empty one
    flight = next(o for o in result.plan if o.name == "fly")
    plane, _, there = flight.args
    alone = (replace(flight, start=0.0, end=1.0),)
    flown = problem[: problem.index("(:goal")] + f"(:goal (and (at {plane} {there}))))\n"
    for fuel, valid in ((100000, True), (0, False)):
        changed = re.sub(rf"\(= \(fuel {plane}\) \d+\)", f"(= (fuel {plane}) {fuel})", flown)
        assert validate_pddl_plan(domain, changed, alone).valid is valid
