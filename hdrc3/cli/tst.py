"""`hdrc3 tst`: Task Specification Trees (chapter section 6.3).

``check FILE`` parses the file, resolves it against its world and agents and propagates its
constraint network, then prints the tree with each node's earliest/latest start and end.
``run FILE`` creates the mission on the TST manager of every agent it names, executes its root
and prints one line per node state change until the root ends; with ``--launch`` it starts the
system first (recorded to ``--out``, by default without the cameras' raw images) and hands
every aircraft to autonomous mode the way ``hdrc3 demo`` does. ``abort``, ``pause``, ``resume``
and ``set`` act on a running mission on every agent given.

Exit codes: 0 ok (run: the mission succeeded), 1 the mission failed or was aborted (the failing
node and its reason are printed), 3 a TST manager refused or could not be reached, 4 invalid
input (syntax, unknown names, inconsistent constraints; errors as FILE:LINE:COLUMN).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from rich.console import Console

from hdrc3.fault_trigger import FaultTrigger, TimedFault, parse_fault
from hdrc3.launch_plan import (
    CAMERA_NODES,
    CATALOG,
    EXECUTION_MONITOR,
    LASER_MAPPER,
    RAW_IMAGES,
    check_topic_pattern,
)
from hdrc3.launched_system import LaunchedSystem
from hdrc3.mission_run import Outcome, fly, replies_ok, settle, status_line, write_timeline
from hdrc3.safety_pilot import hand_over
from hdrc3.saliency_output import collect
from hdrc3_base.agents import parse_agents
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_tst.check import CheckStatus, load_file, tree_lines
from hdrc3_tst.mission_client import Reply, TstClient
from hdrc3_tst.model import NodeKind

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_REFUSED = 3
EXIT_INVALID = 4


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``tst`` subcommand."""
    parser = subparsers.add_parser(
        "tst", help="task specification trees: check, run, abort, pause, resume, set"
    )
    actions = parser.add_subparsers(dest="tst_action", metavar="ACTION", required=True)
    check = actions.add_parser(
        "check",
        help="parse, resolve and propagate a .tst file; print the tree with its time windows",
        description="Exit codes: 0 ok, 4 invalid input (errors as FILE:LINE:COLUMN).",
    )
    check.add_argument("file", help="a .tst file (examples/tst/)")
    check.add_argument(
        "--agents", default=None, help="agents in addition to the file's own, e.g. uav0,uav1"
    )
    check.set_defaults(handler=_check)

    run = actions.add_parser(
        "run",
        help="execute a mission on the agents' TST managers, one line per node state change",
        description=__doc__.split("\n\n")[-1] if __doc__ else None,
    )
    run.add_argument("file", help="a .tst file (examples/tst/)")
    run.add_argument("--agents", default=None, help="agents, e.g. uav0,uav1 (default: the file's)")
    run.add_argument("--mission", default=None, help="mission id (default: FILE stem + time)")
    run.add_argument("--launch", action="store_true", help="start the system first")
    run.add_argument("--world", default=None, help="with --launch: world (default: the file's)")
    run.add_argument(
        "--sim-world",
        default=None,
        metavar="WORLD",
        help="with --launch: the world the simulator makes real when the stack's model (--world)"
        " is stale, e.g. revinge_changed (what a laser-map-area node then finds)",
    )
    run.add_argument("--speed", default="max", help="with --launch: real-time factor or 'max'")
    run.add_argument("--domain-id", type=int, default=43, help="with --launch: ROS domain")
    run.add_argument(
        "--seed", type=int, default=0, help="with --launch: simulation seed (sensor outages)"
    )
    run.add_argument(
        "--out",
        default=None,
        help="directory for run.mcap, timeline.csv and (a launched scan) saliency.geojson",
    )
    run.add_argument(
        "--record-exclude",
        metavar="REGEX",
        default=RAW_IMAGES,
        help="with --launch --out: topics the recording leaves out (default: the cameras' raw"
        " images, %(default)r; '' records every topic)",
    )
    run.add_argument(
        "--timeout", type=float, default=3600.0, help="wall seconds to wait for the root"
    )
    run.add_argument(
        "--fault",
        action="append",
        default=[],
        metavar="AGENT:SENSOR:MODE@NODE+S",
        help="inject a world_sim fault S sim seconds after NODE (a node id, or ACTION#N: the N-th"
        " node of that action on AGENT) started running, e.g. uav0:hook:release@fly-to#2+6"
        " (repeatable)",
    )
    run.set_defaults(handler=_run)

    abort = actions.add_parser("abort", help="abort a running mission: every aircraft hovers")
    abort.add_argument("mission", help="the mission id `hdrc3 tst run` printed")
    abort.add_argument("--agents", required=True, help="the mission's agents, e.g. uav0,uav1")
    abort.add_argument("--reason", default="aborted by the operator")
    abort.set_defaults(handler=_abort)

    for word, resume, what in (
        ("pause", False, "pause a mission's running actions: every aircraft brakes and hovers"),
        ("resume", True, "resume a paused mission's actions from where the aircraft are"),
    ):
        sub = actions.add_parser(word, help=what)
        sub.add_argument("mission", help="the mission id `hdrc3 tst run` printed")
        sub.add_argument("--agents", required=True, help="the mission's agents, e.g. uav0,uav1")
        sub.set_defaults(handler=_pause, resume=resume)

    setp = actions.add_parser("set", help="fix an open parameter of a mission's node")
    setp.add_argument("mission")
    setp.add_argument("node")
    setp.add_argument("param")
    setp.add_argument("value", help="a number in the parameter's unit, or a name")
    setp.add_argument("--agents", required=True, help="the mission's agents, e.g. uav0,uav1")
    setp.set_defaults(handler=_set)


