"""Goal nodes planned by TALplanner in the UAV logistics domain (sections 6.3, 9.2, 11.1.2).

A goal node ``goal at(uav0, Square)`` becomes a planning problem of the ``uav-logistics``
domain (``hdrc3_deliberative/domains/uav_logistics``): the goal node's agent is the helicopter,
where the aircraft is now and every point the mission declares are locations with their
coordinates (TALplanner's motion-plan-info hook turns them into flight times), and the goal
statement is the problem's goal. The TST manager sends it to the ``task_planner`` service and
turns the plan's actions into elementary TST nodes (:class:`PlannedStep`) that the goal node
then executes as a sequence.

Which plan actions can run is derived, not listed: a domain operator is executable when an
elementary action of the same name (``actions.ACTIONS``) has an RMAX executor
(``rmax_executors.RMAX_EXECUTORS``: ``fly-to`` and the payload executors). Each of the action's
point parameters takes the operator argument whose domain type is named like the parameter
(``box``, ``carrier``); a ``place`` or ``destination`` takes the operator's last ``location``
argument (where the helicopter ends up). A plan with any other action fails the goal node with
that reason before anything flies.

Loads (boxes, carriers) enter the problem as :class:`Load` objects at a location: a box object
is named like its TST point (the box's tag), so ``pick-up-box(box)`` finds it. Goals that name a
load are planned with the domain's control rules (``control.tal``), which keep TALplanner from
useless detours. The problem is a :class:`GoalProblem` value, so recovery (``recovery.py``) can
change an assumption (a lift capacity, where a lost box lies) and plan again from it.
"""

from __future__ import annotations

import enum
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cache
from importlib.resources import files
from types import MappingProxyType
from typing import Protocol

from hdrc3_deliberative.model import Domain, Operator
from hdrc3_deliberative.tal_language import TalReader
from hdrc3_tst.actions import ACTIONS, ParamType
from hdrc3_tst.model import Node
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS

DOMAIN = "uav-logistics"
HELICOPTER_FUEL = 3000.0
HELICOPTER_LIFT = 30.0
CARRIER = "carrier"
"""The domain type of a carrier (its load is ``load(c)``, a box's ``weight(b)``)."""


def domain_text() -> str:
    """The UAV logistics domain in TALplanner's language."""
    return files("hdrc3_deliberative.domains.uav_logistics").joinpath("domain.tal").read_text()


def control_text() -> str:
    """The UAV logistics control rules (chapter section 9.2)."""
    return files("hdrc3_deliberative.domains.uav_logistics").joinpath("control.tal").read_text()


def here(agent: str) -> str:
    """The location name of where ``agent`` is when the goal is planned."""
    return f"here_{agent.replace('-', '_')}"


@dataclass(frozen=True)
class Load:
    """A box or carrier the planner may move: its object, domain type, location and weight."""

    name: str
    """The object, named like the TST point of the load (its tag)."""
    type: str
    """Its domain type: ``food-box``, ``medicine-box``, ``box`` or ``carrier``."""
    location: str
    """The location object it is at."""
    weight: float
    """kg: a box's weight; a carrier's ``load(c)``, its own mass and the boxes on it."""
    on: str = ""
    """The carrier a box rests on ("" for none; ``location`` is then the carrier's)."""
    slots: int = 0
    """A carrier's free places for boxes (``slots(c)``)."""


@dataclass(frozen=True)
class Stocked:
    """A box or carrier of the world file's inventory, as the depots hold it."""

    tag: str
    """What the magnet reads; the mission names the object's point like it."""
    kg: float
    """Its own mass."""
    contents: str = ""
    """A box's contents (``food``, ``medicine``, ``water``); "" for a carrier."""
    capacity: int = 0
    """A carrier's places for boxes (0 for a box)."""
    on: str = ""
    """The carrier a box rests on ("" for none)."""

    @property
    def is_carrier(self) -> bool:
        """True for a carrier (it has places for boxes)."""
        return self.capacity > 0


