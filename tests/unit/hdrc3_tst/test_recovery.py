"""Recovery decisions (chapter 9.3.1): steps, the new problem, give-up; replans with TALplanner."""

from __future__ import annotations

from dataclasses import replace

import pytest

from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_tst.goal_planning import (
    GoalProblem,
    Load,
    PlannedStep,
    StepsStatus,
    domain_text,
    goal_problem,
    plan_steps,
)
from hdrc3_tst.model import Node, NodeKind
from hdrc3_tst.recovery import (
    Recovery,
    RecoveryStatus,
    RecoveryStep,
    Violation,
    after,
    progressed,
)
from hdrc3_tst.recovery_spec import DEFAULT_RECOVERY, RecoverySpecParser

SPEC = RecoverySpecParser().parse_file(DEFAULT_RECOVERY)
GOAL = Node("d", NodeKind.GOAL, {}, action="at", goal_args=("box1", "Field"))
POINTS = {"Depot": (0.0, 0.0, 20.0), "Field": (200.0, 0.0, 20.0), "box1": (0.0, 1.0, 0.0)}
WHERE = (80.0, 5.0, 20.0)
"""Where the aircraft's own estimate puts it at the violation."""


def problem() -> GoalProblem:
    loads = (Load("box1", "food-box", "Depot", 6.0),)
    return goal_problem(GOAL, "uav0", (-100.0, 0.0, 20.0), POINTS, loads)


def step(action: str, **args: str) -> PlannedStep:
    return PlannedStep(action, "uav0", args, 0.0, 1.0)


TO_DEPOT = step("fly-to", destination="Depot")
PICKED = step("pick-up-box", box="box1")
DROPPED = step("drop-box", box="box1", place="Field")
BOX_LOST = Violation("held@d/3", "box-lost", True, {"av": "uav0", "box": "box1"})
NO_LIFT = Violation("lifted@d/2", "lower-lift-capacity", False, {"av": "uav0", "box": "box1"})
HALT_BRAKE = (RecoveryStep.SUSPEND, RecoveryStep.BRAKE, RecoveryStep.HOVER)
HALT = (RecoveryStep.SUSPEND, RecoveryStep.HOVER)
RECOVER = (RecoveryStep.APPLY_OPERATOR, RecoveryStep.REPLAN)


@pytest.mark.parametrize(
    ("done", "holding", "box_at"),
    [
        ((), "", "Depot"),
        ((TO_DEPOT, PICKED), "box1", "Depot"),
        ((TO_DEPOT, PICKED, DROPPED), "", "Field"),
    ],
)
def test_succeeded_steps_move_the_loads(
    done: tuple[PlannedStep, ...], holding: str, box_at: str
) -> None:
    now = progressed(problem(), done)
    assert now.holding == holding
    assert {load.name: load.location for load in now.loads} == {"box1": box_at}


@pytest.mark.parametrize(
    ("violation", "done", "steps", "changes", "lift", "box_at"),
    [
        (BOX_LOST, (TO_DEPOT, PICKED), (*HALT_BRAKE, *RECOVER), ("at(box1, recover_uav0_1)",),
         30.0, after("uav0", 1)),
        (
            NO_LIFT,
            (TO_DEPOT,),
            (*HALT, *RECOVER),
            ("lift-capacity(uav0) = 4.8", "release(box1)"),
            4.8,
            "Depot",
        ),
        (Violation("speed_limit", "", True), (TO_DEPOT, PICKED), (*HALT_BRAKE, *RECOVER), (),
         30.0, "Depot"),
    ],
)  # fmt: skip
def test_a_recovery_suspends_hovers_applies_its_operator_and_replans(
    violation: Violation,
    done: tuple[PlannedStep, ...],
    steps: tuple[RecoveryStep, ...],
    changes: tuple[str, ...],
    lift: float,
    box_at: str,
) -> None:
    decision = Recovery(SPEC).decide(violation, problem(), done, WHERE)
    assert decision.status is RecoveryStatus.REPLAN, decision.reason
    assert decision.steps == steps
    assert decision.changes == changes
    assert decision.attempt == 1
    assert decision.problem is not None
    assert decision.problem.start == after("uav0", 1)
    assert decision.problem.locations[after("uav0", 1)] == WHERE
    assert decision.problem.lift_capacity == pytest.approx(lift)
    assert {load.name: load.location for load in decision.problem.loads} == {"box1": box_at}
    assert decision.places[after("uav0", 1)] == WHERE


def plan(p: GoalProblem) -> tuple[PlanStatus, list[tuple[str, dict[str, float | str]]]]:
    result = TaskPlanner().plan(PlanRequest(domain_text(), p.text(), p.control()), timeout=30.0)
    if result.status is not PlanStatus.SOLVED:
        return result.status, []
    steps = plan_steps(
        [o.label for o in result.plan],
        [o.agent or "" for o in result.plan],
        [o.start for o in result.plan],
        [o.duration for o in result.plan],
    )
    assert steps.status is StepsStatus.OK
    return result.status, [(s.action, dict(s.args)) for s in steps.steps]


def test_a_lost_box_is_picked_up_again_where_it_fell() -> None:
    decision = Recovery(SPEC).decide(BOX_LOST, problem(), (TO_DEPOT, PICKED), WHERE)
    assert decision.problem is not None
    assert decision.places["box1"] == WHERE
    status, steps = plan(decision.problem)
    assert status is PlanStatus.SOLVED
    assert steps == [
        ("pick-up-box", {"box": "box1"}),
        ("fly-to", {"destination": "Field"}),
        ("drop-box", {"box": "box1", "place": "Field"}),
    ]


