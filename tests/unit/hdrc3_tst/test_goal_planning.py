"""Goal nodes as planning problems, and plans as steps; the problem solves with TALplanner."""

from __future__ import annotations

from dataclasses import replace

import pytest

from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_tst.goal_planning import (
    GoalProblem,
    Load,
    StepsStatus,
    Stocked,
    control_text,
    domain_text,
    goal_problem,
    operator_mappings,
    plan_steps,
    stocked_loads,
)
from hdrc3_tst.model import Node, NodeKind
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS

GOAL = Node("g", NodeKind.GOAL, {}, action="at", goal_args=("uav0", "Square"))
POINTS = {"Square": (100.0, 50.0, 30.0), "Depot": (10.0, 20.0, 25.0)}


def test_the_problem_names_where_the_aircraft_is_and_every_point() -> None:
    problem = goal_problem(GOAL, "uav0", (-150.0, 0.0, 30.0), POINTS).text()
    assert problem.splitlines() == [
        "problem goal_g for uav-logistics",
        "object here_uav0: location @ (-150.000, 0.000, 30.000)",
        "object Depot: location @ (10.000, 20.000, 25.000)",
        "object Square: location @ (100.000, 50.000, 30.000)",
        "object uav0: helicopter",
        "init at(uav0, here_uav0), free(uav0), hovering(uav0), lift-capacity(uav0) = 30, "
        "fuel(uav0) = 3000",
        "goal at(uav0, Square)",
    ]


def test_talplanner_solves_it_with_one_fly_to() -> None:
    problem = goal_problem(GOAL, "uav0", (-150.0, 0.0, 30.0), POINTS).text()
    result = TaskPlanner().plan(PlanRequest(domain_text(), problem, ""), timeout=30.0)
    assert result.status is PlanStatus.SOLVED
    steps = plan_steps(
        [o.label for o in result.plan],
        [o.agent or "" for o in result.plan],
        [o.start for o in result.plan],
        [o.duration for o in result.plan],
    )
    assert steps.status is StepsStatus.OK
    assert [(s.action, s.agent, dict(s.args)) for s in steps.steps] == [
        ("fly-to", "uav0", {"destination": "Square"})
    ]


@pytest.mark.parametrize(
    ("label", "reason"),
    [
        ("(land uav0 Sq)", "the plan needs (land uav0 Sq), and no RMAX executor"),
        ("(drop-box uav0 b1)", "plan action (drop-box uav0 b1) has too few arguments"),
        ("()", "empty plan action '()'"),
    ],
)
def test_plans_with_actions_nobody_executes_are_refused(label: str, reason: str) -> None:
    steps = plan_steps([label], ["uav0"], [0.0], [1.0])
    assert steps.status is StepsStatus.NOT_EXECUTABLE
    assert steps.reason.startswith(reason)


def test_every_operator_with_an_executor_maps_onto_its_action() -> None:
    mappings = operator_mappings()
    assert {n: dict(m.args) for n, m in mappings.items()} == {
        "fly-to": {"destination": 2},
        "pick-up-box": {"box": 1},
        "drop-box": {"box": 1, "place": 2},
        "put-on-carrier": {"box": 1, "place": 3},
        "take-from-carrier": {"box": 1},
        "attach-carrier": {"carrier": 1},
        "detach-carrier": {"carrier": 1, "place": 2},
    }
    assert set(mappings) <= set(RMAX_EXECUTORS)


@pytest.mark.parametrize(
    ("label", "action", "args"),
    [
        ("(fly-to uav0 here_uav0 Field)", "fly-to", {"destination": "Field"}),
        ("(pick-up-box uav0 box1 Depot)", "pick-up-box", {"box": "box1"}),
        ("(drop-box uav0 box1 Field)", "drop-box", {"box": "box1", "place": "Field"}),
        ("(put-on-carrier uav0 box1 c1 Lot)", "put-on-carrier", {"box": "box1", "place": "Lot"}),
        ("(take-from-carrier uav0 box1 c1 Lot)", "take-from-carrier", {"box": "box1"}),
        ("(attach-carrier uav0 c1 Lot)", "attach-carrier", {"carrier": "c1"}),
        ("(detach-carrier uav0 c1 Field)", "detach-carrier", {"carrier": "c1", "place": "Field"}),
    ],
)
def test_plan_actions_become_steps(label: str, action: str, args: dict[str, str]) -> None:
    steps = plan_steps([label], ["uav0"], [0.0], [1.0])
    assert steps.status is StepsStatus.OK
    assert [(s.action, dict(s.args)) for s in steps.steps] == [(action, args)]