@dataclass(frozen=True)
class GoalProblem:
    """One helicopter's planning problem for a goal, as values recovery can change."""

    name: str
    agent: str
    locations: Mapping[str, tuple[float, float, float]]
    """Location objects by name with their positions (local ENU metres)."""
    start: str
    """The location the helicopter is at."""
    goal: str
    """The goal formula, e.g. ``at(box1, Field)``."""
    loads: tuple[Load, ...] = ()
    lift_capacity: float = HELICOPTER_LIFT
    fuel: float = HELICOPTER_FUEL
    holding: str = ""
    """The box the helicopter holds ("" for none)."""

    def text(self) -> str:
        """The problem in TALplanner's language."""
        agent = self.agent
        lines = [f"problem {self.name} for {DOMAIN}"]
        lines += [
            f"object {name}: location @ ({_xyz(xyz)})" for name, xyz in self.locations.items()
        ]
        lines.append(f"object {agent}: helicopter")
        lines += [f"object {load.name}: {load.type}" for load in self.loads]
        carriers = {load.name for load in self.loads if load.type == CARRIER}
        held = (
            f"holding-{'carrier' if self.holding in carriers else 'box'}({agent}, {self.holding})"
            if self.holding
            else f"free({agent})"
        )
        lines.append(
            f"init at({agent}, {self.start}), {held}, hovering({agent}), "
            f"lift-capacity({agent}) = {self.lift_capacity:g}, fuel({agent}) = {self.fuel:g}"
        )
        for load in self.loads:
            facts = []
            if load.name != self.holding:
                facts.append(
                    f"on({load.name}, {load.on})"
                    if load.on
                    else f"at({load.name}, {load.location})"
                )
            if load.name in carriers:
                facts += [
                    f"load({load.name}) = {load.weight:g}",
                    f"slots({load.name}) = {load.slots}",
                ]
            else:
                facts.append(f"weight({load.name}) = {load.weight:g}")
            lines.append(f"init {', '.join(facts)}")
        lines.append(f"goal {self.goal}")
        return "\n".join(lines) + "\n"

    def control(self) -> str:
        """The control rules to plan with: the domain's when the goal names a load, else none.

        The rules prune flights without a load to fetch or deliver, so a goal that only moves
        the helicopter (``at(uav0, Square)``) plans without them.
        """
        named = set(re.findall(r"[A-Za-z0-9_-]+", self.goal))
        return control_text() if any(load.name in named for load in self.loads) else ""

    def moved(self, agent_at: str, position: tuple[float, float, float]) -> GoalProblem:
        """The same problem with the helicopter at a new location ``agent_at``."""
        locations = {**self.locations, agent_at: position}
        return replace(self, locations=MappingProxyType(locations), start=agent_at)


def goal_problem(
    goal: Node,
    agent: str,
    position: tuple[float, float, float],
    points: Mapping[str, tuple[float, ...]],
    loads: tuple[Load, ...] = (),
) -> GoalProblem:
    """The planning problem of a goal node for one helicopter.

    Args:
        goal: The goal node (``action`` is the goal predicate, ``goal_args`` its arguments).
        agent: The helicopter (the goal node's agent).
        position: Where it is now (local ENU metres).
        points: The mission's declared points by name (local ENU metres); load points are not
            locations (a load is an object at a location).
        loads: The boxes and carriers the plan may move.
    """
    names = {load.name for load in loads}
    locations: dict[str, tuple[float, float, float]] = {here(agent): _triple(position)}
    locations.update(
        {name: _triple(xyz) for name, xyz in sorted(points.items()) if name not in names}
    )
    return GoalProblem(
        f"goal_{goal.node_id.replace('/', '_')}",
        agent,
        MappingProxyType(locations),
        here(agent),
        f"{goal.action}({', '.join(goal.goal_args)})",
        loads,
    )


LOAD_REACH = 30.0
"""m (horizontal): a stocked box is at the nearest declared point this close to it."""


