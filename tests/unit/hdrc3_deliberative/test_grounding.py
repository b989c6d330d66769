from __future__ import annotations

import gc
import itertools
import math
from pathlib import Path

import pytest

from hdrc3_deliberative.errors import GroundingTimeout, PlanningInputError
from hdrc3_deliberative.generators import (
    BLOCKS_DOMAIN,
    DEPOTS_DOMAIN,
    DRIVERLOG_DOMAIN,
    LOGISTICS_DOMAIN,
    ROVERS_DOMAIN,
    SATELLITE_DOMAIN,
    UAV_DOMAIN,
    UAV_SCENARIO,
    ZENOTRAVEL_DOMAIN,
    DepotsSize,
    DriverLogSize,
    LogisticsSize,
    RoversSize,
    SatelliteSize,
    ZenoSize,
    blocks_problem,
    depots_problem,
    driverlog_problem,
    logistics_problem,
    rovers_problem,
    satellite_problem,
    zenotravel_problem,
)
from hdrc3_deliberative.grounding import Grounder, paused_gc
from hdrc3_deliberative.model import AtomEffect, Equality, Literal
from hdrc3_deliberative.motion_plan_info import StraightLineMotionPlanInfo
from hdrc3_deliberative.pddl import PddlReader
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_deliberative.task import Task

MINI = """domain mini
type place
type robot
predicate at(r: robot, p: place)
predicate linked(a: place, b: place)
function battery(r: robot)
operator go(r: robot, a: place, b: place)
  agent r
  duration 2
  pre at(r, a) and linked(a, b) and battery(r) >= 1
  effect [t'] not at(r, a), at(r, b), battery(r) -= 1
end
"""


def ground(domain: str, problem: str, planner: TaskPlanner | None = None) -> Task:
    tp = planner or TaskPlanner()
    d, p, _ = tp.read(PlanRequest(domain, problem, "", "d.tal", "p.tal"))
    return tp.ground(d, p)


def test_static_predicates_and_reachability_prune_instances() -> None:
    task = ground(
        MINI,
        "problem p for mini\nobject a, b, c, d: place\nobject r1: robot\n"
        "init at(r1, a), linked(a, b), linked(b, a), linked(c, d), battery(r1) = 3\n"
        "goal at(r1, b)\n",
    )
    labels = sorted(op.label for op in task.ops)
    # c -> d is linked but r1 can never reach c
    assert labels == ["(go r1 a b)", "(go r1 b a)"]
    assert "linked" in task.static_preds
    assert task.ops[0].duration == 2.0
    assert task.init_nums == (3.0,)


def test_logistics_drive_only_within_city() -> None:
    size = LogisticsSize(4, 3, 1, locations_per_city=3)
    task = ground(LOGISTICS_DOMAIN.read_text(), logistics_problem(size, seed=1))
    drives = [op for op in task.ops if op.name == "drive-truck"]
    # one truck per city, 3 places per city: 3 * 3 ordered pairs (including staying)
    assert len(drives) == size.cities * 9
    for op in drives:
        assert op.args[1].split("-")[0].removeprefix("pos").removeprefix("apt")[0] == op.args[3][3]


def test_flights_come_from_motion_plan_info() -> None:
    task = ground(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text())
    fly = next(op for op in task.ops if op.label == "(fly-to heli1 supply1 body1)")
    expected = math.dist((0, 0, 0), (320, 140, 0)) / 10.0 + 5.0
    assert fly.duration == pytest.approx(expected)
    short_range = TaskPlanner(StraightLineMotionPlanInfo(max_range=200.0))
    limited = ground(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text(), short_range)
    assert not any(op.label == "(fly-to heli1 supply1 body1)" for op in limited.ops)
    assert any(op.label == "(fly-to heli1 supply1 carrierdepot1)" for op in limited.ops)


def test_agents_are_exclusive_tokens() -> None:
    task = ground(UAV_DOMAIN.read_text(), UAV_SCENARIO.read_text())
    a = next(op for op in task.ops if op.label == "(pick-up-box heli1 food1 supply1)")
    b = next(op for op in task.ops if op.label == "(fly-to heli1 supply1 body1)")
    c = next(op for op in task.ops if op.label == "(fly-to heli2 supply1 body1)")
    assert a.writes & b.writes  # same agent
    assert not (b.writes & c.writes)