BOX_GOAL = Node("d", NodeKind.GOAL, {}, action="at", goal_args=("box1", "Field"))
DELIVERY_POINTS = {
    "Depot": (0.0, 0.0, 20.0),
    "Field": (200.0, 0.0, 20.0),
    "box1": (0.0, 1.0, 0.0),
}


def delivery_problem(lift: float = 30.0) -> GoalProblem:
    problem = goal_problem(
        BOX_GOAL,
        "uav0",
        (-100.0, 0.0, 20.0),
        DELIVERY_POINTS,
        (Load("box1", "food-box", "Depot", 6.0),),
    )
    return replace(problem, lift_capacity=lift)


def test_a_delivery_goal_plans_pick_up_and_drop_steps() -> None:
    problem = delivery_problem()
    assert "box1" not in problem.locations
    assert problem.control() == control_text()
    request = PlanRequest(domain_text(), problem.text(), problem.control())
    result = TaskPlanner().plan(request, timeout=30.0)
    assert result.status is PlanStatus.SOLVED, result.reason
    steps = plan_steps(
        [o.label for o in result.plan],
        [o.agent or "" for o in result.plan],
        [o.start for o in result.plan],
        [o.duration for o in result.plan],
    )
    assert steps.status is StepsStatus.OK
    assert [(s.action, dict(s.args)) for s in steps.steps] == [
        ("fly-to", {"destination": "Depot"}),
        ("pick-up-box", {"box": "box1"}),
        ("fly-to", {"destination": "Field"}),
        ("drop-box", {"box": "box1", "place": "Field"}),
    ]


def test_a_box_the_goal_does_not_name_is_no_reason_to_fly() -> None:
    # box2 waits at Aisle, which the search tries first (destinations in name order); fetching
    # a box the goal does not name is a detour the control rules prune: straight to box1
    stock = {**DELIVERY_POINTS, "Aisle": (-50.0, 0.0, 20.0), "box2": (-50.0, 1.0, 0.0)}
    loads = (Load("box1", "food-box", "Depot", 6.0), Load("box2", "food-box", "Aisle", 6.0))
    problem = goal_problem(BOX_GOAL, "uav0", (-100.0, 0.0, 20.0), stock, loads)
    request = PlanRequest(domain_text(), problem.text(), problem.control())
    result = TaskPlanner().plan(request, timeout=30.0)
    assert result.status is PlanStatus.SOLVED, result.reason
    assert [o.label for o in result.plan] == [
        "(fly-to uav0 here_uav0 Depot)",
        "(pick-up-box uav0 box1 Depot)",
        "(fly-to uav0 Depot Field)",
        "(drop-box uav0 box1 Field)",
    ]


def test_only_goals_naming_a_load_plan_with_the_control_rules() -> None:
    problem = delivery_problem()
    assert problem.control() == control_text()
    flight = replace(problem, goal="at(uav0, Field)")
    assert flight.control() == ""
    request = PlanRequest(domain_text(), flight.text(), flight.control())
    assert TaskPlanner().plan(request, timeout=30.0).status is PlanStatus.SOLVED


def test_a_box_heavier_than_the_lift_capacity_has_no_plan() -> None:
    problem = delivery_problem(lift=5.0)
    request = PlanRequest(domain_text(), problem.text(), problem.control())
    result = TaskPlanner().plan(request, timeout=30.0)
    assert result.status is not PlanStatus.SOLVED


def test_a_held_box_is_not_at_a_location() -> None:
    problem = replace(delivery_problem(), holding="box1")
    text = problem.text()
    assert "holding-box(uav0, box1)" in text
    assert "at(box1, Depot)" not in text
    assert "free(uav0)" not in text


SITES = {"Over": (0.0, 0.0, 20.0), "Far": (500.0, 0.0, 20.0), "b1": (10.0, 5.0, 0.0)}
LOT = {**SITES, "c1": (-10.0, 0.0, 0.0), "b2": (-10.0, 0.3, 0.0), "b3": (-10.0, -0.3, 0.0)}
"""A carrier c1 near Over with boxes b2 (declared) and b3 on it, and loose box b1."""
B1 = Stocked("b1", 5.0, "food")
C1 = Stocked("c1", 8.0, capacity=4)
ON_C1 = (C1, Stocked("b2", 5.0, "water", on="c1"), Stocked("b3", 6.0, "food", on="c1"))


