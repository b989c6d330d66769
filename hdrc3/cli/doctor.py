"""`hdrc3 doctor`: versions, DDS settings and a loopback self-test: the first thing to run."""

from __future__ import annotations

import argparse
import importlib
import importlib.metadata
import os
import sys

from hdrc3_base.ros_env import DISCOVERY_RANGE_VAR, PROFILES_VARS

_DISTRIBUTIONS = (
    ("rclpy", "ros-jazzy-rclpy"),
    ("JSBSim", "jsbsim"),
    ("OMPL", "ompl"),
    ("python-fcl", "python-fcl"),
    ("mcap", "mcap"),
    ("lark", "lark"),
)
_INTERFACE_MODULES = ("hdrc3_interfaces.msg", "hdrc3_interfaces.srv", "hdrc3_interfaces.action")


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `doctor` subcommand."""
    parser = subparsers.add_parser("doctor", help="check the installation and DDS settings")
    parser.add_argument(
        "--no-selftest", action="store_true", help="skip the publish/subscribe self-test"
    )
    parser.set_defaults(handler=run)


def _version(distribution: str) -> str:
    try:
        return importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return "NOT INSTALLED"


def _selftest() -> str:
    """Publish one message to ourselves through DDS; return "ok" or what went wrong."""
    from rclpy.node import Node
    from std_msgs.msg import String

    from hdrc3_base.ros_runtime import RosProcess

    received: list[String] = []
    with RosProcess(handle_signals=False) as process:
        node = process.add_node(Node("hdrc3_doctor", context=process.context))
        node.create_subscription(String, "/hdrc3_doctor/ping", received.append, 10)
        pub = node.create_publisher(String, "/hdrc3_doctor/ping", 10)
        ok = process.spin_until(
            lambda: bool(received),
            timeout_s=5.0,
            tick=lambda: pub.publish(String(data="ping")),
        )
        node.destroy_node()
    return "ok" if ok else "FAILED: no message came back within 5 s"


def run(args: argparse.Namespace) -> int:
    """Print the report; exit 1 when something essential is missing."""
    healthy = True
    print(f"python              {sys.version.split()[0]} ({sys.executable})")
    for label, dist in _DISTRIBUTIONS:
        version = _version(dist)
        healthy &= version != "NOT INSTALLED"
        print(f"{label:<19} {version}")
    try:
        from rclpy.utilities import get_rmw_implementation_identifier

        print(f"rmw implementation  {get_rmw_implementation_identifier()}")
    except ImportError as exc:
        healthy = False
        print(f"rmw implementation  UNAVAILABLE ({exc})")
    print(f"ROS_DOMAIN_ID       {os.environ.get('ROS_DOMAIN_ID', '0 (default)')}")
    print(f"{DISCOVERY_RANGE_VAR} {os.environ.get(DISCOVERY_RANGE_VAR)}")
    for var in PROFILES_VARS:
        if os.environ.get(var):
            print(f"{var} {os.environ[var]}")
    for module in _INTERFACE_MODULES:
        try:
            importlib.import_module(module)
            print(f"import {module:<28} ok")
        except ImportError as exc:
            healthy = False
            print(f"import {module:<28} FAILED ({exc}); run `make setup`")
    if not args.no_selftest and healthy:
        result = _selftest()
        healthy &= result == "ok"
        print(f"DDS loopback pub/sub {result}")
    print("healthy" if healthy else "PROBLEMS FOUND")
    return 0 if healthy else 1
