"""`hdrc3 plan`: run TALplanner on a domain and problem (PDDL or the TAL language)."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from rich.console import Console

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner, is_pddl
from hdrc3_deliberative.result import PlanningProgress, PlanStatus
from hdrc3_deliberative.search import CycleCheck
from hdrc3_deliberative.tst_export import plan_to_tst

EXIT_CODES = {
    PlanStatus.SOLVED: 0,
    PlanStatus.UNSOLVABLE_PROVEN: 2,
    PlanStatus.TIMEOUT: 3,
    PlanStatus.INVALID_INPUT: 4,
}


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``plan`` subcommand."""
    parser = subparsers.add_parser(
        "plan",
        help="plan with TALplanner (PDDL or TAL domain language)",
        description=(
            "Plan with the concurrent TALplanner. Exit codes: 0 solved, 2 unsolvable, "
            "3 timeout, 4 invalid input."
        ),
    )
    parser.add_argument("domain", type=Path, help="domain file (.pddl or TAL language)")
    parser.add_argument("problem", type=Path, help="problem file (.pddl or TAL language)")
    parser.add_argument("--control", type=Path, default=None, help="TAL control-rule file")
    parser.add_argument("--timeout", type=float, default=30.0, help="planning budget in seconds")
    parser.add_argument("--sequential", action="store_true", help="plan sequentially")
    parser.add_argument(
        "--cycle-check",
        choices=[c.value for c in CycleCheck],
        default=CycleCheck.PATH_CLOSED.value,
        help="visited states that prune: along the path (Algorithm 3), plus exact duplicates "
        "(default, loses no plan), better-or-equal across branches (may lose plans), none",
    )
    parser.add_argument("--tst", action="store_true", help="also print the plan as a TST (JSON)")
    parser.add_argument(
        "--validate",
        action="store_true",
        help="validate the plan with unified-planning (PDDL inputs only)",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Plan, print the IPC plan and statistics, return the status exit code."""
    if not math.isfinite(args.timeout) or args.timeout <= 0:
        print(
            f"hdrc3 plan: error: --timeout must be a positive number, got {args.timeout}",
            file=sys.stderr,
        )
        return EXIT_CODES[PlanStatus.INVALID_INPUT]
    try:
        request = PlanRequest.from_files(args.domain, args.problem, args.control)
    except PlanningInputError as exc:
        print(f"hdrc3 plan: error: {exc}", file=sys.stderr)
        return EXIT_CODES[PlanStatus.INVALID_INPUT]
    console = Console(stderr=True)
    with console.status("planning") as status:  # drawn on a terminal only

        def progress(report: PlanningProgress) -> None:
            status.update(report.line())

        result = TaskPlanner().plan(
            request,
            timeout=args.timeout,
            sequential=args.sequential,
            progress=progress,
            cycle_check=CycleCheck(args.cycle_check),
        )
    if result.status is PlanStatus.INVALID_INPUT:
        print(f"hdrc3 plan: error: {result.reason}", file=sys.stderr)
        return EXIT_CODES[result.status]
    for line in result.ipc_lines():
        print(line)
    for line in result.summary_lines():
        print(line)
    if result.solved and args.tst:
        print(json.dumps(plan_to_tst(result.plan).to_dict(), indent=1))
    if result.solved and args.validate:
        if not (is_pddl(request.domain) and is_pddl(request.problem)):
            print("; validation: skipped (needs PDDL domain and problem)")
        else:
            from hdrc3_deliberative.validation import validate_pddl_plan

            outcome = validate_pddl_plan(request.domain, request.problem, result.plan)
            print(f"; validation: {'valid' if outcome.valid else 'INVALID ' + outcome.reason}")
            if not outcome.valid:
                return 1
    return EXIT_CODES[result.status]