def test_a_box_too_heavy_after_the_lift_capacity_is_lowered_has_no_plan() -> None:
    decision = Recovery(SPEC).decide(NO_LIFT, problem(), (TO_DEPOT,), WHERE)
    assert decision.problem is not None
    status, _ = plan(decision.problem)
    assert status is not PlanStatus.SOLVED


def test_the_same_fault_gives_up_after_the_operators_attempts() -> None:
    recovery = Recovery(SPEC)
    statuses = [recovery.decide(BOX_LOST, problem(), (), WHERE).status for _ in range(4)]
    assert statuses == [RecoveryStatus.REPLAN] * 3 + [RecoveryStatus.GAVE_UP]
    last = recovery.decide(BOX_LOST, problem(), (), WHERE)
    assert last.steps == (*HALT_BRAKE, RecoveryStep.GIVE_UP)
    assert "failed 5 times on the same fault (box-lost recovers from 3)" in last.reason
    # another fault (another step of the same formula counts as the same fault; another box not)
    other = replace(BOX_LOST, monitor_id="held@d/7", arguments={"av": "uav0", "box": "box2"})
    assert recovery.decide(other, problem(), (), WHERE).attempt == 1
    again = replace(BOX_LOST, monitor_id="held@d/7")
    assert recovery.decide(again, problem(), (), WHERE).attempt == 6


@pytest.mark.parametrize(
    ("violation", "reason"),
    [
        (Violation("m", "teleport"), "m: no recovery operator 'teleport'"),
        (Violation("m", "box-lost", False, {"av": "uav0"}), "has no argument 'box'"),
        (Violation("m", "box-lost", False, {"box": "box9"}), "box9 is not a load"),
    ],
)
def test_recoveries_that_cannot_apply_give_up_with_a_reason(
    violation: Violation, reason: str
) -> None:
    decision = Recovery(SPEC).decide(violation, problem(), (), WHERE)
    assert decision.status is RecoveryStatus.NOT_APPLICABLE
    assert decision.steps[-1] is RecoveryStep.GIVE_UP
    assert decision.problem is None
    assert reason in decision.reason


def test_a_carrier_that_did_not_lift_is_planned_again_with_fewer_boxes() -> None:
    loads = (
        Load("c1", "carrier", "Depot", 28.0),
        *(Load(f"b{i}", "food-box", "Depot", 5.0, on="c1") for i in range(1, 5)),
    )
    goal = " and ".join(f"at(b{i}, Field)" for i in range(1, 5))
    start = replace(goal_problem(GOAL, "uav0", (-100.0, 0.0, 20.0), POINTS, loads), goal=goal)
    too_heavy = Violation("lifted@d/2", "carrier-too-heavy", False, {"av": "uav0", "carrier": "c1"})
    decision = Recovery(SPEC).decide(too_heavy, start, (TO_DEPOT,), WHERE)
    assert decision.changes == ("lift-capacity(uav0) = 22.4", "release(c1)")
    assert decision.released == ("c1",)  # the magnet still grips it: let go before planning
    assert decision.problem is not None
    status, steps = plan(decision.problem)
    assert status is PlanStatus.SOLVED
    actions = [action for action, _ in steps]
    before = actions[: actions.index("attach-carrier")]
    assert before.count("take-from-carrier") == 2  # 18 kg left on the carrier
    assert actions.count("drop-box") == 4


LOT = (
    Load("c1", "carrier", "Depot", 18.0, slots=2),
    Load("b1", "food-box", "Depot", 5.0, on="c1"),
    Load("b2", "food-box", "Depot", 5.0, on="c1"),
    Load("b3", "food-box", "Depot", 5.0),
)
"""A carrier of 8 kg with b1 and b2 on it, and b3 beside it."""


@pytest.mark.parametrize(
    ("done", "holding", "where"),
    [
        # b1 off the carrier: the carrier is 5 kg lighter, b1 is on the hook
        (
            (step("take-from-carrier", box="b1"),),
            "b1",
            {"c1": ("Depot", "", 13.0, 3), "b1": ("Depot", "", 5.0, 0)},
        ),
        # b3 onto the one carrier at the depot
        (
            (step("pick-up-box", box="b3"), step("put-on-carrier", box="b3", place="Depot")),
            "",
            {"c1": ("Depot", "", 23.0, 1), "b3": ("Depot", "c1", 5.0, 0)},
        ),
        # the carrier flown to the field: its boxes with it, still on it
        (
            (
                step("attach-carrier", carrier="c1"),
                step("detach-carrier", carrier="c1", place="Field"),
            ),
            "",
            {"c1": ("Field", "", 18.0, 2), "b1": ("Field", "c1", 5.0, 0)},
        ),
    ],
)
def test_succeeded_steps_move_boxes_on_and_off_carriers(
    done: tuple[PlannedStep, ...], holding: str, where: dict[str, tuple[str, str, float, int]]
) -> None:
    now = progressed(replace(problem(), loads=LOT), done)
    assert now.holding == holding
    loads = {load.name: load for load in now.loads}
    for name, (location, on, kg, slots) in where.items():
        load = loads[name]
        assert (load.location, load.on, load.weight, load.slots) == (location, on, kg, slots)
