from __future__ import annotations

import pytest

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.generators import LOGISTICS_DOMAIN, LogisticsSize, logistics_problem
from hdrc3_deliberative.model import (
    Atom,
    BinOp,
    Comparison,
    EffectTime,
    Equality,
    FuncTerm,
    Literal,
    Num,
    NumEffect,
    Param,
    Term,
)
from hdrc3_deliberative.pddl import PddlReader


@pytest.fixture(scope="module")
def reader() -> PddlReader:
    return PddlReader()


def test_reads_logistics_domain(reader: PddlReader) -> None:
    domain = reader.read_domain(LOGISTICS_DOMAIN.read_text(), "domain.pddl")
    assert domain.name == "logistics"
    assert [op.name for op in domain.operators] == [
        "load-truck",
        "load-airplane",
        "unload-truck",
        "unload-airplane",
        "drive-truck",
        "fly-airplane",
    ]
    assert domain.types["truck"] == "vehicle"
    assert domain.types["airport"] == "place"
    assert domain.predicates["in"] == ("package", "vehicle")
    drive = domain.operators[4]
    assert [p.name for p in drive.params] == ["?truck", "?loc-from", "?loc-to", "?city"]


def test_reads_generated_problem(reader: PddlReader) -> None:
    problem = reader.read_problem(logistics_problem(LogisticsSize(5, 2, 1), seed=3), "p.pddl")
    assert problem.domain == "logistics"
    assert len([o for o in problem.objects if o.type == "package"]) == 5
    assert len(problem.goal) == 5


def test_negative_preconditions_and_equality(reader: PddlReader) -> None:
    text = """(define (domain d) (:requirements :strips :negative-preconditions :equality)
      (:predicates (p ?x) (q ?x))
      (:action a :parameters (?x ?y) :precondition (and (p ?x) (not (q ?y)) (not (= ?x ?y)))
        :effect (and (q ?y) (not (p ?x)))))"""
    op = reader.read_domain(text).operators[0]
    assert Literal(op.pre[0].atom, True) == op.pre[0]
    assert isinstance(op.pre[1], Literal) and not op.pre[1].positive
    assert isinstance(op.pre[2], Equality) and not op.pre[2].positive