def _check(args: argparse.Namespace) -> int:
    agents = parse_agents(args.agents) if args.agents is not None else ()
    result = load_file(args.file, agents)
    for diag in result.diagnostics:
        print(diag, flush=True)
    if result.status is not CheckStatus.OK or result.tst is None:
        print(f"{args.file}: {result.status.value}", flush=True)
        return EXIT_INVALID
    for line in tree_lines(result.tst):
        print(line, flush=True)
    tst = result.tst
    net = tst.network
    n_cons = len(net.finite.linear) + len(net.finite.symbolic)
    print(
        f"{args.file}: ok ({len(tst.tree.nodes)} nodes, {len(net.stn.variables)} time "
        f"variables, {net.stn.edge_count} temporal and {n_cons} other constraints)",
        flush=True,
    )
    return EXIT_OK


def _console() -> Console:
    # soft wrap: one line per event even when piped to a file (no wrapping at 80 columns)
    # no markup: node ids of foreach instances contain brackets (m[uav1]/s)
    return Console(highlight=False, soft_wrap=True, markup=False)


def _on_agents(
    args: argparse.Namespace,
    call: Callable[[TstClient, tuple[str, ...]], list[Reply]],
    refused: int,
) -> int:
    """Call every agent given with ``--agents``; print the replies; 0 or ``refused``."""
    console = _console()
    with RosProcess() as process:
        ok = replies_ok(console.print, call(TstClient(process), parse_agents(args.agents)))
    return EXIT_OK if ok else refused


def _abort(args: argparse.Namespace) -> int:
    return _on_agents(args, lambda c, a: c.abort(args.mission, a, args.reason), EXIT_REFUSED)


def _pause(args: argparse.Namespace) -> int:
    return _on_agents(args, lambda c, a: c.pause(args.mission, a, args.resume), EXIT_REFUSED)


def _set(args: argparse.Namespace) -> int:
    return _on_agents(
        args,
        lambda c, a: c.set(args.mission, a, args.node, args.param, args.value),
        EXIT_INVALID,
    )