@pytest.mark.parametrize(
    ("domain", "problem", "message"),
    [
        (
            MINI.replace("at(r, a) and", "att(r, a) and"),
            "problem p for mini",
            "undefined predicate 'att'",
        ),
        (
            MINI.replace("r: robot, a: place", "r: robot, a: plaice"),
            "problem p for mini",
            "undefined type 'plaice'",
        ),
        (
            MINI,
            "problem p for mini\nobject r: robot\ninit at(r, nowhere)",
            "undefined object or variable 'nowhere'",
        ),
        (MINI, "problem p for mini\nobject r: robot\ninit at(r)", "takes 2 arguments, got 1"),
        (MINI, "problem p for other", "not 'mini'"),
        (MINI, "problem p for mini\nobject x: blob", "undefined type 'blob'"),
        (MINI.replace("type robot", "type robot: machine"), "problem p for mini", "'machine'"),
        (
            MINI,
            "problem p for mini\nobject a: place\nobject r: robot\ninit at(r, a), linked(a, a)",
            "no initial value",
        ),
        (
            MINI.replace("effect [t']", "effect [t'] speed(r) := 1,"),
            "problem p for mini",
            "undefined function 'speed'",
        ),
        (
            MINI.replace("agent r", "agent q"),
            "problem p for mini",
            "agent 'q' of 'go' is not a parameter",
        ),
    ],
)
def test_undefined_names_are_reported(domain: str, problem: str, message: str) -> None:
    with pytest.raises(PlanningInputError, match=message):
        ground(domain, problem)


def test_undefined_predicate_error_has_position() -> None:
    with pytest.raises(PlanningInputError) as err:
        ground(MINI.replace("at(r, a) and", "att(r, a) and"), "problem p for mini")
    assert str(err.value).startswith("d.tal:10:7:")


def test_flight_needs_positions() -> None:
    problem = UAV_SCENARIO.read_text().replace(
        "object body4: body @ (-150, 300, 0)", "object body4: body"
    )
    with pytest.raises(PlanningInputError, match="'body4' has no position"):
        ground(UAV_DOMAIN.read_text(), problem)


def test_grounder_rejects_nonpositive_duration() -> None:
    tp = TaskPlanner()
    d, p, _ = tp.read(
        PlanRequest(
            MINI.replace("duration 2", "duration 0"),
            "problem p for mini\nobject a, b: place\nobject r: robot\n"
            "init at(r, a), linked(a, b), battery(r) = 1",
        )
    )
    with pytest.raises(PlanningInputError, match="non-positive duration"):
        Grounder(d, p).ground()


def test_grounding_stops_at_the_deadline() -> None:
    """A clock past the deadline interrupts grounding; the planner reports TIMEOUT."""
    reader = PddlReader()
    domain = reader.read_domain(LOGISTICS_DOMAIN.read_text())
    problem = reader.read_problem(logistics_problem(LogisticsSize(30, 10, 3), 1))
    ticks = iter(range(10**9))
    with pytest.raises(GroundingTimeout):
        Grounder(domain, problem, deadline=3.0, clock=lambda: float(next(ticks))).ground()
    full = Grounder(domain, problem, deadline=100.0, clock=lambda: 0.0).ground()
    assert len(full.ops) > 1000
    text = logistics_problem(LogisticsSize(30, 10, 3), 1)
    result = TaskPlanner().plan(PlanRequest(LOGISTICS_DOMAIN.read_text(), text), timeout=0.0)
    assert result.status is PlanStatus.TIMEOUT and "grounding" in result.reason


def _naive_reachable(domain_text: str, problem_text: str) -> set[tuple[str, tuple[str, ...]]]:
    """Reference: relaxed reachability over the cross product of typed objects, to fixpoint."""
    tp = TaskPlanner()
    d, p, _ = tp.read(PlanRequest(domain_text, problem_text))
    g = Grounder(d, p)
    reached = set(g.init_fluents)
    found: set[tuple[str, tuple[str, ...]]] = set()
    grew = True
    while grew:
        grew = False
        for op in d.operators:
            pools = [g.types.objects.get(param.type, ()) for param in op.params]
            for values in itertools.product(*pools):
                env = dict(zip((param.name for param in op.params), values, strict=True))

                def sub(name: str, env: dict[str, str] = env) -> str:
                    return env.get(name, name)

                ok = True
                for c in op.pre:
                    if isinstance(c, Equality):
                        ok = (sub(c.left.name) == sub(c.right.name)) == c.positive
                    elif isinstance(c, Literal):
                        atom = (c.atom.pred, tuple(sub(t.name) for t in c.atom.args))
                        if c.atom.pred in g.static_preds:
                            ok = (atom in g.static_facts) == c.positive
                        elif c.positive:
                            ok = atom in reached
                    if not ok:
                        break
                if not ok:
                    continue
                found.add((op.name, values))
                for e in op.effects:
                    if isinstance(e, AtomEffect) and e.literal.positive:
                        atom = (
                            e.literal.atom.pred,
                            tuple(sub(t.name) for t in e.literal.atom.args),
                        )
                        if atom not in reached:
                            reached.add(atom)
                            grew = True
    return found


