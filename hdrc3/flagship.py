"""The flagship demo: the emergency-services mission (chapter section 11.1) with two aircraft.

One launched system (world_sim with both RMAXes, their control kernels, Platform Servers, TST
managers, task and path planners, execution monitors, cameras and saliency nodes, recorded to
MCAP) flies both legs:

1. Leg I: the TST of :func:`~hdrc3.emergency_mission.leg1_text` scans the region, each aircraft
   its band, and the saliency maps of both are merged into ``saliency.geojson``.
2. The confirmed bodies get kits from the depot's stock; the whole delivery goes to TALplanner
   (the ``task_planner`` service of the first aircraft, whose motion-plan-info hook asks the path
   planner for flight times) as one problem with both helicopters where they now are. Its plan
   says who carries which box.
3. Leg II: the TST of :func:`~hdrc3.emergency_mission.leg2_text` flies it: goal nodes planned
   again on board, monitored, recovered, then home and land.

What the operator knows is the mission (region, depot, stock): no decision reads the
simulator's state. Every product goes to ``out``: both TSTs, the planning problem and plan, the
saliency map, the timelines and the recording.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hdrc3.emergency_mission import (
    Body,
    Box,
    EmergencyMission,
    KitPlan,
    assign_bands,
    confirmed_bodies,
    deliveries_from_plan,
    delivery_problem,
    kits_for,
    leg1_text,
    leg2_text,
)
from hdrc3.launch_plan import CAMERA_NODES, CATALOG, EXECUTION_MONITOR, RAW_IMAGES
from hdrc3.launched_system import LaunchedSystem
from hdrc3.mission_run import Flown, Outcome, fly, settle, status_line, write_timeline
from hdrc3.safety_pilot import hand_over
from hdrc3.saliency_output import collect
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_interfaces.msg import HelicopterState
from hdrc3_interfaces.srv import Plan
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.goal_planning import control_text, domain_text
from hdrc3_tst.mission_client import TstClient
from sim.world import ObjectKind
from sim.world_loader import load_world

PLAN_TIMEOUT_S = 60.0
"""TALplanner's budget for leg II (CPU seconds on the planner's side)."""
PLAN_WAIT_S = 120.0
STATE_WAIT_S = 30.0
LEG_TIMEOUT_S = 3600.0
"""Wall seconds a leg may take before it is aborted."""


@dataclass
class FlagshipResult:
    """What happened, for the summary and the report."""

    legs: dict[str, Flown] = field(default_factory=dict)
    bodies: tuple[Body, ...] = ()
    kits: KitPlan | None = None
    deliveries: dict[str, list[tuple[str, str]]] = field(default_factory=dict)
    failure: str = ""
    problems: list[str] = field(default_factory=list)
    """What went wrong after the mission (stopping the system)."""
    depot: tuple[float, float] = (0.0, 0.0)
    plan_lines: tuple[str, ...] = ()

    @property
    def succeeded(self) -> bool:
        """Both legs flew to success."""
        return not self.failure and all(f.outcome is Outcome.SUCCEEDED for f in self.legs.values())


def depot_stock(world_name: str, depot: str) -> tuple[tuple[float, float], tuple[Box, ...]]:
    """The supply depot's position and the boxes the world file stocks there (the inventory)."""
    world = load_world(world_name)
    try:
        site = world.depot(depot)
    except KeyError:
        raise ConfigError(f"world {world_name!r} has no depot {depot!r}") from None
    boxes = tuple(
        Box(o.id, o.contents.value if o.contents else "", o.mass or 0.0, o.east, o.north)
        for o in world.objects_of(ObjectKind.BOX)
        if math.hypot(o.east - site.east, o.north - site.north) <= site.radius
    )
    return (site.east, site.north), boxes


def home_pads(world_name: str, starts: dict[str, tuple[float, float]]) -> dict[str, str]:
    """The pad each aircraft stands on at the start (the world file's nearest pad to it)."""
    pads = [p for p in load_world(world_name).pads if not p.pattern]
    if not pads:
        raise ConfigError(f"world {world_name!r} has no pads to land on")
    return {
        agent: min(pads, key=lambda p: math.hypot(p.east - e, p.north - n)).name
        for agent, (e, n) in starts.items()
    }


