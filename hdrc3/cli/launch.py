"""`hdrc3 launch`: start, supervise and stop the nodes of one or more agents."""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

from hdrc3.launch_plan import (
    CAMERA_NODES,
    CATALOG,
    GATEWAY,
    LIVE_VIEW,
    LaunchOptions,
    build_plan,
    check_discovery,
    check_domain_id,
    check_keystore,
    check_live_port,
    check_monitor_spec,
    check_record_path,
    check_seed,
    check_topic_pattern,
    check_world,
    parse_capabilities,
    parse_nodes,
    parse_speed,
)
from hdrc3.launcher import LauncherNode
from hdrc3.live import DEFAULT_PORT
from hdrc3.supervisor import Supervisor
from hdrc3.warm_spare import WarmSpare
from hdrc3_base.agents import parse_agents
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess

CONFLICT_WAIT_S = 1.5


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `launch` subcommand."""
    nodes = ", ".join(kind.name for kind in CATALOG)
    parser = subparsers.add_parser(
        "launch",
        help="start the hdrc3 nodes of one or more agents",
        description=f"Start and supervise hdrc3 nodes. Known nodes: {nodes}.",
    )
    parser.add_argument("--agents", default="uav0", help="comma-separated agents (default uav0)")
    parser.add_argument("--world", default="revinge", help="world to simulate (default revinge)")
    parser.add_argument(
        "--sim-world",
        metavar="WORLD",
        default=None,
        help="the world world_sim and world_render simulate when it differs from --world, the "
        "model the stack's nodes hold (e.g. revinge_changed: a stale map)",
    )
    parser.add_argument("--speed", default="1", help="real-time factor, or 'max' (default 1)")
    parser.add_argument("--record", metavar="FILE.mcap", help="record every topic to MCAP")
    parser.add_argument(
        "--record-exclude",
        metavar="REGEX",
        default=None,
        help="with --record: topics not to record, e.g. 'image_raw$' (the cameras' images)",
    )
    parser.add_argument("--domain-id", type=int, help="ROS_DOMAIN_ID for every node (0..101)")
    parser.add_argument("--nodes", help="comma-separated subset of nodes to start")
    parser.add_argument(
        "--live", action="store_true", help="also start the live view (Foxglove WebSocket)"
    )
    parser.add_argument(
        "--live-port", type=int, help="port of the live view on 127.0.0.1 (default 8765)"
    )
    parser.add_argument(
        "--monitor-spec",
        metavar="FILE",
        help="monitor formulas of the execution_monitor nodes (default: the packaged ones)",
    )
    parser.add_argument(
        "--cameras",
        action="store_true",
        help="also start world_render (colour and thermal images on /<agent>/camera/...) and "
        "each agent's saliency node (Algorithm 4 while the PPC engages it: ppcl ip_saliency)",
    )
    parser.add_argument(
        "--keystore",
        metavar="FILE",
        help="agent keys (hdrc3 keys generate); also starts each agent's gateway (delegation)",
    )
    parser.add_argument(
        "--acl-domain",
        type=int,
        help="ROS domain of the gateways' speech acts (default: the launch's own)",
    )
    parser.add_argument(
        "--acl-discovery",
        metavar="RANGE",
        help="discovery range of the ACL domain only, e.g. SUBNET inside a test's network "
        "namespaces (default: loopback, as everywhere)",
    )
    parser.add_argument(
        "--capabilities",
        metavar="AGENT=CAP+CAP",
        action="append",
        help="what an agent's gateway offers, e.g. uav2=flight+hook (default: everything)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="simulation seed: sensor noise, outages (default 0)"
    )
    parser.add_argument(
        "--ready-timeout", type=float, default=60.0, help="seconds to wait for every node"
    )
    parser.add_argument(
        "--cold-restarts", action="store_true",
        help="restart crashed nodes in new interpreters, without the pre-imported warm spare",
    )  # fmt: skip
    parser.set_defaults(handler=run)


def options_from(args: argparse.Namespace) -> LaunchOptions:
    """Validate the command line into launch options (raises ConfigError)."""
    return LaunchOptions(
        agents=parse_agents(args.agents),
        nodes=parse_nodes(args.nodes, extra=_extra_nodes(args)),
        world=check_world(args.world),
        sim_world=None if args.sim_world is None else check_world(args.sim_world),
        speed=parse_speed(args.speed),
        record=check_record_path(args.record),
        domain_id=check_domain_id(args.domain_id),
        seed=check_seed(args.seed),
        live_port=check_live_port(
            args.live_port if args.live_port is not None else DEFAULT_PORT if args.live else None
        ),
        monitor_spec=check_monitor_spec(args.monitor_spec),
        keystore=check_keystore(args.keystore),
        capabilities=parse_capabilities(args.capabilities, parse_agents(args.agents)),
        acl_domain=check_domain_id(args.acl_domain),
        acl_discovery=check_discovery(args.acl_discovery),
        record_exclude=check_topic_pattern(args.record_exclude),
    )


def _extra_nodes(args: argparse.Namespace) -> tuple[str, ...]:
    """The nodes the flags add: the renderer (``--cameras``), the live view (``--live``)."""
    live = args.live or args.live_port is not None
    gateway = (GATEWAY,) * bool(args.keystore)
    return CAMERA_NODES * bool(args.cameras) + (LIVE_VIEW,) * bool(live) + gateway


def run(args: argparse.Namespace) -> int:
    """Launch, print READY when every node is up, supervise until SIGINT/SIGTERM."""
    options = options_from(args)
    # run files (world_sim's checkpoint) live as long as the launch: a restarted node resumes
    with tempfile.TemporaryDirectory(prefix="hdrc3-launch-") as run_dir:
        return _launch(args, replace(options, run_dir=Path(run_dir)))


def _launch(args: argparse.Namespace, options: LaunchOptions) -> int:
    """Start the plan of ``options`` and supervise it (see :func:`run`)."""
    if options.domain_id is not None:
        os.environ["ROS_DOMAIN_ID"] = str(options.domain_id)
    specs = build_plan(options)
    # A restarted node runs in a warm spare, an interpreter that did its imports in advance: it
    # is up in well under a second instead of 3-4.5 s. The spare imports while the nodes start
    # (before READY), not later, when a mission may be flying. --cold-restarts: no spare.
    modules = [] if args.cold_restarts else [s.entry.partition(":")[0] for s in specs if s.entry]
    spare = WarmSpare(modules, lambda line: print(line, flush=True))
    with RosProcess() as process, spare:
        supervisor = Supervisor(specs, spawn=spare.spawn)
        launcher = LauncherNode(process.context, specs, supervisor=supervisor)
        process.add_node(launcher)
        domain = os.environ.get("ROS_DOMAIN_ID", "0")
        if process.spin_until(lambda: bool(launcher.conflicts()), timeout_s=CONFLICT_WAIT_S):
            raise ConfigError(
                f"ROS domain {domain} already runs {', '.join(launcher.conflicts())} "
                "(another hdrc3 launch?); choose another --domain-id"
            )
        spare.start()
        launcher.supervisor.start_all()
        # Discovery can be slower than CONFLICT_WAIT_S on a loaded machine, and two launches may
        # start together: a name of ours that shows up twice is a clash, and the younger launch
        # (by the start time in its launcher's name) stops; the older one keeps running.
        clash: list[str] = []

        def supervise() -> None:
            spare.collect()
            launcher.tick()
            if not clash and launcher.older_launch_present():
                clash[:] = launcher.conflicts(started=True)

        ready = process.spin_until(
            lambda: not launcher.missing() or bool(launcher.failed()) or bool(clash),
            timeout_s=args.ready_timeout,
            tick=supervise,
        )
        code = 0
        if ready and not launcher.failed() and not clash:
            names = ", ".join(s.node_name or s.name for s in specs)
            print(f"READY: {len(specs)} processes up ({names})", flush=True)
            process.spin_until(lambda: bool(clash), math.inf, 0.1, supervise)
        elif not process.stop_requested.is_set() and not clash:
            problem = launcher.failed() or launcher.missing()
            print(f"hdrc3 launch: error: not up: {', '.join(problem)}", file=sys.stderr)
            code = 1
        launcher.stop()
        print("stopped", flush=True)
        launcher.destroy_node()
    if clash:
        raise ConfigError(
            f"ROS domain {domain} already runs {', '.join(clash)} (another hdrc3 launch, "
            "started earlier); stopped. Give each launch its own --domain-id"
        )
    return code
