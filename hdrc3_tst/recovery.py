"""Recovery from a monitor violation in a goal node (HDRC3 chapter 9.3.1): the decision.

When a monitor formula is violated during a planned goal's execution, the chapter's recovery is:
suspend the running step, brake if the formula requires it, hover, run the recovery operator
attached to the formula (it changes the planner's assumptions), and plan the remaining goals
again with TALplanner. After more failures on the same fault than the operator tolerates, the
goal gives up. :class:`Recovery` decides that sequence and builds the new planning problem; the
TST engine carries it out (stopping, braking, hovering and asking the planner are its ports).

The new problem starts from what is known, never from simulator truth: the goal's problem as
planned, advanced by the effects of the plan steps that succeeded (:func:`progressed`), with the
helicopter where its own state estimate puts it at the violation, then the operator's changes.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cache
from types import MappingProxyType

from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.goal_planning import CARRIER, GoalProblem, Load, PlannedStep
from hdrc3_tst.recovery_spec import (
    DEFAULT_ATTEMPTS,
    DEFAULT_RECOVERY,
    EffectKind,
    RecoveryOperator,
    RecoverySpec,
    RecoverySpecParser,
)

STEP_FAILED = "step-failed"
"""The recovery operator a goal uses when one of its planned steps fails (not a monitor
violation: the step's executor gave up); with no operator of that name, the goal fails."""

PUT_ON_CARRIER = "put-on-carrier"
"""The one action that puts a load down onto another load (a box onto a carrier)."""
LOAD_PARAMS = ("box", "carrier")
"""Action parameters naming a load; an action with one and no ``place`` takes it onto the hook,
one with a ``place`` puts it down there."""


class RecoveryStep(enum.Enum):
    """One step of a recovery, in the order they are carried out."""

    SUSPEND = "suspend"
    BRAKE = "brake"
    HOVER = "hover"
    APPLY_OPERATOR = "apply_operator"
    REPLAN = "replan"
    GIVE_UP = "give_up"
    IGNORED = "ignored"
    """Not a recovery: the violation concerns no running planned goal of this agent."""


class RecoveryStatus(enum.Enum):
    """The outcome of a recovery decision."""

    REPLAN = "replan"
    """Plan ``problem`` and continue with the new plan."""
    GAVE_UP = "gave_up"
    """Too many failures on this fault: the goal fails."""
    NOT_APPLICABLE = "not_applicable"
    """The operator is unknown or its arguments are missing: the goal fails."""


@dataclass(frozen=True)
class Violation:
    """What the execution monitor reported (``MonitorViolation``), as recovery needs it."""

    monitor_id: str
    """The formula's name, with ``@node_id`` for an operator-specific one."""
    recovery: str = ""
    emergency_brake: bool = False
    arguments: Mapping[str, str] = field(default_factory=dict)
    cause: str = ""
    """What went wrong, for the record (a failed step's reason); not part of the fault."""

    @property
    def fault(self) -> tuple[str, ...]:
        """What makes two violations the same fault: formula, operator and arguments."""
        name = self.monitor_id.split("@", 1)[0]
        return (name, self.recovery, *(f"{k}={v}" for k, v in sorted(self.arguments.items())))


@dataclass(frozen=True)
class RecoveryDecision:
    """The recovery to carry out, with its status and readable reason."""

    status: RecoveryStatus
    steps: tuple[RecoveryStep, ...]
    attempt: int
    """Failures on this fault so far, this one included."""
    problem: GoalProblem | None = None
    """The remaining goals' planning problem (REPLAN)."""
    places: Mapping[str, tuple[float, float, float]] = field(default_factory=dict)
    """Points the new plan's steps use that changed or are new (a lost box's place)."""
    changes: tuple[str, ...] = ()
    """The operator's changes as planning-language facts."""
    released: tuple[str, ...] = ()
    """Loads the hook must let go of (and wind in) before the new plan starts."""
    reason: str = ""


@dataclass(frozen=True)
class RecoveryReport:
    """One recovery step as carried out, for the record (``RecoveryEvent``)."""

    node_id: str
    """The goal node recovering ("" when ignored)."""
    monitor_id: str
    recovery: str
    step: RecoveryStep
    attempt: int = 0
    changes: tuple[str, ...] = ()
    plan: tuple[str, ...] = ()
    reason: str = ""


def after(agent: str, attempt: int) -> str:
    """The location name of where ``agent`` hovers when recovery ``attempt`` plans."""
    return f"recover_{agent.replace('-', '_')}_{attempt}"


def progressed(problem: GoalProblem, done: Sequence[PlannedStep]) -> GoalProblem:
    """The problem with the effects of the steps that succeeded on the loads.

    Who holds which load, where each is put down; a box taken off its carrier lightens it, a
    box put onto the one carrier at its place weighs it down, a carrier's boxes go where it
    goes.
    """
    loads = {load.name: load for load in problem.loads}
    holding = problem.holding
    for step in done:
        spec = ACTIONS[step.action]
        name = next((str(step.args[p]) for p in LOAD_PARAMS if p in step.args), "")
        if not name or name not in loads:
            continue
        load = loads[name]
        if spec.param("place") is None:  # onto the hook
            holding = name
            carrier = loads.get(load.on)
            if carrier is not None:
                loads[carrier.name] = _aboard(carrier, -load.weight)
                loads[name] = replace(load, on="", location=carrier.location)
            continue
        holding = ""
        place = str(step.args["place"])
        loads[name] = replace(load, location=place)
        if load.type == CARRIER:
            for box in [b for b in loads.values() if b.on == name]:
                loads[box.name] = replace(box, location=place)
        elif step.action == PUT_ON_CARRIER:
            carriers = [c for c in loads.values() if c.type == CARRIER and c.location == place]
            if len(carriers) == 1:  # the step names the place; one carrier stands there
                loads[name] = replace(load, location=place, on=carriers[0].name)
                loads[carriers[0].name] = _aboard(carriers[0], load.weight)
    return replace(problem, loads=tuple(loads.values()), holding=holding)


def _aboard(carrier: Load, kg: float) -> Load:
    """The carrier with a box of ``kg`` put on (negative: taken off)."""
    return replace(
        carrier, weight=carrier.weight + kg, slots=carrier.slots - int(math.copysign(1, kg))
    )


@cache
def default_recovery() -> RecoverySpec:
    """The packaged recovery operators (``default.recovery``)."""
    return RecoverySpecParser().parse_file(DEFAULT_RECOVERY)


class Recovery:
    """Decides recoveries and counts failures per fault (one instance per goal node)."""

    def __init__(self, spec: RecoverySpec) -> None:
        """Use the operators of ``spec``."""
        self._spec = spec
        self._failures: dict[tuple[str, ...], int] = {}

    def attempts(self, violation: Violation) -> int:
        """Failures on the violation's fault so far."""
        return self._failures.get(violation.fault, 0)

    def decide(
        self,
        violation: Violation,
        problem: GoalProblem,
        done: Sequence[PlannedStep],
        position: tuple[float, float, float],
    ) -> RecoveryDecision:
        """The recovery of ``violation`` for a goal planned as ``problem``.

        Args:
            violation: The violated formula, its operator and arguments.
            problem: The goal's planning problem as last planned.
            done: The steps of the current plan that succeeded, in order.
            position: The aircraft's estimated position at the violation (local ENU m).
        """
        attempt = self._failures.get(violation.fault, 0) + 1
        self._failures[violation.fault] = attempt
        halt: tuple[RecoveryStep, ...] = (RecoveryStep.SUSPEND,)
        halt += (RecoveryStep.BRAKE,) if violation.emergency_brake else ()
        halt += (RecoveryStep.HOVER,)
        operator = self._operator(violation.recovery)
        if operator is None:
            return RecoveryDecision(
                RecoveryStatus.NOT_APPLICABLE,
                (*halt, RecoveryStep.GIVE_UP),
                attempt,
                reason=f"{violation.monitor_id}: no recovery operator "
                f"{violation.recovery!r} (known: {', '.join(self._spec.operators) or 'none'})",
            )
        if attempt > operator.attempts:
            return RecoveryDecision(
                RecoveryStatus.GAVE_UP,
                (*halt, RecoveryStep.GIVE_UP),
                attempt,
                reason=f"{violation.monitor_id}: failed {attempt} times on the same fault "
                f"({operator.name} recovers from {operator.attempts})"
                + (f"; last: {violation.cause}" if violation.cause else ""),
            )
        here = after(problem.agent, attempt)
        current = progressed(problem, done).moved(here, position)
        applied = _apply(operator, violation, current, position)
        if isinstance(applied, str):
            return RecoveryDecision(
                RecoveryStatus.NOT_APPLICABLE,
                (*halt, RecoveryStep.GIVE_UP),
                attempt,
                reason=f"{violation.monitor_id}: {operator.name}: {applied}",
            )
        new, places, changes, released = applied
        return RecoveryDecision(
            RecoveryStatus.REPLAN,
            (*halt, RecoveryStep.APPLY_OPERATOR, RecoveryStep.REPLAN),
            attempt,
            new,
            MappingProxyType({here: position, **places}),
            changes,
            released,
            f"{violation.monitor_id}: {operator.name}, attempt {attempt} of {operator.attempts}",
        )

    def _operator(self, name: str) -> RecoveryOperator | None:
        if not name:
            # a formula without an operator: nothing learnt, plan again
            return RecoveryOperator("replan", (), DEFAULT_ATTEMPTS)
        return self._spec.operators.get(name)


_Applied = tuple[
    GoalProblem, dict[str, tuple[float, float, float]], tuple[str, ...], tuple[str, ...]
]


def _apply(
    operator: RecoveryOperator,
    violation: Violation,
    problem: GoalProblem,
    position: tuple[float, float, float],
) -> _Applied | str:
    """The operator's changes, or why they cannot be made."""
    places: dict[str, tuple[float, float, float]] = {}
    changes: list[str] = []
    released: list[str] = []
    loads = {load.name: load for load in problem.loads}
    for effect in operator.effects:
        if effect.kind is EffectKind.REPLAN:
            continue
        name = violation.arguments.get(effect.parameter)
        if name is None:
            return f"the violation has no argument {effect.parameter!r}"
        load = loads.get(name)
        if load is None:
            return f"{name} is not a load of the goal's problem"
        if effect.kind is EffectKind.LIFT_CAPACITY:
            lift = effect.factor * load.weight
            problem = replace(problem, lift_capacity=lift)
            changes.append(f"lift-capacity({problem.agent}) = {lift:g}")
        elif effect.kind is EffectKind.RELEASE:
            # not lifted: it stays where it was, off the hook
            released.append(name)
            problem = replace(problem, holding="" if problem.holding == name else problem.holding)
            changes.append(f"release({name})")
        else:
            # it lies below the aircraft: at the location the aircraft hovers at now
            where = problem.start
            loads[name] = Load(load.name, load.type, where, load.weight)
            holding = "" if problem.holding == name else problem.holding
            problem = replace(problem, loads=tuple(loads.values()), holding=holding)
            places[name] = position
            changes.append(f"at({name}, {where})")
    return problem, places, tuple(changes), tuple(released)
