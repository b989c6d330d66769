from __future__ import annotations

import random
from pathlib import Path

import pytest

from hdrc3_deliberative.control import ControlCompiler
from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.generators import (
    DEPOTS_CONTROL,
    DEPOTS_DOMAIN,
    DRIVERLOG_CONTROL,
    DRIVERLOG_DOMAIN,
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    ROVERS_CONTROL,
    ROVERS_DOMAIN,
    DepotsSize,
    DriverLogSize,
    LogisticsSize,
    RoversSize,
    depots_problem,
    driverlog_problem,
    logistics_problem,
    rovers_problem,
)
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.pruning import ControlProgram
from hdrc3_deliberative.result import PlanStatus
from hdrc3_deliberative.task import Task

DOMAIN = """domain grid
type cell
type special: cell
type robot
predicate at(r: robot, c: cell)
predicate adj(a: cell, b: cell)
predicate painted(c: cell)
operator move(r: robot, a: cell, b: cell)
  agent r
  pre at(r, a) and adj(a, b)
  effect [t'] not at(r, a), at(r, b)
end
operator paint(r: robot, c: cell)
  agent r
  pre at(r, c) and not painted(c)
  effect [t'] painted(c)
end
operator scrub(r: robot, c: cell)
  agent r
  pre at(r, c) and painted(c)
  effect [t'] not painted(c)
end
"""
PROBLEM = """problem p for grid
object c1, c2, c3: cell
object hot: special
object r1: robot
init at(r1, c1), adj(c1, c2), adj(c2, c1), adj(c2, c3), adj(c3, c2), adj(c2, hot), adj(hot, c3)
goal painted(c3)
"""


def setup(rules: str, problem: str = PROBLEM) -> tuple[Task, ControlProgram]:
    tp = TaskPlanner()
    d, p, spec = tp.read(PlanRequest(DOMAIN, problem, rules, control_source="c.tal"))
    task = tp.ground(d, p)
    return task, ControlCompiler(task, spec).compile()


def state(task: Task, *atoms: str) -> int:
    bits = 0
    for text in atoms:
        pred, rest = text.rstrip(")").split("(")
        bits |= task.mask_of((pred, tuple(a.strip() for a in rest.split(","))))
    return bits


def op(task: Task, label: str):  # type: ignore[no-untyped-def]
    return next(o for o in task.ops if o.label == label)


SHAPES = {
    # a change to true, explicit in the antecedent: add-triggered
    "add": "rule r: forall c: cell . [t] not painted(c) and [t+1] painted(c) -> goal(painted(c))",
    # a change to false, explicit: delete-triggered
    "del": "rule r: forall c: cell . [t] painted(c) and [t+1] not painted(c) -> false",
    # persistence form [t] p ... -> [t+1] p: delete-triggered
    "keep": "rule r: forall c: cell . [t] painted(c) and goal(painted(c)) -> [t+1] painted(c)",
    # negative persistence form: add-triggered
    "keep-off": "rule r: forall c: cell . [t] not painted(c) and not goal(painted(c))"
    " -> [t+1] not painted(c)",
}


@pytest.mark.parametrize(
    ("shape", "on_add"), [("add", True), ("del", False), ("keep", False), ("keep-off", True)]
)
def test_triggered_shapes(shape: str, on_add: bool) -> None:
    task, program = setup(SHAPES[shape])
    rule = program.rules[0]
    assert (
        rule.trigger is not None
        and rule.trigger.on_add is on_add
        and rule.trigger.pred == "painted"
    )
    paint_c1 = op(task, "(paint r1 c1)")
    paint_c3 = op(task, "(paint r1 c3)")
    before = state(task, "at(r1, c1)")
    after_c1 = before | paint_c1.add
    if on_add:  # painting a cell that is not a goal violates both add-shapes
        assert program.step_violation(paint_c1, before, after_c1) == "r"
        assert program.step_violation(paint_c3, before, before | paint_c3.add) is None
    else:  # scrubbing a painted (goal) cell violates
        scrub = op(task, "(scrub r1 c3)")
        painted = state(task, "at(r1, c3)", "painted(c3)")
        assert program.step_violation(scrub, painted, painted & ~scrub.delete) == "r"
    # moving does not touch 'painted': the rule is not among move's incremental constraints
    assert program.incremental_rules("move") == ()


def test_untriggered_state_rule_initial_and_incremental() -> None:
    rules = "rule avoid: forall r: robot, c: cell . special(c) -> not at(r, c)"
    task, program = setup(rules)
    assert program.rules[0].trigger is None
    start = state(task, "at(r1, c1)")
    assert program.initial_violation(start) is None
    move = op(task, "(move r1 c2 hot)")
    before = state(task, "at(r1, c2)")
    assert program.step_violation(move, before, (before & ~move.delete) | move.add) == "avoid"
    assert program.initial_violation(state(task, "at(r1, hot)")) == "avoid"


