from __future__ import annotations

import itertools

import pytest

from hdrc3_deliberative.matching import FactIndex, join_plan, match
from hdrc3_deliberative.model import Operator
from hdrc3_deliberative.pddl import PddlReader

OBJECTS = {"place": ("a", "b", "c"), "robot": ("r1", "r2")}
FACTS = [
    ("at", ("r1", "a")),
    ("at", ("r2", "b")),
    ("road", ("a", "b")),
    ("road", ("b", "c")),
    ("road", ("c", "c")),
    ("road", ("b", "a")),
]


def operator(params: str, pre: str) -> Operator:
    domain = f"""(define (domain d) (:requirements :typing)
      (:types place robot)
      (:predicates (at ?r - robot ?p - place) (road ?x ?y - place))
      (:action act :parameters ({params}) :precondition {pre} :effect (and)))"""
    return PddlReader().read_domain(domain, "d.pddl").operators[0]


def brute_force(op: Operator, facts: set[tuple[str, tuple[str, ...]]]) -> set[tuple[str, ...]]:
    """Every typed binding whose positive preconditions are facts (the specification)."""
    names = [p.name for p in op.params]
    found = set()
    for values in itertools.product(*(OBJECTS[p.type] for p in op.params)):
        env = dict(zip(names, values, strict=True))
        atoms = [c.atom for c in op.pre if getattr(c, "positive", False)]  # type: ignore[attr-defined]
        if all((a.pred, tuple(env.get(t.name, t.name) for t in a.args)) in facts for a in atoms):
            found.add(values)
    return found


CASES = [
    ("?r - robot ?x ?y - place", "(and (at ?r ?x) (road ?x ?y))"),  # chain
    ("?x - place", "(road ?x ?x)"),  # a parameter twice in one atom
    ("?r - robot ?y - place", "(and (at ?r a) (road a ?y))"),  # constants
    ("?r - robot ?x ?y - place", "(at ?r ?x)"),  # ?y bound by no atom: every place
    ("?x ?y ?z - place", "(and (road ?x ?y) (road ?y ?z) (road ?z ?x))"),  # a cycle
    ("?r - robot ?x - place", "(and (at ?r ?x) (not (road ?x ?x)))"),  # negatives not joined
]


@pytest.mark.parametrize(("params", "pre"), CASES)
def test_match_equals_brute_force(params: str, pre: str) -> None:
    op = operator(params, pre)
    facts = FactIndex()
    for pred, args in FACTS:
        facts.add(pred, args)
    members = [frozenset(OBJECTS[p.type]) for p in op.params]
    objects = [OBJECTS[p.type] for p in op.params]
    ticks: list[None] = []
    found = match(join_plan(op, None), facts, members, objects, lambda: ticks.append(None))
    assert sorted(found) == sorted(brute_force(op, set(FACTS)))
    assert len(found) == len(set(found))
    assert ticks  # the deadline hook is called


def test_seeded_match_uses_only_the_seed_facts_for_the_seed_atom() -> None:
    op = operator("?r - robot ?x ?y - place", "(and (at ?r ?x) (road ?x ?y))")
    facts = FactIndex()
    for pred, args in FACTS:
        facts.add(pred, args)
    road = op.pre[1].atom  # type: ignore[union-attr]
    plan = join_plan(op, road)
    assert plan.steps[0].pred == "road"
    members = [frozenset(OBJECTS[p.type]) for p in op.params]
    objects = [OBJECTS[p.type] for p in op.params]
    found = match(plan, facts, members, objects, lambda: None, [("b", "c")])
    assert found == [("r2", "b", "c")]


def test_join_order_prefers_bound_atoms() -> None:
    op = operator("?r - robot ?x ?y - place", "(and (road ?x ?y) (at ?r a) (road a ?x))")
    plan = join_plan(op, None)
    # (at ?r a) and (road a ?x) have one bound argument each; the first wins, then the
    # atom sharing ?x, then the rest
    assert [s.pred for s in plan.steps] == ["at", "road", "road"]
    assert plan.free == ()