def stocked_loads(
    stock: Sequence[Stocked], points: Mapping[str, tuple[float, ...]]
) -> tuple[Load, ...]:
    """The boxes and carriers a mission declares as points, as the planner's loads.

    Args:
        stock: The world file's boxes and carriers; one the mission does not declare as a
            point (``point box1 = box1 at 0``) is left out (no executor could find it).
        points: The mission's points by name (local ENU m).

    A loose box or a carrier is at the nearest other point within :data:`LOAD_REACH` m (the
    mission's point above the depot, say); a box's type is ``<contents>-box`` when the domain
    has that type. A box resting on a declared carrier is ``on`` it; the carrier's load counts
    its own mass and every box on it, declared or not (the hook lifts them all).
    """
    types = logistics_domain().types
    names = {item.tag for item in stock}
    sites = {n: p for n, p in points.items() if n not in names}
    where: dict[str, str] = {}
    for item in stock:
        xy = points.get(item.tag)
        if xy is None or item.on:
            continue
        near = sorted((math.hypot(p[0] - xy[0], p[1] - xy[1]), n) for n, p in sites.items())
        if near and near[0][0] <= LOAD_REACH:
            where[item.tag] = near[0][1]
    loads: list[Load] = []
    for item in stock:
        if item.is_carrier and item.tag in where:
            aboard = [b for b in stock if b.on == item.tag]
            kg = item.kg + sum(b.kg for b in aboard)
            loads.append(
                Load(item.tag, CARRIER, where[item.tag], kg, slots=item.capacity - len(aboard))
            )
        elif not item.is_carrier and item.tag in points and (item.on or item.tag) in where:
            kind = f"{item.contents}-box" if f"{item.contents}-box" in types else "box"
            loads.append(Load(item.tag, kind, where[item.on or item.tag], item.kg, on=item.on))
    return tuple(loads)


def _triple(xyz: Sequence[float]) -> tuple[float, float, float]:
    return (float(xyz[0]), float(xyz[1]), float(xyz[2]))


def _xyz(xyz: Sequence[float]) -> str:
    return ", ".join(f"{v:.3f}" for v in xyz[:3])


@dataclass(frozen=True)
class OperatorMapping:
    """How a domain operator becomes an elementary action: which argument goes where."""

    action: str
    args: Mapping[str, int] = field(default_factory=dict)
    """Point parameter of the action -> index of the operator argument giving its value."""


LOCATION = "location"
"""The domain type of places (``place``/``destination`` parameters take one)."""


@cache
def logistics_domain() -> Domain:
    """The UAV logistics domain, parsed."""
    return TalReader().read_domain(domain_text(), "uav_logistics/domain.tal")


def _is_a(domain: Domain, type_name: str, ancestor: str) -> bool:
    current: str | None = type_name
    while current:
        if current == ancestor:
            return True
        current = domain.types.get(current)
    return False


def _mapping(domain: Domain, op: Operator) -> OperatorMapping | None:
    """The operator's mapping onto its elementary action (None: no such action or executor)."""
    spec = ACTIONS.get(op.name)
    if spec is None or op.name not in RMAX_EXECUTORS:
        return None
    args: dict[str, int] = {}
    for pspec in spec.params:
        if pspec.type is not ParamType.POINT:
            continue
        typed = [i for i, p in enumerate(op.params) if _is_a(domain, p.type, pspec.name)]
        if not typed:
            typed = [i for i, p in enumerate(op.params) if _is_a(domain, p.type, LOCATION)]
        if not typed:
            return None
        args[pspec.name] = typed[-1]
    return OperatorMapping(op.name, MappingProxyType(args))


def operator_mappings(domain: Domain | None = None) -> Mapping[str, OperatorMapping]:
    """Every executable operator of the domain (default: UAV logistics) by name."""
    domain = logistics_domain() if domain is None else domain
    found = ((op.name, _mapping(domain, op)) for op in domain.operators)
    return MappingProxyType({name: m for name, m in found if m is not None})


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
    operators = operator_mappings()
    steps: list[PlannedStep] = []
    for label, agent, start, duration in zip(labels, agents, starts, durations, strict=True):
        words = label.strip("() ").split()
        if not words:
            return PlanSteps(StepsStatus.NOT_EXECUTABLE, (), f"empty plan action {label!r}")
        mapping = operators.get(words[0])
        if mapping is None:
            return PlanSteps(
                StepsStatus.NOT_EXECUTABLE,
                (),
                f"the plan needs {label}, and no RMAX executor performs {words[0]} "
                f"(executable: {', '.join(operators)})",
            )
        if any(1 + i >= len(words) for i in mapping.args.values()):
            return PlanSteps(
                StepsStatus.NOT_EXECUTABLE, (), f"plan action {label} has too few arguments"
            )
        args: dict[str, float | str] = {k: words[1 + i] for k, i in mapping.args.items()}
        steps.append(PlannedStep(mapping.action, agent, args, start, duration))
    return PlanSteps(StepsStatus.OK, tuple(steps))


@dataclass
class PlanHandle:
    """A planning request in flight; the port fills it when the planner answers."""

    problem: str
    control: str = ""
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

    def request(self, domain: str, problem: str, control: str = "") -> PlanHandle:
        """Ask for a plan (with TAL control rules, if any); the handle is filled later."""
