"""`hdrc3 path`: plan a path, build a roadmap, change a running planner's world (chapter 7).

``path plan`` plans in a world file; ``path roadmap`` builds or refreshes its cached PRM roadmap.

``path gis`` adds or removes a no-fly zone or an obstacle in ``/<agent>/path_planner`` at
runtime; a fly-to in progress on that agent replans if its path no longer holds. Exit 0 when the
planner took the change, 1 when it refused it (the reason is printed), 4 when no planner answers.

Exit codes of ``path plan``: 0 solved, 2 no path, 3 timeout, 4 invalid request (start/goal
outside the world, in an obstacle or a no-fly zone, inconsistent constraints).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from rich.console import Console

from hdrc3.cli.progress import message_bar
from hdrc3_base.errors import ConfigError
from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.constraints import Constraints
from hdrc3_navigation.cost import Criterion
from hdrc3_navigation.gis import DEFAULT_MARGIN, Gis
from hdrc3_navigation.planner import PathPlanner, PlannerKind, PlanRequest, PlanResult, PlanStatus
from hdrc3_navigation.roadmap import DEFAULT_NODES, Roadmap
from sim.world_loader import WorldError, load_world

EXIT_CODES = {PlanStatus.SOLVED: 0, PlanStatus.NO_PATH: 2, PlanStatus.TIMEOUT: 3}
INVALID_EXIT = 4
GIS_OPERATIONS = {
    "add-zone": "ADD_NO_FLY_ZONE",
    "remove-zone": "REMOVE_NO_FLY_ZONE",
    "add-obstacle": "ADD_OBSTACLE",
    "remove-obstacle": "REMOVE_OBSTACLE",
}
"""The ``GisUpdate.Request`` operation constant each ``path gis`` word names."""


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``path`` subcommand."""
    parser = subparsers.add_parser("path", help="path planning (PRM/RRT) in a world")
    actions = parser.add_subparsers(dest="path_action", metavar="ACTION", required=True)
    plan = actions.add_parser("plan", help="plan a collision-free cubic path")
    _common(plan)
    plan.add_argument("--from", dest="start", required=True, help="start E,N,U (m, local ENU)")
    plan.add_argument("--to", dest="goal", required=True, help="goal E,N,U (m, local ENU)")
    plan.add_argument("--planner", choices=[k.value for k in PlannerKind], default="prm+rrt")
    plan.add_argument("--criterion", choices=[c.value for c in Criterion], default="length")
    plan.add_argument("--speed", type=float, default=10.0, help="requested speed, m/s")
    plan.add_argument("--min-alt", type=float, help="minimum altitude, m local up")
    plan.add_argument("--max-alt", type=float, help="maximum altitude, m local up")
    plan.add_argument("--max-climb", type=float, help="maximum ascent rate, m/s")
    plan.add_argument("--max-descent", type=float, help="maximum descent rate, m/s")
    plan.add_argument(
        "--no-fly", action="append", default=[], metavar="E,N;E,N;...",
        help="a no-fly polygon for this query (repeatable)",
    )  # fmt: skip
    plan.add_argument(
        "--start-direction", metavar="E,N,U",
        help="tangent the first segment leaves the start with (joining a path in flight)",
    )  # fmt: skip
    plan.add_argument("--timeout", type=float, default=5.0, help="seconds")
    plan.add_argument("--json", action="store_true", help="print one JSON object")
    plan.set_defaults(handler=_plan)
    roadmap = actions.add_parser("roadmap", help="build or refresh the cached PRM roadmap")
    _common(roadmap)
    roadmap.add_argument("--rebuild", action="store_true", help="rebuild even if cached")
    roadmap.set_defaults(handler=_roadmap)
    gis = actions.add_parser("gis", help="change a running path planner's world model")
    gis.add_argument("operation", choices=sorted(GIS_OPERATIONS), help="what to change")
    gis.add_argument("--agent", default="uav0", help="whose path planner")
    gis.add_argument("--name", required=True, help="name of the zone or obstacle")
    gis.add_argument("--polygon", metavar="E,N;E,N;...", help="footprint (add-*)")
    gis.add_argument("--floor", type=float, default=-1e3, help="zone floor / obstacle base, m up")
    gis.add_argument("--ceiling", type=float, default=1e3, help="zone ceiling / obstacle top, m up")
    gis.add_argument("--timeout", type=float, default=10.0, help="seconds to wait for the planner")
    gis.set_defaults(handler=_gis)


