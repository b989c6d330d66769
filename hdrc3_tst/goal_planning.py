"""Goal nodes planned by TALplanner in the UAV logistics domain (sections 6.3, 9.2, 11.1.2).

A goal node ``goal at(uav0, Square)`` becomes a planning problem of the ``uav-logistics``
domain (``hdrc3_deliberative/domains/uav_logistics``): the goal node's agent is the helicopter,
where the aircraft is now and every point the mission declares are locations with their
coordinates (TALplanner's motion-plan-info hook turns them into flight times), and the goal
statement is the problem's goal. The TST manager sends it to the ``task_planner`` service and
turns the plan's actions into elementary TST nodes (:class:`PlannedStep`) that the goal node
then executes as a sequence. Only plan actions with an RMAX executor can run: ``fly-to`` today
(payload handling comes with the payload issue); a plan with any other action fails the goal
node with that reason before anything flies.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib.resources import files
from typing import Protocol

from hdrc3_tst.model import Node

DOMAIN = "uav-logistics"
HELICOPTER_FUEL = 3000.0
HELICOPTER_LIFT = 30.0


def domain_text() -> str:
    """The UAV logistics domain in TALplanner's language."""
    return files("hdrc3_deliberative.domains.uav_logistics").joinpath("domain.tal").read_text()


def here(agent: str) -> str:
    """The location name of where ``agent`` is when the goal is planned."""
    return f"here_{agent.replace('-', '_')}"


def goal_problem(
    goal: Node,
    agent: str,
    position: tuple[float, float, float],
    points: Mapping[str, tuple[float, ...]],
) -> str:
    """The planning problem of a goal node for one helicopter.

    Args:
        goal: The goal node (``action`` is the goal predicate, ``goal_args`` its arguments).
        agent: The helicopter (the goal node's agent).
        position: Where it is now (local ENU metres).
        points: The mission's declared points by name (local ENU metres).
    """
    lines = [f"problem goal_{goal.node_id.replace('/', '_')} for {DOMAIN}"]
    lines.append(f"object {here(agent)}: location @ ({_xyz(position)})")
    lines += [f"object {name}: location @ ({_xyz(xyz)})" for name, xyz in sorted(points.items())]
    lines.append(f"object {agent}: helicopter")
    lines.append(
        f"init at({agent}, {here(agent)}), free({agent}), hovering({agent}), "
        f"lift-capacity({agent}) = {HELICOPTER_LIFT:g}, fuel({agent}) = {HELICOPTER_FUEL:g}"
    )
    lines.append(f"goal {goal.action}({', '.join(goal.goal_args)})")
    return "\n".join(lines) + "\n"


def _xyz(xyz: Sequence[float]) -> str:
    return ", ".join(f"{v:.3f}" for v in xyz[:3])


class StepsStatus(enum.Enum):
    """Whether a plan can become TST nodes."""

    OK = "ok"
    NOT_EXECUTABLE = "not_executable"


@dataclass(frozen=True)
class PlannedStep:
    """One planned action as an elementary node: its action type, agent and arguments."""

    action: str
    agent: str
    args: Mapping[str, float | str]
    """Type-specific parameters the plan determines (a point name for destinations); the
    others stay open and are bound when the node starts, like any open parameter."""
    start: float
    duration: float


@dataclass(frozen=True)
class PlanSteps:
    """The plan as steps, or why it cannot be executed."""

    status: StepsStatus
    steps: tuple[PlannedStep, ...] = ()
    reason: str = ""


@dataclass(frozen=True)
class _Mapping:
    """How a domain operator becomes an action: its type and which argument goes where."""

    action: str
    args: Mapping[str, int] = field(default_factory=dict)
    """Type-specific parameter -> index of the operator argument giving its value."""


_OPERATORS: Mapping[str, _Mapping] = {"fly-to": _Mapping("fly-to", {"destination": 2})}
"""Domain operators that have an RMAX executor."""


def plan_steps(
    labels: Sequence[str],
    agents: Sequence[str],
    starts: Sequence[float],
    durations: Sequence[float],
) -> PlanSteps:
    """Turn the ``task_planner`` answer's columns into steps.

    Args:
        labels: Plan actions as ``(fly-to uav0 here_uav0 Square)``.
        agents: The agent of each action.
        starts: Planned start times (s).
        durations: Planned durations (s).
    """
    steps: list[PlannedStep] = []
    for label, agent, start, duration in zip(labels, agents, starts, durations, strict=True):
        words = label.strip("() ").split()
        if not words:
            return PlanSteps(StepsStatus.NOT_EXECUTABLE, (), f"empty plan action {label!r}")
        mapping = _OPERATORS.get(words[0])
        if mapping is None:
            return PlanSteps(
                StepsStatus.NOT_EXECUTABLE,
                (),
                f"the plan needs {label}, and no RMAX executor performs {words[0]} "
                f"(executable: {', '.join(_OPERATORS)})",
            )
        args: dict[str, float | str] = {k: words[1 + i] for k, i in mapping.args.items()}
        steps.append(PlannedStep(mapping.action, agent, args, start, duration))
    return PlanSteps(StepsStatus.OK, tuple(steps))


@dataclass
class PlanHandle:
    """A planning request in flight; the port fills it when the planner answers."""

    problem: str
    done: bool = False
    solved: bool = False
    reason: str = ""
    labels: tuple[str, ...] = ()
    agents: tuple[str, ...] = ()
    starts: tuple[float, ...] = ()
    durations: tuple[float, ...] = ()

    def answer(
        self,
        solved: bool,
        reason: str,
        labels: Sequence[str] = (),
        agents: Sequence[str] = (),
        starts: Sequence[float] = (),
        durations: Sequence[float] = (),
    ) -> None:
        """Record the planner's answer (the plan's columns when solved)."""
        self.done, self.solved, self.reason = True, solved, reason
        self.labels, self.agents = tuple(labels), tuple(agents)
        self.starts, self.durations = tuple(starts), tuple(durations)


class GoalPlannerPort(Protocol):
    """The ``task_planner`` service, as the engine uses it."""

    def request(self, domain: str, problem: str) -> PlanHandle:
        """Ask for a plan; the handle is filled when the answer arrives."""