@pytest.mark.parametrize(
    ("text", "position", "message"),
    [
        (
            "(define (domain d)\n  (:requirements :strips :timed-initial-literals))",
            "2:26",
            "':timed-initial-literals'",
        ),
        ("(define (domain d)\n  (:requirements :adl))", "2:18", "accepted: :strips :typing"),
        ("(define (domain d)\n (:predicates (p ?x))", "2:22", "expected ')'"),
        ("(define (domain d)\n (:predicates (p ?x))))", "2:23", "unexpected ')'"),
        (
            "(define (domain d)\n (:action a :parameters () :precondition (or (p) (q))))",
            "2:42",
            "needs requirement :disjunctive-preconditions",
        ),
        (
            "(define (domain d)\n (:action a :parameters () :pre (p)))",
            "2:28",
            "expected ':parameters'",
        ),
        ("(define (domain d)\n (:functions (f) - obj))", "2:20", ":object-fluents"),
        (
            "(define (domain d)\n (:action a :parameters () :effect (scale-up (f) 2)))",
            "2:36",
            "scale-up",
        ),
        (
            "(define (domain d)\n (:action a :parameters () :effect (increase (f) #t)))",
            "2:36",
            ":continuous-effects",
        ),
        (
            "(define (domain d)\n (:durative-action a :parameters ()"
            " :duration (<= ?duration 3) :effect (p)))",
            "2:47",
            ":duration-inequalities",
        ),
        (
            "(define (domain d)\n (:durative-action a :parameters () :duration (= ?duration 3)"
            "\n  :condition (at end (p)) :effect (at end (q))))",
            "3:14",
            "'(at end ...)' conditions are not supported",
        ),
        (
            "(define (domain d)\n (:durative-action a :parameters () :duration (= ?duration 3)"
            "\n  :effect (p)))",
            "3:11",
            "expected '(at start ...)'",
        ),
        (
            "(define (domain d)\n (:action a :parameters () :effect (increase (f) ?duration)))",
            "2:50",
            "only defined in durative actions",
        ),
        ("(define (domain d)\n (:bogus))", "2:2", "unknown domain section ':bogus'"),
        ("(define (problem p))", "1:9", "expected '(domain ...)'"),
        ("(define (domain d) (:types a - (either)))", "1:32", "'(either TYPE TYPE ...)'"),
    ],
)
def test_domain_errors_have_position_and_expectation(
    reader: PddlReader, text: str, position: str, message: str
) -> None:
    with pytest.raises(PlanningInputError) as err:
        reader.read_domain(text, "bad.pddl")
    assert str(err.value).startswith(f"bad.pddl:{position}:"), str(err.value)
    assert message in str(err.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("(define (problem p) (:objects a))", "missing '(:domain NAME)'"),
        ("(define (problem p) (:domain d) (:init (p ?x)))", "must be ground"),
        ("(define (problem p) (:domain d) (:init (= (f) x)))", "expected a number"),
        ("(define (problem p) (:domain d) (:init (= f 1)))", "expected '(= (FUNCTION"),
        ("(define (problem p) (:domain d) (:goal (p) (q)))", "expected '(:goal CONDITION)'"),
    ],
)
def test_problem_errors(reader: PddlReader, text: str, message: str) -> None:
    with pytest.raises(PlanningInputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        reader.read_problem(text, "p.pddl")


ZENO_NUMERIC = """(define (domain zeno) (:requirements :typing :fluents)
  (:types aircraft person city - object)
  (:predicates (at ?x - (either person aircraft) ?c - city) (in ?p - person ?a - aircraft))
  (:functions (fuel ?a - aircraft) (distance ?c1 - city ?c2 - city) (total-fuel-used) - number)
  (:action fly :parameters (?a - aircraft ?c1 ?c2 - city)
    :precondition (and (at ?a ?c1) (>= (fuel ?a) (* 2 (distance ?c1 ?c2))) (not (= ?c1 ?c2)))
    :effect (and (not (at ?a ?c1)) (at ?a ?c2)
                 (increase (total-fuel-used) (* 2 (distance ?c1 ?c2)))
                 (decrease (fuel ?a) (* 2 (distance ?c1 ?c2))))))"""


def test_numeric_fluents_and_either_types(reader: PddlReader) -> None:
    domain = reader.read_domain(ZENO_NUMERIC)
    assert domain.predicates["at"] == ("(either aircraft person)", "city")
    assert domain.functions == {
        "fuel": ("aircraft",),
        "distance": ("city", "city"),
        "total-fuel-used": (),
    }
    fly = domain.operators[0]
    comparison = fly.pre[1]
    assert isinstance(comparison, Comparison) and comparison.op == ">="
    assert comparison.right == BinOp(
        "*", Num(2.0), FuncTerm(Atom("distance", (Term("?c1", True), Term("?c2", True))))
    )
    assert isinstance(fly.pre[2], Equality) and not fly.pre[2].positive
    ops = [(e.op, e.target.pred) for e in fly.effects if isinstance(e, NumEffect)]
    assert ops == [("+=", "total-fuel-used"), ("-=", "fuel")]
    problem = reader.read_problem(
        "(define (problem p) (:domain zeno) (:objects a - aircraft c d - city)"
        " (:init (at a c) (= (fuel a) 10) (= (distance c d) 3))"
        " (:goal (and (at a d) (not (< (fuel a) 2)))))"
    )
    assert [(a.pred, v) for a, v in problem.init_values] == [("fuel", 10.0), ("distance", 3.0)]
    assert isinstance(problem.goal[1], Comparison) and problem.goal[1].op == ">="


def test_durative_action(reader: PddlReader) -> None:
    text = """(define (domain d) (:requirements :durative-actions :fluents)
      (:predicates (p) (q) (r)) (:functions (speed))
      (:durative-action a :parameters ()
        :duration (= ?duration (/ 10 (speed)))
        :condition (and (at start (p)) (over all (r)))
        :effect (and (at start (not (p))) (at end (q)) (at end (increase (speed) ?duration)))))"""
    op = reader.read_domain(text).operators[0]
    speed = FuncTerm(Atom("speed", ()))
    assert op.duration == BinOp("/", Num(10.0), speed)
    assert op.pre == (Literal(Atom("p", ())),) and op.prevail == (Literal(Atom("r", ())),)
    times = [e.time for e in op.effects]
    assert times == [EffectTime.START, EffectTime.END, EffectTime.END]
    increase = op.effects[2]
    assert isinstance(increase, NumEffect) and increase.value == op.duration


def test_constants(reader: PddlReader) -> None:
    text = """(define (domain d) (:types c) (:constants home - c)
      (:predicates (at ?x - c)) (:action go :parameters (?x - c)
        :precondition (at home) :effect (and (not (at home)) (at ?x))))"""
    domain = reader.read_domain(text)
    assert domain.constants == (Param("home", "c"),)
    assert domain.operators[0].pre == (Literal(Atom("at", (Term("home"),))),)