def _common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--world", default="revinge", help="shipped world name or .toml path")
    parser.add_argument("--margin", type=float, default=DEFAULT_MARGIN, help="safety margin, m")
    parser.add_argument("--nodes", type=int, default=DEFAULT_NODES, help="roadmap size")
    parser.add_argument("--cache-dir", type=Path, help="roadmap cache directory")


def parse_point(text: str, what: str) -> tuple[float, float, float]:
    """Parse ``E,N,U``."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise ConfigError(f"{what} {text!r}: expected E,N,U in metres") from None
    if len(values) != 3:
        raise ConfigError(f"{what} {text!r}: expected E,N,U in metres")
    return values[0], values[1], values[2]


def parse_polygon(text: str, option: str = "--no-fly") -> tuple[tuple[float, float], ...]:
    """Parse ``e,n;e,n;...`` (at least 3 vertices)."""
    points = []
    for pair in text.split(";"):
        parts = pair.split(",")
        try:
            if len(parts) != 2:
                raise ValueError
            points.append((float(parts[0]), float(parts[1])))
        except ValueError:
            raise ConfigError(f"{option} {text!r}: expected e,n;e,n;... in metres") from None
    if len(points) < 3:
        raise ConfigError(f"{option} {text!r}: a polygon needs at least 3 vertices")
    return tuple(points)


def _planner(args: argparse.Namespace) -> PathPlanner:
    try:
        world = load_world(args.world)
    except WorldError as exc:
        raise ConfigError(f"world {args.world!r}: {exc.issues[0]}") from exc
    if args.nodes < 10:
        raise ConfigError(f"--nodes must be at least 10, got {args.nodes}")
    return PathPlanner(Gis(world, args.margin), args.cache_dir, roadmap_nodes=args.nodes)


def segment_json(segment: PathSegment) -> dict[str, Any]:
    """One segment as the ``--json`` output describes it."""
    return {
        "start": list(segment.start),
        "end": list(segment.end),
        "start_direction": list(segment.start_direction),
        "end_direction": list(segment.end_direction),
        "target_velocity": segment.target_velocity,
        "end_velocity": segment.end_velocity,
        "coefficients": [list(c) for c in segment.coefficients],
    }


def result_json(result: PlanResult, planner: PlannerKind) -> dict[str, Any]:
    """The ``--json`` object of one query."""
    return {
        "status": result.status.value,
        "reason": result.reason,
        "planner": planner.value,
        "reconnected": result.reconnected,
        "planning_ms": result.planning_time * 1e3,
        "length_m": result.length,
        "duration_s": result.duration,
        "energy_j": result.energy,
        "hover_stops": result.hover_stops,
        "segments": [segment_json(s) for s in result.segments],
    }


def _plan(args: argparse.Namespace) -> int:
    constraints = Constraints(
        args.min_alt,
        args.max_alt,
        args.max_climb,
        args.max_descent,
        tuple(parse_polygon(p) for p in args.no_fly),
    )
    request = PlanRequest(
        parse_point(args.start, "--from"),
        parse_point(args.goal, "--to"),
        args.speed,
        constraints,
        PlannerKind(args.planner),
        args.timeout,
        Criterion(args.criterion),
        parse_point(args.start_direction, "--start-direction") if args.start_direction else None,
    )
    planner = _planner(args)
    if request.planner is not PlannerKind.RRT:
        _roadmap_of(planner, rebuild=False)
    result = planner.plan(request)
    if args.json:
        print(json.dumps(result_json(result, request.planner)), flush=True)
    else:
        print(
            f"{result.status.value}: {result.reason} ({request.planner.value}, "
            f"{result.planning_time * 1e3:.0f} ms)",
            flush=True,
        )
        if result.ok:
            print(
                f"length {result.length:.1f} m, duration {result.duration:.1f} s, "
                f"energy {result.energy / 1e3:.0f} kJ",
                flush=True,
            )
            for seg in result.segments:
                print(
                    f"  {seg.segment_id:3d} ({seg.start[0]:.1f}, {seg.start[1]:.1f}, "
                    f"{seg.start[2]:.1f}) -> ({seg.end[0]:.1f}, {seg.end[1]:.1f}, "
                    f"{seg.end[2]:.1f})  v {seg.target_velocity:.1f} end {seg.end_velocity:.1f}",
                    flush=True,
                )
    return EXIT_CODES.get(result.status, INVALID_EXIT)


def _roadmap_of(planner: PathPlanner, rebuild: bool) -> tuple[Roadmap, bool]:
    """The planner's roadmap from its cache, or built with a progress bar on a terminal."""
    with message_bar(Console(stderr=True), "roadmap of") as bar:
        task = bar.add_task("roadmap", total=planner.roadmap_nodes, name=planner.gis.world.name)

        def progress(milestones: int, wanted: int) -> None:
            bar.update(task, completed=milestones, total=wanted)

        return planner.roadmap(rebuild=rebuild, progress=progress)


