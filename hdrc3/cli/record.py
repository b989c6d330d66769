"""`hdrc3 record`: record topics to an MCAP file in the rosbag2 layout."""

from __future__ import annotations

import argparse
import sys
import time

from hdrc3.launch_plan import check_world
from hdrc3.live.view import LiveView
from hdrc3.mcap_recording import RecordingWriter
from hdrc3.recorder import RecorderNode
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from sim.world_loader import load_world

DRAIN_S = 1.5
"""After a stop request, keep writing what DDS already delivered for at most this long, s."""


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `record` subcommand."""
    parser = subparsers.add_parser(
        "record", help="record topics to MCAP (rosbag2 layout, CDR, ros2msg schemas)"
    )
    parser.add_argument("output", help="output file, e.g. run.mcap")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--topics", nargs="+", default=[], help="topics to record")
    which.add_argument("--all", action="store_true", help="record every topic (the default)")
    parser.add_argument("--exclude", help="regular expression of topics not to record")
    parser.add_argument("--duration", type=float, help="stop after this many seconds")
    parser.add_argument(
        "--live-channels",
        action="store_true",
        help="also write the live view's Foxglove channels (protobuf/JSON), converted from the "
        "recorded topics, so that the recording opens in foxglove/hdrc3.json; readers that "
        "decode only ROS messages (rosbag2, mcap-ros2-support) do not decode those channels",
    )
    parser.add_argument(
        "--world",
        default="revinge",
        help="with --live-channels: the world being flown, for the scene (default revinge)",
    )
    parser.add_argument(
        "--wait-topics",
        type=float,
        default=10.0,
        help="with --topics: fail if a topic has not appeared within this many seconds",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Record until SIGINT/SIGTERM or --duration; always leave a valid file."""
    if not str(args.output).endswith(".mcap"):
        raise ConfigError(f"output file {args.output} must end in .mcap")
    if args.duration is not None and not args.duration > 0:
        raise ConfigError(f"--duration must be positive, got {args.duration}")
    live = LiveView(load_world(check_world(args.world))) if args.live_channels else None
    writer = RecordingWriter(args.output)
    code = 0
    try:
        # the events executor: a recorder of every topic takes thousands of messages per second
        with RosProcess(events=True) as process:
            node = RecorderNode(process.context, writer, args.topics, args.exclude, live)
            process.add_node(node)
            start = time.monotonic()
            if (
                args.topics
                and not process.spin_until(
                    lambda: not node.missing_topics(), timeout_s=args.wait_topics
                )
                and not process.stop_requested.is_set()
            ):
                missing = ", ".join(sorted(node.missing_topics()))
                print(f"hdrc3 record: error: topic(s) not found: {missing}", file=sys.stderr)
                code = 2
            if code == 0:
                done = (
                    (lambda: time.monotonic() - start >= args.duration)
                    if args.duration is not None
                    else (lambda: False)
                )
                process.spin_until(done, timeout_s=float("inf"))
            node.drain(process.spin_once, DRAIN_S)
            node.destroy_node()
    finally:
        writer.close()
    print(
        f"recorded {writer.message_count} messages on {len(writer.topics)} topics to {args.output}"
    )
    return code