class Flagship:
    """Flies the emergency-services mission on a launched system."""

    def __init__(
        self, mission: EmergencyMission, out: Path, log: Callable[[str], None] = print
    ) -> None:
        """``out``: where every product is written (created)."""
        self.mission = mission
        self.out = out
        self.log = log
        out.mkdir(parents=True, exist_ok=True)

    def nodes(self) -> list[str]:
        """The nodes every agent runs."""
        defaults = [k.name for k in CATALOG if k.default]
        planning = ["tst_manager", "task_planner", "path_planner", EXECUTION_MONITOR]
        return [*defaults, *planning, *CAMERA_NODES]

    def run(self, speed: str, domain_id: int, seed: int) -> FlagshipResult:
        """Launch, fly both legs, stop; the recording is ``out/run.mcap``."""
        result = FlagshipResult()
        system = LaunchedSystem(
            self.mission.agents,
            self.mission.world,
            speed,
            domain_id,
            self.out / "run.mcap",
            self.nodes(),
            self.log,
            seed,
            ["--record-exclude", RAW_IMAGES],
        )
        with system, RosProcess() as process:
            client = TstClient(process)
            client.on_status = lambda msg: self.log(status_line(msg))
            try:
                self._fly(process, client, result)
            except ConfigError as exc:
                result.failure = str(exc)
            settle(process, client)
        if system.returncode not in (0, None):
            # the mission is over by then: a slow teardown is reported, not a failed mission
            result.problems.append(f"the launch ended with code {system.returncode}")
        return result

    def _fly(self, process: RosProcess, client: TstClient, result: FlagshipResult) -> None:
        mission = self.mission
        for agent in mission.agents:
            hand_over(process, client.node, agent)
            self.log(f"safety pilot: {agent} engine on, RC switch to autonomous")
        starts = {a: (e, n) for a, (e, n, _) in self._positions(process, client).items()}
        homes = home_pads(mission.world, starts)
        bands = assign_bands(mission, starts)
        self.log("bands: " + ", ".join(f"{a} scans band {k}" for a, k in bands.items()))
        leg1 = leg1_text(mission, bands)
        (self.out / "leg1.tst").write_text(leg1, encoding="utf-8")
        flown = fly(
            process, client, self.log, "leg1", leg1, "leg1.tst", mission.agents, LEG_TIMEOUT_S
        )
        result.legs["leg1"] = flown
        self.log(flown.verdict)
        write_timeline(self.out / "leg1_timeline.csv", flown.latest)
        got = collect(
            process, client.node, mission.agents, mission.world, self.out / "saliency.geojson"
        )
        self.log(f"saliency map: {got.locations} locations, {got.confirmed} confirmed: {got.path}")
        if flown.outcome is not Outcome.SUCCEEDED:
            raise ConfigError(f"leg I did not succeed: {flown.verdict}")
        features = json.loads(got.path.read_text(encoding="utf-8")).get("features", [])
        result.bodies = confirmed_bodies(features)
        depot, boxes = depot_stock(mission.world, mission.depot)
        result.depot = depot
        kits = kits_for(result.bodies, boxes, mission.kits)
        result.kits = kits
        for body in kits.unserved:
            self.log(f"no boxes left for {body.name} at ({body.east:.1f}, {body.north:.1f})")
        result.deliveries = {agent: [] for agent in mission.agents}
        if kits.kits:
            positions = self._positions(process, client)
            problem = delivery_problem(positions, kits, depot, mission.cruise_altitude)
            (self.out / "leg2_problem.tal").write_text(problem, encoding="utf-8")
            labels, agents = self._plan(process, client, problem, result)
            result.deliveries = deliveries_from_plan(labels, agents, mission.agents)
        else:
            self.log("leg I confirmed no body: nothing to deliver, the aircraft fly home")
        for agent, items in result.deliveries.items():
            listed = ", ".join(f"{box} -> {body}" for box, body in items) or "nothing"
            self.log(f"allocation: {agent} delivers {listed}")
        leg2 = leg2_text(mission, result.deliveries, kits, depot, homes)
        (self.out / "leg2.tst").write_text(leg2, encoding="utf-8")
        flown = fly(
            process, client, self.log, "leg2", leg2, "leg2.tst", mission.agents, LEG_TIMEOUT_S
        )
        result.legs["leg2"] = flown
        self.log(flown.verdict)
        write_timeline(self.out / "leg2_timeline.csv", flown.latest)

    def _positions(
        self, process: RosProcess, client: TstClient
    ) -> dict[str, tuple[float, float, float]]:
        """Every aircraft's position from its own Data Interface (local ENU m)."""
        frame = frame_from_world(self.mission.world)
        seen: dict[str, tuple[float, float, float]] = {}

        def keep(agent: str) -> Callable[[Any], None]:
            def on_state(msg: Any) -> None:
                position = frame.state_enu(msg)
                if position is not None:
                    seen[agent] = position

            return on_state

        subs = [
            client.node.create_subscription(HelicopterState, f"/{a}/helicopter_state", keep(a), 10)
            for a in self.mission.agents
        ]
        try:
            if not process.spin_until(lambda: len(seen) == len(self.mission.agents), STATE_WAIT_S):
                missing = sorted(set(self.mission.agents) - set(seen))
                raise ConfigError(f"no Data Interface state from {', '.join(missing)}")
        finally:
            for sub in subs:
                client.node.destroy_subscription(sub)
        return seen

    def _plan(
        self, process: RosProcess, client: TstClient, problem: str, result: FlagshipResult
    ) -> tuple[list[str], list[str]]:
        planner = self.mission.agents[0]
        service = client.node.create_client(Plan, f"/{planner}/plan")
        try:
            if not process.spin_until(service.service_is_ready, STATE_WAIT_S):
                raise ConfigError(f"no task planner answers on /{planner}/plan")
            request = Plan.Request(
                domain=domain_text(),
                problem=problem,
                control=control_text(),
                timeout=PLAN_TIMEOUT_S,
                sequential=False,
            )
            future: Any = service.call_async(request)
            if not process.spin_until(lambda: bool(future.done()), PLAN_WAIT_S):
                raise ConfigError(f"/{planner}/plan did not answer in {PLAN_WAIT_S:g} s")
            answer = future.result()
        finally:
            client.node.destroy_client(service)
        if answer.status != Plan.Response.STATUS_SOLVED:
            raise ConfigError(f"TALplanner found no plan for leg II: {answer.reason}")
        result.plan_lines = tuple(answer.plan)
        (self.out / "leg2_plan.txt").write_text("\n".join(answer.plan) + "\n", encoding="utf-8")
        self.log(
            f"TALplanner: {len(answer.plan)} actions, makespan {answer.makespan:.0f} s, "
            f"{answer.planning_time:.2f} s to plan"
        )
        return list(answer.actions), list(answer.agents)


def flagship_summary(result: FlagshipResult, out: Path) -> list[str]:
    """The one-screen summary: legs, bodies, allocation, products."""
    lines = ["emergency-services mission (chapter 11.1)"]
    for name, flown in result.legs.items():
        lines.append(f"  {name}: {flown.verdict}")
    lines.append(f"  bodies confirmed by the saliency map: {len(result.bodies)}")
    lines += [
        f"    {b.name} at ({b.east:.1f}, {b.north:.1f}) p_body {b.p_body:.2f}"
        for b in result.bodies
    ]
    if result.kits is not None:
        for body in result.kits.unserved:
            lines.append(f"    {body.name}: no boxes left")
    for agent, items in result.deliveries.items():
        listed = ", ".join(f"{box} -> {body}" for box, body in items) or "nothing"
        lines.append(f"  {agent} delivers {listed}")
    if result.failure:
        lines.append(f"  failure: {result.failure}")
    lines += [f"  problem: {p}" for p in result.problems]
    lines.append(f"  products: {out}")
    return lines