def _run(args: argparse.Namespace) -> int:
    console = _console()
    path = Path(args.file)
    check = load_file(path, parse_agents(args.agents) if args.agents else ())
    for diag in check.diagnostics:
        console.print(str(diag))
    if check.status is not CheckStatus.OK or check.tst is None:
        console.print(f"{path}: {check.status.value}")
        return EXIT_INVALID
    agents = parse_agents(args.agents) if args.agents else check.tst.agents
    mission = args.mission or f"{path.stem}-{int(time.time())}"
    faults = [parse_fault(text) for text in args.fault]
    exclude = check_topic_pattern(args.record_exclude)
    out = Path(args.out) if args.out else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    if not args.launch:
        return _execute(console, path, mission, agents, out, args.timeout, faults=faults)
    world = args.world or check.tst.world
    if world is None:
        raise ConfigError("--launch needs a world: the file declares none; give --world")
    nodes = [k.name for k in CATALOG if k.default] + ["tst_manager", "task_planner", "path_planner"]
    if any(node.kind is NodeKind.GOAL for node in check.tst.tree.nodes.values()):
        nodes.append(EXECUTION_MONITOR)  # violations recover planned goals (chapter 9.3)
    scans = any(node.action == "scan-area" for node in check.tst.tree.nodes.values())
    if scans:
        nodes += CAMERA_NODES  # a scan builds the saliency map from rendered images
    if any(node.action == "laser-map-area" for node in check.tst.tree.nodes.values()):
        nodes.append(LASER_MAPPER)  # the elevation map goes to the path planner's GIS (11.2)
    record = out / "run.mcap" if out is not None else None
    extra = ["--sim-world", args.sim_world] if args.sim_world else []
    if record is not None and exclude:
        extra += ["--record-exclude", exclude]
    system = LaunchedSystem(
        agents, world, args.speed, args.domain_id, record, nodes, console.print, args.seed, extra
    )
    scanned = world if scans else None
    with system:
        code = _execute(
            console,
            path,
            mission,
            agents,
            out,
            args.timeout,
            hand_over_first=True,
            scanned=scanned,
            faults=faults,
        )
    if record is not None:
        console.print(f"recording: {record}")
    return code


def _execute(
    console: Console,
    path: Path,
    mission: str,
    agents: tuple[str, ...],
    out: Path | None,
    timeout: float,
    hand_over_first: bool = False,
    scanned: str | None = None,
    faults: Sequence[TimedFault] = (),
) -> int:
    """Create and run the mission; ``scanned``: the world, when the run builds saliency maps."""
    with RosProcess() as process:
        client = TstClient(process)
        trigger = FaultTrigger(client.node, faults, console.print)

        def on_status(msg: Any) -> None:
            console.print(status_line(msg))
            trigger.on_status(msg)

        client.on_status = on_status
        if hand_over_first:
            for agent in agents:
                hand_over(process, client.node, agent)
                console.print(f"safety pilot: {agent} engine on, RC switch to autonomous")
        text = path.read_text(encoding="utf-8")
        flown = fly(process, client, console.print, mission, text, str(path), agents, timeout)
        if flown.outcome is Outcome.INVALID:
            return EXIT_INVALID
        if flown.outcome is Outcome.REFUSED:
            return EXIT_REFUSED
        for fault in trigger.not_injected():
            console.print(f"fault: {fault} was never injected (its node never ran long enough)")
        if hand_over_first:
            settle(process, client)
        latest = client.latest(mission)
        if out is not None and scanned is not None:
            got = collect(process, client.node, agents, scanned, out / "saliency.geojson")
            console.print(
                f"saliency map: {got.locations} locations, {got.confirmed} confirmed: {got.path}"
            )
            for agent in got.missing:
                console.print(f"  no saliency map from {agent}")
            for line in got.refused:
                console.print(f"  map refused: {line}")
    if out is not None:
        write_timeline(out / "timeline.csv", latest)
        console.print(f"timeline: {out / 'timeline.csv'}")
    console.print(flown.verdict)
    return EXIT_OK if flown.outcome is Outcome.SUCCEEDED else EXIT_FAILED