def test_final_rule_and_planning_outcomes() -> None:
    # the planner must respect the always-rule (no detour via hot) and the final rule
    tp = TaskPlanner()
    rules = (
        "rule avoid: forall r: robot, c: cell . special(c) -> not at(r, c)\n"
        "final home: at(r1, c2)\n"
    )
    result = tp.plan(PlanRequest(DOMAIN, PROBLEM, rules), timeout=5)
    assert result.status is PlanStatus.SOLVED
    labels = [o.label for o in result.plan]
    assert "(move r1 c2 hot)" not in labels
    assert labels[-1] == "(move r1 c3 c2)"
    # a start inside the forbidden cell: the initial constraint proves unsolvability
    bad_start = PROBLEM.replace("init at(r1, c1)", "init at(r1, hot)")
    result = tp.plan(PlanRequest(DOMAIN, bad_start, rules), timeout=5)
    assert result.status is PlanStatus.UNSOLVABLE_PROVEN
    assert "avoid" in result.reason


def test_exists_forall_equality_and_goal_modality() -> None:
    rules = (
        "rule r: forall c: cell . [t] not painted(c) and [t+1] painted(c) ->\n"
        "  exists d: cell . adj(c, d) and d != c and (forall e: cell . goal(painted(e)) -> e = c)"
    )
    task, program = setup(rules)
    paint_c3 = op(task, "(paint r1 c3)")
    paint_c1 = op(task, "(paint r1 c1)")
    s = state(task, "at(r1, c1)")
    assert program.step_violation(paint_c3, s, s | paint_c3.add) is None
    assert program.step_violation(paint_c1, s, s | paint_c1.add) == "r"


NESTED = (
    "rule r: forall c: cell . [t] not painted(c) and [t+1] painted(c) ->\n"
    "  exists d: cell, e: cell . adj(c, d) and adj(d, e) and painted(e)"
)


@pytest.mark.parametrize(
    ("painted", "target", "allowed"),
    [
        ((), "c1", False),  # nothing painted two steps away
        (("c3",), "c1", True),  # c1 -> c2 -> c3
        (("hot",), "c1", True),  # c1 -> c2 -> hot
        (("c1",), "c3", True),  # c3 -> c2 -> c1
        (("c2",), "hot", True),  # hot -> c3 -> c2
        (("c3",), "hot", False),  # hot's only neighbour is c3, whose only neighbour is c2
    ],
)
def test_quantifier_whose_guard_binds_some_variables(
    painted: tuple[str, ...], target: str, allowed: bool
) -> None:
    """``exists d, e`` with guard ``adj(c, d)`` binds d first, then e under ``adj(d, e)``."""
    task, program = setup(NESTED)
    paint = op(task, f"(paint r1 {target})")
    s = state(task, f"at(r1, {target})", *(f"painted({c})" for c in painted))
    expected = None if allowed else "r"
    assert program.step_violation(paint, s, s | paint.add) == expected


@pytest.mark.parametrize(
    ("rules", "message"),
    [
        ("rule r: forall c: cell . [t] paint(c)", "undefined predicate 'paint'"),
        ("rule r: forall c: cel . [t] painted(c)", "undefined type 'cel'"),
        ("rule r: painted(c9)", "undefined object or variable 'c9'"),
        ("rule r: at(r1)", "takes 2 arguments, got 1"),
        ("prefer fly", "undefined operator 'fly'"),
        ("agents drone", "undefined agent type 'drone'"),
    ],
)
def test_control_errors(rules: str, message: str) -> None:
    with pytest.raises(PlanningInputError, match=message):
        setup(rules)


def test_control_error_position() -> None:
    with pytest.raises(PlanningInputError) as err:
        setup("\nrule r: forall c: cell .\n  [t] paint(c)")
    assert str(err.value).startswith("c.tal:3:7:")


@pytest.mark.parametrize(
    ("domain", "control", "problem"),
    [
        (LOGISTICS_DOMAIN, LOGISTICS_CONTROL, logistics_problem(LogisticsSize(4, 2, 1), seed=5)),
        (DEPOTS_DOMAIN, DEPOTS_CONTROL, depots_problem(DepotsSize(1, 2, 2, 4, 3, 6), seed=3)),
        (DRIVERLOG_DOMAIN, DRIVERLOG_CONTROL, driverlog_problem(DriverLogSize(5, 2, 4, 2), 3)),
        (ROVERS_DOMAIN, ROVERS_CONTROL, rovers_problem(RoversSize(2, 6, 3, 2, 5), seed=3)),
    ],
)
def test_incremental_constraints_agree_with_full_evaluation(
    domain: Path, control: Path, problem: str
) -> None:
    """Triggered (incremental) checks equal the whole rule evaluated on each transition."""
    tp = TaskPlanner()
    d, p, spec = tp.read(PlanRequest(domain.read_text(), problem, control.read_text()))
    task = tp.ground(d, p)
    program = ControlCompiler(task, spec).compile()
    assert all(rule.trigger is not None for rule in program.rules)
    rng = random.Random(7)
    checked = 0
    bits = task.init_bits
    for _ in range(150):
        applicable = [o for o in task.ops if bits & o.pre_pos == o.pre_pos and not bits & o.pre_neg]
        for candidate in applicable:
            after = (bits & ~candidate.delete) | candidate.add
            incremental = program.step_violation(candidate, bits, after)
            full = next((r.name for r in program.rules if not r.full(bits, after)), None)
            assert incremental == full, candidate.label
            checked += 1
        chosen = rng.choice(applicable)
        bits = (bits & ~chosen.delete) | chosen.add
    assert checked > 500