@pytest.mark.parametrize(
    ("domain", "problem"),
    [
        (LOGISTICS_DOMAIN, logistics_problem(LogisticsSize(4, 2, 1), 1)),
        (BLOCKS_DOMAIN, blocks_problem(4, 1)),
        (DEPOTS_DOMAIN, depots_problem(DepotsSize(1, 2, 2, 3, 3, 6), 1)),
        (DRIVERLOG_DOMAIN, driverlog_problem(DriverLogSize(3, 1, 2, 1), 1)),
        (SATELLITE_DOMAIN, satellite_problem(SatelliteSize(1, 1, 3, 3, 3), 1)),
        (ROVERS_DOMAIN, rovers_problem(RoversSize(1, 4, 2, 1, 3), 1)),
        (ZENOTRAVEL_DOMAIN, zenotravel_problem(ZenoSize(3, 1, 2), 1)),
    ],
)
def test_reachability_grounds_exactly_the_naively_reachable_instances(
    domain: Path, problem: str
) -> None:
    """The join-based grounder finds the same instances as the cross product to fixpoint."""
    text = domain.read_text()
    task = ground(text, problem)
    assert {(op.name, op.args) for op in task.ops} == _naive_reachable(text, problem)
    for op in task.ops:
        bits = [b for b in range(op.pre_pos.bit_length()) if op.pre_pos >> b & 1]
        assert op.pre_bits == tuple(bits)


CONSTS = """(define (domain consts)
  (:requirements :typing :negative-preconditions :equality)
  (:types place robot)
  (:constants home - place)
  (:predicates (at ?r - robot ?p - place) (road ?a - place ?b - place)
               (closed ?p - place) (visited ?p - place))
  (:action go
    :parameters (?r - robot ?a - place ?b - place)
    :precondition (and (at ?r ?a) (road ?a ?b) (not (= ?a ?b)) (not (closed ?b)))
    :effect (and (not (at ?r ?a)) (at ?r ?b) (visited ?b)))
  (:action home-again
    :parameters (?r - robot ?a - place)
    :precondition (and (at ?r ?a) (visited home) (road ?a home))
    :effect (and (not (at ?r ?a)) (at ?r home))))
"""


def test_equalities_negative_statics_and_constants_filter_instances() -> None:
    problem = """(define (problem p) (:domain consts)
  (:objects a b c d - place r - robot)
  (:init (at r a) (road a a) (road a b) (road b home) (road home c) (road c d)
         (road a c) (closed c))
  (:goal (at r home)))
"""
    task = ground(CONSTS, problem)
    labels = sorted(op.label for op in task.ops)
    # go a a: equal places; go a c, go home c: c is closed, so d is unreachable;
    # home-again needs the constant's visited(home) and road(?a, home): only from b
    assert labels == ["(go r a b)", "(go r b home)", "(home-again r b)"]
    assert labels == sorted(f"({n} {' '.join(a)})" for n, a in _naive_reachable(CONSTS, problem))


def test_unreachable_operators_are_not_grounded() -> None:
    """An operator whose precondition needs an atom no action adds has no instance."""
    domain = CONSTS.replace("(visited ?b)))", "))")  # nothing adds visited any more
    problem = """(define (problem p) (:domain consts)
  (:objects a b - place r - robot)
  (:init (at r a) (road a b) (road b home))
  (:goal (at r home)))
"""
    task = ground(domain, problem)
    assert sorted(op.label for op in task.ops) == ["(go r a b)", "(go r b home)"]


@pytest.mark.parametrize("enabled", [True, False])
def test_paused_gc_restores_the_collector_state(enabled: bool) -> None:
    was = gc.isenabled()
    try:
        (gc.enable if enabled else gc.disable)()
        with paused_gc():
            assert not gc.isenabled()
        assert gc.isenabled() is enabled
        with pytest.raises(RuntimeError), paused_gc():
            raise RuntimeError
        assert gc.isenabled() is enabled
    finally:
        (gc.enable if was else gc.disable)()
