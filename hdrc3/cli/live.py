"""`hdrc3 live`: run the live view alone against a running system (Foxglove WebSocket)."""

from __future__ import annotations

import argparse

from hdrc3.launch_plan import check_domain_id, check_world
from hdrc3.live import DEFAULT_HOST, DEFAULT_PORT
from hdrc3_base.ros_runtime import RosProcess


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `live` subcommand."""
    parser = subparsers.add_parser(
        "live",
        help="serve the running system to Foxglove (WebSocket; layout foxglove/hdrc3.json)",
    )
    parser.add_argument("--port", type=int, default=DEFAULT_PORT, help="port (default 8765)")
    parser.add_argument(
        "--host",
        default=DEFAULT_HOST,
        help="address to bind (default 127.0.0.1; another exposes the view beyond this machine)",
    )
    parser.add_argument("--world", default="revinge", help="world being flown (default revinge)")
    parser.add_argument("--domain-id", type=int, help="ROS_DOMAIN_ID of the system (0..101)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Serve until SIGINT/SIGTERM; a port in use is a ConfigError (exit 2)."""
    from hdrc3.live.node import LiveViewNode  # rclpy and foxglove only when serving

    world = check_world(args.world)
    ros_args = ["--ros-args", "-p", f"world:={world}", "-p", f"port:={args.port}"]
    ros_args += ["-p", f"host:={args.host}"]
    with RosProcess(args=ros_args, domain_id=check_domain_id(args.domain_id)) as process:
        node = process.add_node(LiveViewNode(process.context))
        try:
            process.spin_until_stopped()
        finally:
            node.destroy_node()
    return 0
