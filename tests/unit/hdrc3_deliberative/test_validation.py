from __future__ import annotations

from hdrc3_deliberative.generators import LOGISTICS_DOMAIN, LogisticsSize, logistics_problem
from hdrc3_deliberative.result import Occurrence
from hdrc3_deliberative.validation import validate_pddl_plan


def test_validator_rejects_inapplicable_and_incomplete_plans() -> None:
    domain = LOGISTICS_DOMAIN.read_text()
    problem = logistics_problem(LogisticsSize(1, 1, 1), 1)
    wrong = (
        Occurrence(0, 1, "fly-airplane", ("apn1", "apt1", "apt1")),
        Occurrence(1, 2, "load-truck", ("obj1", "tru1", "apt1")),
    )
    outcome = validate_pddl_plan(domain, problem, wrong)
    assert not outcome.valid
    assert outcome.reason