@pytest.mark.parametrize(
    ("stock", "points", "loads"),
    [
        ([B1], SITES, (Load("b1", "food-box", "Over", 5.0),)),
        (
            [replace(B1, contents="medicine", kg=4.0)],
            SITES,
            (Load("b1", "medicine-box", "Over", 4.0),),
        ),
        ([replace(B1, contents="water")], SITES, (Load("b1", "box", "Over", 5.0),)),
        ([replace(B1, tag="b9")], SITES, ()),  # not declared as a point
        ([B1], {**SITES, "b1": (40.0, 0.0, 0.0)}, ()),  # no point near it
        # a loaded carrier weighs its boxes too, declared or not; b3 is not a point
        (
            [B1, *ON_C1],
            {k: v for k, v in LOT.items() if k != "b3"},
            (
                Load("b1", "food-box", "Over", 5.0),
                Load("c1", "carrier", "Over", 19.0, slots=2),
                Load("b2", "box", "Over", 5.0, on="c1"),
            ),
        ),
        (ON_C1, {k: v for k, v in LOT.items() if k != "c1"}, ()),  # its carrier is no point
    ],
)
def test_stocked_boxes_and_carriers_are_loads_at_the_nearest_point(
    stock: list[Stocked],
    points: dict[str, tuple[float, ...]],
    loads: tuple[Load, ...],
) -> None:
    assert stocked_loads(stock, points) == loads


LOADED = (
    Load("c1", "carrier", "Lot", 28.0, slots=0),
    *(Load(f"b{i}", "food-box", "Lot", 5.0, on="c1") for i in range(1, 5)),
)
"""A carrier of 8 kg with four boxes of 5 kg on it."""
CARRIER_GOAL = Node("c", NodeKind.GOAL, {}, action="at", goal_args=("b1", "Field"))
CARRIER_POINTS = {"Lot": (0.0, 0.0, 20.0), "Field": (200.0, 0.0, 20.0)}


def carrier_problem(lift: float) -> GoalProblem:
    """All four boxes to the field, lifting ``lift`` kg."""
    problem = goal_problem(CARRIER_GOAL, "uav0", (-100.0, 0.0, 20.0), CARRIER_POINTS, LOADED)
    goal = " and ".join(f"at(b{i}, Field)" for i in range(1, 5))
    return replace(problem, lift_capacity=lift, goal=goal)


def test_a_loaded_carrier_is_in_the_problem_with_its_boxes_on_it() -> None:
    text = carrier_problem(30.0).text().splitlines()
    assert "init at(c1, Lot), load(c1) = 28, slots(c1) = 0" in text
    assert "init on(b1, c1), weight(b1) = 5" in text
    held = replace(carrier_problem(30.0), holding="c1").text()
    assert "holding-carrier(uav0, c1)" in held and "at(c1, Lot)" not in held


@pytest.mark.parametrize(
    ("lift", "by_hook"),
    [
        (30.0, 0),  # the whole load lifts: the carrier flies with all four boxes
        (22.4, 2),  # 0.8 x 28 kg (a failed lift): two boxes fly on the hook, 18 kg on the carrier
        (6.0, 4),  # the empty carrier does not lift: every box flies on the hook
        (4.0, None),  # not even a box lifts: no plan
    ],
)
def test_a_carrier_too_heavy_for_the_lift_capacity_flies_with_fewer_boxes(
    lift: float, by_hook: int | None
) -> None:
    problem = carrier_problem(lift)
    request = PlanRequest(domain_text(), problem.text(), problem.control())
    result = TaskPlanner().plan(request, timeout=30.0)
    if by_hook is None:
        assert result.status is not PlanStatus.SOLVED
        return
    assert result.status is PlanStatus.SOLVED, result.reason
    actions = [o.label.strip("()").split()[0] for o in result.plan]
    attach = actions.index("attach-carrier") if "attach-carrier" in actions else len(actions)
    assert actions[:attach].count("take-from-carrier") == by_hook
    assert actions[:attach].count("drop-box") == by_hook
    assert "put-on-carrier" not in actions  # nothing taken off goes back on
    assert actions.count("drop-box") == 4
