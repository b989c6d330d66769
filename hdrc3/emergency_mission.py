"""The emergency-services mission of chapter section 11.1 as TSTs and a planning problem.

Leg I (§11.1.1) scans the operator's region with every aircraft: band k of n of the region
per aircraft, cameras down, the saliency pipeline on (``scan-area``). Its output is the merged
saliency map. Leg II (§11.1.2) delivers a kit (a food box and a medicine box) to every body the
map confirms: :func:`kits_for` pairs the bodies with the boxes stocked at the supply depot,
:func:`delivery_problem` states the whole delivery as one problem of the ``uav-logistics``
domain with every helicopter where it is, and TALplanner (the ``task_planner`` service) decides
who carries which box in which order. :func:`deliveries_from_plan` reads that allocation off the
plan's drop-box actions and :func:`leg2_text` turns it into a TST: per aircraft a sequence of
goal nodes ``goal at(box, Drop_box)``, one per box (each box has its own drop point beside its
body), which the aircraft's own TST manager plans again
when it starts them (from where the aircraft then is) and recovers under execution monitoring
(§9.3), then the flight home and the landing.

Pure: no rclpy. The texts are checked by the TST language's own loader before anything flies.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from hdrc3_base.errors import ConfigError
from hdrc3_navigation.coverage import CoverageStatus, Platform, pair_footprint_width, plan_part
from hdrc3_tst.goal_planning import DOMAIN

DEPOT_POINT = "OverDepot"
"""The TST point above the supply depot (where the boxes are picked up)."""
DROP_OFFSET_M = 8.0
"""m from a body to where its boxes are put down: never onto the person."""
DROP_SPREAD = math.pi / 2.0
"""rad between the drop points of one body's boxes (two boxes: 11 m apart), centred on the
direction of the depot, so that two aircraft delivering to one body never share a point."""


@dataclass(frozen=True)
class EmergencyMission:
    """What the operator specifies: where to search, with whom, what to deliver.

    Attributes:
        world: The world (its pads, depots and boxes are the mission's resources).
        agents: The aircraft, each starting on its pad (``sim.world_sim.start_pads`` order).
        region: The search region's corners (local ENU m, counter-clockwise).
        scan_altitude: m above ground while scanning.
        scan_speed: m/s while scanning.
        cruise_altitude: m above ground for transit and deliveries.
        cruise_speed: m/s of the flights home.
        kits: Box contents every body receives (one box each).
        depot: The supply depot's name in the world file.
        deadline: s of sim time each leg may take.
    """

    world: str
    agents: tuple[str, ...]
    region: tuple[tuple[float, float], ...]
    scan_altitude: float = 30.0
    scan_speed: float = 5.0
    cruise_altitude: float = 20.0
    cruise_speed: float = 6.0
    kits: tuple[str, ...] = ("food", "medicine")
    depot: str = "supply_depot"
    deadline: float = 1500.0

    def __post_init__(self) -> None:
        """Validate (ConfigError names the first problem)."""
        if not self.agents:
            raise ConfigError("the mission needs at least one aircraft")
        if len(self.region) < 3:
            raise ConfigError("the region needs at least three corners")
        for name in ("scan_altitude", "scan_speed", "cruise_altitude", "cruise_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"{name} must be a positive number, not {value}")


@dataclass(frozen=True)
class Body:
    """A body the saliency map confirms, named for the mission (``Body1`` ...)."""

    name: str
    east: float
    north: float
    p_body: float


@dataclass(frozen=True)
class Box:
    """A box stocked at the depot: its tag in the world file and what it holds."""

    tag: str
    contents: str
    mass: float
    east: float
    north: float


@dataclass(frozen=True)
class Kit:
    """The boxes one body receives."""

    body: Body
    boxes: tuple[Box, ...]


@dataclass(frozen=True)
class KitPlan:
    """Which bodies get a kit, and which cannot (not enough boxes)."""

    kits: tuple[Kit, ...]
    unserved: tuple[Body, ...]


def confirmed_bodies(features: Sequence[Mapping[str, object]]) -> tuple[Body, ...]:
    """The confirmed points of a merged saliency map (``saliency.geojson`` features).

    Ordered by certainty (most certain first); malformed features raise ConfigError.
    """
    found: list[tuple[float, float, float]] = []
    for index, feature in enumerate(features):
        props = feature.get("properties")
        if not isinstance(props, Mapping):
            raise ConfigError(f"saliency map feature {index} has no properties")
        if not props.get("confirmed"):
            continue
        values = [props.get(k) for k in ("east", "north", "p_body")]
        numbers = [float(v) for v in values if isinstance(v, int | float)]
        if len(numbers) != 3 or not all(math.isfinite(v) for v in numbers):
            raise ConfigError(f"saliency map feature {index} needs finite east, north, p_body")
        found.append((numbers[0], numbers[1], numbers[2]))
    found.sort(key=lambda f: (-f[2], f[0], f[1]))
    return tuple(Body(f"Body{i + 1}", e, n, p) for i, (e, n, p) in enumerate(found))


def kits_for(bodies: Sequence[Body], boxes: Sequence[Box], kits: Sequence[str]) -> KitPlan:
    """Give each body (in order) one box of every kind in ``kits`` while boxes last."""
    stock = {kind: [b for b in boxes if b.contents == kind] for kind in kits}
    served: list[Kit] = []
    unserved: list[Body] = []
    for body in bodies:
        if all(stock[kind] for kind in kits):
            served.append(Kit(body, tuple(stock[kind].pop(0) for kind in kits)))
        else:
            unserved.append(body)
    return KitPlan(tuple(served), tuple(unserved))


def drop_point(
    body: Body, depot: tuple[float, float], index: int = 0, count: int = 1
) -> tuple[float, float]:
    """Where box ``index`` of ``count`` for ``body`` goes down, :data:`DROP_OFFSET_M` from it.

    The points spread by :data:`DROP_SPREAD` around the direction of the depot; one box (or
    the body as a planning location) lies straight towards the depot.
    """
    toward = math.atan2(depot[1] - body.north, depot[0] - body.east)
    angle = toward + (index - (count - 1) / 2.0) * DROP_SPREAD
    return (
        body.east + DROP_OFFSET_M * math.cos(angle),
        body.north + DROP_OFFSET_M * math.sin(angle),
    )


def box_drops(
    plan: KitPlan, depot: tuple[float, float]
) -> dict[str, tuple[str, tuple[float, float]]]:
    """Every box of the plan -> (its body's name, where it goes down)."""
    return {
        box.tag: (kit.body.name, drop_point(kit.body, depot, i, len(kit.boxes)))
        for kit in plan.kits
        for i, box in enumerate(kit.boxes)
    }


def _polygon(corners: Sequence[tuple[float, float]]) -> str:
    return ", ".join(f"({e:g}, {n:g})" for e, n in corners)


def _header(mission: EmergencyMission) -> list[str]:
    return [f"world {mission.world}", f"agents {', '.join(mission.agents)}", ""]


def assign_bands(
    mission: EmergencyMission, starts: Mapping[str, tuple[float, float]]
) -> dict[str, int]:
    """Which band of the region each aircraft scans: least total time to finish all bands.

    Each aircraft prices every band as the coverage planner would plan it for it (transit from
    its start plus the lawn-mower, ``plan_part``); the assignment problem over those times is
    solved exactly (scipy's ``linear_sum_assignment``), so aircraft do not cross each other to
    reach their bands.

    Raises:
        ConfigError: an aircraft without a start, or a region the coverage planner refuses.
    """
    count = len(mission.agents)
    cost = np.zeros((count, count))
    footprint = pair_footprint_width(mission.scan_altitude)
    for i, agent in enumerate(mission.agents):
        if agent not in starts:
            raise ConfigError(f"no start position for {agent}")
        me = Platform(agent, footprint, mission.scan_speed, starts[agent])
        for part in range(1, count + 1):
            plan = plan_part(mission.region, part, count, me, mission.scan_altitude)
            if plan.status is not CoverageStatus.PLANNED:
                raise ConfigError(f"the region cannot be scanned: {plan.reason}")
            cost[i, part - 1] = plan.assignments[0].duration
    rows, cols = linear_sum_assignment(cost)
    return {mission.agents[r]: int(c) + 1 for r, c in zip(rows, cols, strict=True)}


def leg1_text(mission: EmergencyMission, bands: Mapping[str, int] | None = None) -> str:
    """Leg I: each aircraft scans its band of the region (concurrently), then hovers there.

    ``bands``: agent -> band (1-based, :func:`assign_bands`); default: in the agents' order.
    """
    chosen = bands or {a: k for k, a in enumerate(mission.agents, start=1)}
    lines = _header(mission)
    lines.append(f"area Region = polygon({_polygon(mission.region)})")
    lines.append("")
    count = len(mission.agents)
    variables = [v for k in range(1, count + 1) for v in (f"P{k}", f"TS{k}", f"TE{k}")]
    children = [
        f"  band{k}(P{k}, TS{k}, TE{k}) = scan-area(TS{k}, TE{k}, {mission.scan_speed:g}, "
        f"Region, {mission.scan_altitude:g}, {chosen[agent]}, {count})"
        for k, agent in enumerate(mission.agents, start=1)
    ]
    order = " and ".join(
        f"TS0 <= TS{k} and TS{k} < TE{k} and TE{k} <= TE0" for k in range(1, count + 1)
    )
    agents = " and ".join(f"P{k} = {a}" for k, a in enumerate(mission.agents, start=1))
    lines.append(f"leg1(P0, TS0, TE0) = with {', '.join(variables)} concurrent")
    lines.append(";\n".join(children))
    lines.append(
        f"where {order} and {agents} and P0 = {mission.agents[0]} and TS0 = 0 "
        f"and TE0 <= {mission.deadline:g}"
    )
    return "\n".join(lines) + "\n"


def delivery_problem(
    positions: Mapping[str, tuple[float, float, float]],
    plan: KitPlan,
    depot: tuple[float, float],
    altitude: float,
) -> str:
    """The whole of leg II as one ``uav-logistics`` problem for TALplanner.

    Args:
        positions: Every helicopter's position now (local ENU m).
        plan: The kits to deliver.
        depot: The supply depot (local ENU m); the boxes are there.
        altitude: m of the delivery points above ground.
    """
    lines = [f"problem leg2 for {DOMAIN}"]
    lines.append(
        f"object {DEPOT_POINT}: supply-depot @ ({depot[0]:.3f}, {depot[1]:.3f}, {altitude:g})"
    )
    for kit in plan.kits:
        e, n = drop_point(kit.body, depot)
        lines.append(f"object {kit.body.name}: body @ ({e:.3f}, {n:.3f}, {altitude:g})")
    for agent, (e, n, u) in positions.items():
        lines.append(f"object here_{agent}: location @ ({e:.3f}, {n:.3f}, {max(u, altitude):.3f})")
        lines.append(f"object {agent}: helicopter")
    boxes = [box for kit in plan.kits for box in kit.boxes]
    lines += [f"object {box.tag}: {box.contents}-box" for box in boxes]
    for agent in positions:
        lines.append(
            f"init at({agent}, here_{agent}), free({agent}), hovering({agent}), "
            f"lift-capacity({agent}) = 30, fuel({agent}) = 3000"
        )
    for box in boxes:
        lines.append(f"init at({box.tag}, {DEPOT_POINT}), weight({box.tag}) = {box.mass:g}")
    for kit in plan.kits:
        goal = " and ".join(f"at({box.tag}, {kit.body.name})" for box in kit.boxes)
        lines.append(f"goal {goal}")
    return "\n".join(lines) + "\n"


def deliveries_from_plan(
    labels: Sequence[str], agents: Sequence[str], helicopters: Sequence[str]
) -> dict[str, list[tuple[str, str]]]:
    """Each helicopter's deliveries (box, body) in the plan's order, from its drop-box actions.

    Raises:
        ConfigError: a drop-box action of an unknown helicopter or with too few arguments.
    """
    out: dict[str, list[tuple[str, str]]] = {h: [] for h in helicopters}
    for label, agent in zip(labels, agents, strict=True):
        words = label.strip("() ").split()
        if not words or words[0] != "drop-box":
            continue
        if len(words) < 4 or agent not in out:
            raise ConfigError(f"plan action {label} ({agent}) is not a delivery of this mission")
        out[agent].append((words[2], words[3]))
    return out


def leg2_text(
    mission: EmergencyMission,
    deliveries: Mapping[str, Sequence[tuple[str, str]]],
    plan: KitPlan,
    depot: tuple[float, float],
    homes: Mapping[str, str],
) -> str:
    """Leg II as a TST: per aircraft its deliveries as goal nodes, then home and land.

    Every box is picked up from the point above it (``Pick_<box>``, the nearest point to it, so
    the on-board goal problem finds it there) and put down at its own drop point
    (``Drop_<box>``, :func:`box_drops`): two aircraft never aim at one point.

    Args:
        mission: The mission.
        deliveries: Per aircraft (box, body) in order (:func:`deliveries_from_plan`).
        plan: The kits (for the bodies' drop points and the boxes).
        depot: The supply depot (local ENU m).
        homes: Per aircraft the pad it lands on.
    """
    alt = mission.cruise_altitude
    lines = _header(mission)
    drops = box_drops(plan, depot)
    for box in (box for kit in plan.kits for box in kit.boxes):
        e, n = drops[box.tag][1]
        lines.append(f"point {box.tag} = {box.tag} at 0")
        lines.append(f"point Pick_{box.tag} = ({box.east:.2f}, {box.north:.2f}, {alt:g})")
        lines.append(f"point Drop_{box.tag} = ({e:.2f}, {n:.2f}, {alt:g})")
    busy = [a for a in mission.agents if a in deliveries]
    lines += [f"point Home_{a} = {homes[a]} at {alt:g}" for a in busy]
    lines.append("")
    parts: list[str] = []
    outer: list[str] = []
    order: list[str] = []
    for k, agent in enumerate(busy, start=1):
        steps = [f"goal at({box}, Drop_{box})" for box, _ in deliveries[agent]]
        steps += [f"fly-to(#s, #e, {mission.cruise_speed:g}, Home_{agent})", "land(#s, #e, 0)"]
        times = [f"T{k}_{i}" for i in range(1, 2 * len(steps) + 1)]
        children = []
        for i, step in enumerate(steps):
            ts, te = times[2 * i], times[2 * i + 1]
            body = step.replace("#s", ts).replace("#e", te)
            children.append(f"    a{k}_{i + 1}({ts}, {te}) = {body}")
        parts.append(
            f"  deliver{k}(P{k}, TS{k}, TE{k}) = with {', '.join(times)} sequence\n"
            + ";\n".join(children)
            + f"\n  where P{k} = {agent}"
        )
        outer += [f"P{k}", f"TS{k}", f"TE{k}"]
        order.append(f"TS0 <= TS{k} and TS{k} < TE{k} and TE{k} <= TE0")
    lines.append(f"leg2(P0, TS0, TE0) = with {', '.join(outer)} concurrent")
    lines.append(";\n".join(parts))
    lines.append(
        f"where {' and '.join(order)} and P0 = {busy[0]} and TS0 = 0 "
        f"and TE0 <= {mission.deadline:g}"
    )
    return "\n".join(lines) + "\n"
