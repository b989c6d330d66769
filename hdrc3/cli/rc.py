"""`hdrc3 rc`: the simulated safety pilot's transmitter (engine on/off, manual/autonomous)."""

from __future__ import annotations

import argparse

from hdrc3.safety_pilot import Switch, set_rc
from hdrc3_base.agents import parse_agents


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `rc` subcommand."""
    parser = subparsers.add_parser(
        "rc", help="the simulated safety pilot: engine and manual/autonomous switches"
    )
    parser.add_argument("agent", help="agent, e.g. uav0")
    parser.add_argument("--mode", choices=("manual", "autonomous"), help="flight mode switch")
    parser.add_argument("--engine", choices=("on", "off"), help="engine switch")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Set the switches; exit 0 when world_sim accepted them, 1 when it refused."""
    from rclpy.node import Node

    from hdrc3_base.ros_runtime import RosProcess

    (agent,) = parse_agents(args.agent)
    mode = Switch(args.mode) if args.mode else Switch.KEEP
    engine = Switch(args.engine) if args.engine else Switch.KEEP
    with RosProcess() as process:
        node = process.add_node(Node("hdrc3_rc", context=process.context))
        code, reason = set_rc(process, node, agent, mode, engine, timeout_s=10.0)
        node.destroy_node()
    print(f"rc {agent}: mode {mode.value}, engine {engine.value}: " + (reason or "ok"))
    return 0 if code == 0 else 1
