from __future__ import annotations

import pytest

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.generators import LOGISTICS_DOMAIN, LogisticsSize, logistics_problem
from hdrc3_deliberative.model import Equality, Literal
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
            "(define (domain d)\n  (:requirements :strips :durative-actions))",
            "2:26",
            "':durative-actions'",
        ),
        ("(define (domain d)\n  (:requirements :fluents))", "2:18", "accepted: :strips :typing"),
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
        ("(define (domain d)\n (:functions (f)))", "2:2", ":numeric-fluents"),
        ("(define (domain d)\n (:bogus))", "2:2", "unknown domain section ':bogus'"),
        ("(define (problem p))", "1:9", "expected '(domain ...)'"),
        ("(define (domain d) (:types a - (either b c)))", "1:32", "either"),
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
        ("(define (problem p) (:domain d) (:init (= (f) 1)))", ":numeric-fluents"),
        ("(define (problem p) (:domain d) (:goal (p) (q)))", "expected '(:goal CONDITION)'"),
    ],
)
def test_problem_errors(reader: PddlReader, text: str, message: str) -> None:
    with pytest.raises(PlanningInputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        reader.read_problem(text, "p.pddl")