NUMERIC_DOMAIN = """domain bots
type cell
type robot
predicate at(r: robot, c: cell)
predicate adj(a: cell, b: cell)
function battery(r: robot)
function cost(c: cell)
operator move(r: robot, a: cell, b: cell)
  agent r
  pre at(r, a) and adj(a, b)
  effect [t'] not at(r, a), at(r, b), battery(r) -= cost(b)
end
"""
NUMERIC_PROBLEM = """problem p for bots
object c1, c2, c3: cell
object r1: robot
init at(r1, c1), adj(c1, c2), adj(c2, c3), adj(c2, c1), adj(c3, c2)
init battery(r1) = 5, cost(c1) = 1, cost(c2) = 2, cost(c3) = 4
goal at(r1, c3)
"""
ENTER = "rule r: forall r: robot, c: cell . [t] not at(r, c) and [t+1] at(r, c) -> "


def numeric_setup(rules: str) -> tuple[Task, ControlProgram]:
    tp = TaskPlanner()
    request = PlanRequest(NUMERIC_DOMAIN, NUMERIC_PROBLEM, rules, control_source="c.tal")
    d, p, spec = tp.read(request)
    task = tp.ground(d, p)
    return task, ControlCompiler(task, spec).compile()


@pytest.mark.parametrize(
    ("rules", "battery", "label", "violated", "violated_when_charged"),
    [
        # untriggered rule on a function: checked for operators that change it, at t and t+1
        ("rule r: forall r: robot . battery(r) >= 1", 5.0, "(move r1 c1 c2)", False, False),
        ("rule r: forall r: robot . battery(r) >= 1", 2.0, "(move r1 c1 c2)", True, False),
        ("rule r: forall r: robot . [t+1] battery(r) > 3", 5.0, "(move r1 c1 c2)", True, False),
        # triggered rule, static function and arithmetic in the consequent
        (ENTER + "battery(r) >= cost(c) + 1", 3.0, "(move r1 c1 c2)", False, False),
        (ENTER + "battery(r) >= cost(c) + 1", 2.0, "(move r1 c1 c2)", True, False),
        (ENTER + "[t+1] battery(r) = 1", 3.0, "(move r1 c1 c2)", False, True),
        (ENTER + "battery(r) * 2 < cost(c) / 0", 3.0, "(move r1 c1 c2)", False, False),  # x/0: inf
    ],
)
def test_numeric_comparisons_in_rules(
    rules: str, battery: float, label: str, violated: bool, violated_when_charged: bool
) -> None:
    """Verdicts at (battery, battery - 2), then at (100, 98) on the same boolean states."""
    task, program = numeric_setup(rules)
    move = op(task, label)
    bits = state(task, "at(r1, c1)")
    before = (battery,)
    after = tuple(before[0] - 2.0 for _ in before)  # cost(c2) = 2
    verdict = program.step_violation(move, bits, (bits & ~move.delete) | move.add, before, after)
    assert (verdict == "r") is violated
    # the same boolean states with other numbers: numeric verdicts are not memoised
    other = program.step_violation(move, bits, (bits & ~move.delete) | move.add, (100.0,), (98.0,))
    assert (other == "r") is violated_when_charged


@pytest.mark.parametrize(
    ("rules", "status", "length"),
    [
        ("", PlanStatus.SOLVED, 2),
        # c1 -> c2 -> c3 costs 2 + 4 = 6 > 5: the rule proves there is no plan
        ("rule r: forall r: robot . battery(r) >= 0", PlanStatus.UNSOLVABLE_PROVEN, 0),
        ("final f: forall r: robot . battery(r) + 2 > 0", PlanStatus.SOLVED, 2),  # ends at -1
        (
            "rule b: forall r: robot . battery(r) + 10 >= 0\n"
            "final f: forall r: robot . battery(r) > 0",
            PlanStatus.UNSOLVABLE_PROVEN,
            0,
        ),
    ],
)
def test_numeric_rules_decide_planning(rules: str, status: PlanStatus, length: int) -> None:
    result = TaskPlanner().plan(PlanRequest(NUMERIC_DOMAIN, NUMERIC_PROBLEM, rules), timeout=20)
    assert result.status is status, result.reason
    assert len(result.plan) == length


@pytest.mark.parametrize(
    ("rules", "message"),
    [
        ("rule r: forall r: robot . charge(r) > 1", "1:27: undefined function 'charge'"),
        ("rule r: forall r: robot . battery(r, r) > 1", "takes 1 arguments, got 2"),
        ("rule r: forall r: robot . battery(q) > 1", "undefined object or variable 'q'"),
    ],
)
def test_numeric_comparison_errors(rules: str, message: str) -> None:
    with pytest.raises(PlanningInputError, match=message):
        numeric_setup(rules)
