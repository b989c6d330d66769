"""Planner facade: read domain/problem/control (PDDL or TAL language), ground, search."""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

from hdrc3_deliberative.control import ControlCompiler
from hdrc3_deliberative.errors import GroundingTimeout, PlanningInputError
from hdrc3_deliberative.grounding import Grounder, paused_gc
from hdrc3_deliberative.model import ControlSpec, Domain, Problem
from hdrc3_deliberative.motion_plan_info import MotionPlanInfo
from hdrc3_deliberative.pddl import PddlReader
from hdrc3_deliberative.result import (
    Occurrence,
    PlanningPhase,
    PlanningProgress,
    PlanResult,
    PlanStatus,
    ProgressHook,
    Statistics,
)
from hdrc3_deliberative.search import CycleCheck, SearchConfig, TalPlanner
from hdrc3_deliberative.tal_language import TalReader
from hdrc3_deliberative.task import Task


def is_pddl(text: str) -> bool:
    """PDDL files start with '(' after comments and blank lines."""
    for line in text.splitlines():
        stripped = line.strip()
        if stripped and not stripped.startswith(";"):
            return stripped.startswith("(")
    return False


@dataclass(frozen=True)
class PlanRequest:
    """Texts of a planning request (``control`` may be empty)."""

    domain: str
    problem: str
    control: str = ""
    domain_source: str = "<domain>"
    problem_source: str = "<problem>"
    control_source: str = "<control>"

    @classmethod
    def from_files(cls, domain: Path, problem: Path, control: Path | None = None) -> PlanRequest:
        """Read the files; unreadable files raise PlanningInputError."""
        texts = []
        for path in (domain, problem, control):
            if path is None:
                texts.append("")
                continue
            try:
                texts.append(path.read_text())
            except (OSError, UnicodeDecodeError) as exc:
                raise PlanningInputError(f"cannot read file: {exc}", str(path)) from None
        return cls(texts[0], texts[1], texts[2], str(domain), str(problem), str(control or ""))


class TaskPlanner:
    """Owns the parsers; turns requests into PlanResults (never raises on bad input)."""

    def __init__(self, motion: MotionPlanInfo | None = None) -> None:
        self._pddl = PddlReader()
        self._tal = TalReader()
        self._motion = motion

    def read(self, request: PlanRequest) -> tuple[Domain, Problem, ControlSpec]:
        """Parse the three texts (each PDDL or TAL language)."""
        if is_pddl(request.domain):
            domain = self._pddl.read_domain(request.domain, request.domain_source)
        else:
            domain = self._tal.read_domain(request.domain, request.domain_source)
        if is_pddl(request.problem):
            problem = self._pddl.read_problem(request.problem, request.problem_source)
        else:
            problem = self._tal.read_problem(request.problem, request.problem_source)
        control = ControlSpec(source=request.control_source)
        if request.control.strip():
            control = self._tal.read_control(request.control, request.control_source)
        return domain, problem, control

    def ground(self, domain: Domain, problem: Problem, deadline: float = float("inf")) -> Task:
        """Ground the task with this planner's motion-plan-info hook (GroundingTimeout)."""
        return Grounder(domain, problem, self._motion, deadline).ground()

    def plan(
        self,
        request: PlanRequest,
        timeout: float = 10.0,
        sequential: bool = False,
        progress: ProgressHook | None = None,
        cycle_check: CycleCheck = CycleCheck.PATH_CLOSED,
    ) -> PlanResult:
        """Plan; bad input becomes an INVALID_INPUT result with a readable reason.

        ``progress`` hears each phase as it begins and the search's effort as it goes;
        ``cycle_check`` selects the visited states that prune (see ``search.CycleCheck``).
        The cyclic garbage collector is paused for the call (see ``grounding.paused_gc``).
        """
        with paused_gc():
            return self._plan(request, timeout, sequential, progress, cycle_check)

    def _plan(
        self,
        request: PlanRequest,
        timeout: float,
        sequential: bool,
        progress: ProgressHook | None,
        cycle_check: CycleCheck,
    ) -> PlanResult:
        t0 = time.perf_counter()
        cpu0 = time.process_time()  # CPU time too: wall time is noisy on a shared machine
        try:
            domain, problem, spec = self.read(request)
            if progress is not None:
                phase = PlanningPhase.GROUNDING
                progress(PlanningProgress(phase, Statistics(), time.perf_counter() - t0))
            task = self.ground(domain, problem, t0 + timeout)
            program = ControlCompiler(task, spec).compile()
        except GroundingTimeout:
            stats = Statistics(grounding_seconds=time.perf_counter() - t0)
            return PlanResult(PlanStatus.TIMEOUT, (), stats, f"grounding took over {timeout:g} s")
        except PlanningInputError as exc:
            return PlanResult(PlanStatus.INVALID_INPUT, (), Statistics(), str(exc))
        except RecursionError:
            return PlanResult(PlanStatus.INVALID_INPUT, (), Statistics(), "input nested too deeply")
        grounding = time.perf_counter() - t0
        remaining = max(0.0, timeout - grounding)
        config = SearchConfig(
            timeout=remaining, sequential=sequential, cycle_check=cycle_check, prefer=spec.prefer
        )
        result = TalPlanner(task, program, config, progress=progress, started=t0).solve()
        plan = label_agents(result.plan, task, spec.agent_types)
        stats = replace(
            result.stats, grounding_seconds=grounding, cpu_seconds=time.process_time() - cpu0
        )
        return replace(result, plan=plan, stats=stats)


def label_agents(
    plan: tuple[Occurrence, ...], task: Task, agent_types: tuple[str, ...]
) -> tuple[Occurrence, ...]:
    """Fill in missing agents: the first argument that is an object of an agent type."""
    if not agent_types:
        return plan
    members = {o for t in agent_types for o in task.objects_by_type.get(t, ())}
    return tuple(
        occ
        if occ.agent is not None
        else replace(occ, agent=next((a for a in occ.args if a in members), None))
        for occ in plan
    )
