from __future__ import annotations

import pytest

from hdrc3_deliberative.control import ControlCompiler
from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_deliberative.steps import MapDistances

# a one-way ring a -> b -> c -> d -> a with a shortcut a -> c, and an island e -> f
EDGES = [("a", "b"), ("b", "c"), ("c", "d"), ("d", "a"), ("a", "c"), ("e", "f")]


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (("a", "c", "d"), True),  # a -> c -> d: 2 links, through the shortcut
        (("a", "b", "d"), False),  # a -> b -> c -> d: 3 links
        (("b", "c", "a"), True),
        (("c", "b", "a"), False),  # no edge c -> b
        (("a", "b", "b"), True),
        (("a", "c", "f"), False),  # f is unreachable from a
        (("e", "f", "f"), True),
    ],
)
def test_step_is_an_edge_on_a_shortest_path(args: tuple[str, ...], expected: bool) -> None:
    assert MapDistances(EDGES).step(args) is expected


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (("a", "c", "d"), True),  # 1 link < 2 links
        (("a", "d", "c"), False),
        (("a", "b", "c"), False),  # equal distances
        (("a", "a", "b"), True),  # being there is nearest
        (("a", "d", "f"), True),  # reachable beats unreachable
        (("a", "f", "d"), False),
    ],
)
def test_nearer_compares_link_counts(args: tuple[str, ...], expected: bool) -> None:
    assert MapDistances(EDGES).nearer(args) is expected


def test_maps_are_separate_per_key() -> None:
    edges = [("r1", "a", "b"), ("r1", "b", "c"), ("r2", "a", "c")]
    maps = MapDistances(edges)
    assert maps.between(("r1",), "a", "c") == 2
    assert maps.between(("r2",), "a", "c") == 1
    assert maps.step(("r1", "a", "b", "c"))
    assert not maps.step(("r2", "a", "b", "c"))


DOMAIN = """domain grid
type cell
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
"""
# c1 - c2 - c3 - c4 in a line, with a dead end c2 - x
PROBLEM = """problem p for grid
object c1, c2, c3, c4, x: cell
object r1: robot
init at(r1, c1)
init adj(c1, c2), adj(c2, c1), adj(c2, c3), adj(c3, c2), adj(c3, c4), adj(c4, c3)
init adj(c2, x), adj(x, c2)
goal painted(c4)
"""
TOWARD_GOAL = """step toward by adj
rule only-toward-the-goal:
  forall r: robot, a: cell, b: cell . [t] at(r, a) and not at(r, b) and [t+1] at(r, b) ->
    exists c: cell . goal(painted(c)) and toward(a, b, c)
"""


def test_step_rule_steers_the_search_without_backtracking() -> None:
    result = TaskPlanner().plan(PlanRequest(DOMAIN, PROBLEM, TOWARD_GOAL), timeout=10)
    assert result.status is PlanStatus.SOLVED
    assert [o.name for o in result.plan] == ["move", "move", "move", "paint"]
    assert result.stats.nodes_expanded == len(result.plan)


def test_step_rule_prunes_moves_away_from_the_goal() -> None:
    tp = TaskPlanner()
    d, p, spec = tp.read(PlanRequest(DOMAIN, PROBLEM, TOWARD_GOAL))
    task = tp.ground(d, p)
    program = ControlCompiler(task, spec).compile()
    at_c2 = (task.init_bits & ~task.mask_of(("at", ("r1", "c1")))) | task.mask_of(
        ("at", ("r1", "c2"))
    )
    verdicts = {}
    for op in task.ops:
        if op.name == "move" and op.args[1] == "c2":
            after = (at_c2 & ~op.delete) | op.add
            verdicts[op.args[2]] = program.step_violation(op, at_c2, after)
    assert verdicts == {"c1": "only-toward-the-goal", "x": "only-toward-the-goal", "c3": None}


@pytest.mark.parametrize(
    ("rules", "message"),
    [
        ("step toward by road", "'step toward by road': undefined predicate 'road'"),
        ("nearer n by at", "'at' is changed by an action"),
        ("step s by painted", "'painted' is changed by an action"),
        ("step adj by adj", "'adj' is already a predicate or type"),
        ("nearer cell by adj", "'cell' is already a predicate or type"),
        ("step s by adj\nnearer s by adj", "'s' is already a predicate or type"),
        ("step s by adj\nrule r: s(c1, c2)", "takes 3 arguments, got 2"),
    ],
)
def test_map_relation_errors(rules: str, message: str) -> None:
    tp = TaskPlanner()
    d, p, spec = tp.read(PlanRequest(DOMAIN, PROBLEM, rules, control_source="c.tal"))
    with pytest.raises(PlanningInputError, match=message):
        ControlCompiler(tp.ground(d, p), spec).compile()


STATIC_UNARY_DOMAIN = DOMAIN.replace(
    "predicate painted(c: cell)", "predicate painted(c: cell)\npredicate dock(c: cell)"
)


def test_map_relation_needs_an_edge_predicate_and_names_its_line() -> None:
    tp = TaskPlanner()
    request = PlanRequest(
        STATIC_UNARY_DOMAIN, PROBLEM, "\n\nstep s by dock", control_source="c.tal"
    )
    d, p, spec = tp.read(request)
    with pytest.raises(PlanningInputError, match="must end with two arguments of one type") as err:
        ControlCompiler(tp.ground(d, p), spec).compile()
    assert str(err.value).startswith("c.tal:3:1:")