def _roadmap(args: argparse.Namespace) -> int:
    planner = _planner(args)
    roadmap, built = _roadmap_of(planner, args.rebuild)
    nodes, edges = roadmap.size
    verb = "built" if built else "cached"
    print(
        f"{planner.gis.world.name}: roadmap {verb}: {nodes} nodes, {edges} edges, "
        f"build time {roadmap.build_seconds:.1f} s",
        flush=True,
    )
    print(f"  file {planner.cache.path(roadmap.key)}", flush=True)
    return 0


def _gis(args: argparse.Namespace) -> int:
    from hdrc3_base.ros_runtime import SERVICE_QOS, RosProcess
    from hdrc3_interfaces.srv import GisUpdate
    from hdrc3_platform_server.client import check_agent

    check_agent(args.agent)
    operation = getattr(GisUpdate.Request, GIS_OPERATIONS[args.operation])
    polygon: tuple[tuple[float, float], ...] = ()
    if args.operation.startswith("add-"):
        if args.polygon is None:
            raise ConfigError(f"path gis {args.operation} needs --polygon")
        polygon = parse_polygon(args.polygon, "--polygon")
    request = GisUpdate.Request(
        operation=operation,
        name=args.name,
        polygon_east=[p[0] for p in polygon],
        polygon_north=[p[1] for p in polygon],
        floor=args.floor,
        ceiling=args.ceiling,
    )
    service = f"/{args.agent}/path_planner/gis_update"
    with RosProcess(args=[]) as process:
        node = process.add_node(_client_node(process.context))
        try:
            client = node.create_client(GisUpdate, service, qos_profile=SERVICE_QOS)
            if not process.spin_until(client.service_is_ready, args.timeout):
                print(f"{args.operation} {args.name}: no service {service}", flush=True)
                return INVALID_EXIT
            future: Any = client.call_async(request)  # rclpy's Future is untyped
            if not process.spin_until(lambda: bool(future.done()), args.timeout):
                print(f"{args.operation} {args.name}: no answer from {service}", flush=True)
                return INVALID_EXIT
        finally:
            node.destroy_node()
    answer = future.result()
    verdict = "done" if answer.success else "refused"
    print(f"{args.operation} {args.name}: {verdict}: {answer.reason}", flush=True)
    return 0 if answer.success else 1


def _client_node(context: Any) -> Any:
    from rclpy.node import Node

    return Node("hdrc3_path_gis", context=context)
