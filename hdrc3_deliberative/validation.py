"""Independent plan validation with unified-planning (PDDL tasks only).

The concurrent plan is linearised by start time (the planner guarantees that this order is a
valid sequential plan) and checked by unified-planning's SequentialPlanValidator on the
problem as read by unified-planning's own PDDL reader.

unified-planning 1.3's reader rejects ``(either ...)`` types (ZenoTravel's ``at``): they are
widened to ``object`` in the text handed to it. That only loosens the predicate signatures;
the action parameters, whose types decide which actions exist, are unchanged, so a plan
valid under the widened domain with the problem's typed objects is valid under the original.
"""

from __future__ import annotations

import os
import re
import tempfile
from dataclasses import dataclass

from hdrc3_deliberative.result import Occurrence

_EITHER = re.compile(r"\(\s*either\s[^()]*\)", re.IGNORECASE)


def widen_either(domain_text: str) -> str:
    """The domain text with every ``(either ...)`` type replaced by ``object``."""
    return _EITHER.sub("object", domain_text)


@dataclass(frozen=True)
class ValidationOutcome:
    """Verdict of the external validator."""

    valid: bool
    reason: str = ""


def validate_pddl_plan(
    domain_text: str, problem_text: str, plan: tuple[Occurrence, ...]
) -> ValidationOutcome:
    """Validate ``plan`` against PDDL domain and problem texts with unified-planning."""
    from unified_planning.engines import SequentialPlanValidator, ValidationResultStatus
    from unified_planning.io import PDDLReader
    from unified_planning.plans import ActionInstance, SequentialPlan
    from unified_planning.shortcuts import get_environment

    get_environment().credits_stream = None
    with tempfile.TemporaryDirectory() as tmp:
        domain_path = os.path.join(tmp, "domain.pddl")
        problem_path = os.path.join(tmp, "problem.pddl")
        with open(domain_path, "w") as f:
            f.write(widen_either(domain_text))
        with open(problem_path, "w") as f:
            f.write(problem_text)
        problem = PDDLReader().parse_problem(domain_path, problem_path)
    actions = []
    for occ in sorted(plan, key=lambda o: o.start):
        action = problem.action(occ.name)
        objects = [problem.object(arg) for arg in occ.args]
        actions.append(ActionInstance(action, objects))
    validator = SequentialPlanValidator(problem_kind=problem.kind)
    result = validator.validate(problem, SequentialPlan(actions))
    valid = result.status == ValidationResultStatus.VALID
    reason = (
        ""
        if valid
        else str(getattr(result, "reason", ""))
        + " "
        + str(getattr(result, "inapplicable_action", ""))
    )
    return ValidationOutcome(valid, reason.strip())
