"""`hdrc3 replay`: republish a recording with its original timing."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from rich.console import Console

from hdrc3.cli.progress import message_bar
from hdrc3.mcap_recording import RecordingReader
from hdrc3.replayer import ReplayerNode, paced, select_topics
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `replay` subcommand."""
    parser = subparsers.add_parser("replay", help="republish an MCAP recording")
    parser.add_argument("input", help="recording, e.g. run.mcap")
    parser.add_argument("--speed", type=float, default=1.0, help="playback rate (default 1.0)")
    parser.add_argument("--loop", action="store_true", help="start again at the end")
    parser.add_argument("--topics", nargs="+", default=[], help="replay only these topics")
    parser.add_argument(
        "--wait-for-subscribers",
        type=float,
        default=0.0,
        metavar="S",
        help="before playing, wait up to S seconds until every topic has a subscriber",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Replay the recording; exit 0 when it played to the end (or was stopped)."""
    if not (math.isfinite(args.speed) and args.speed > 0):
        raise ConfigError(f"invalid --speed {args.speed}: expected a positive number")
    reader = RecordingReader.open(args.input)
    topics = select_topics(reader.topics(), args.topics)
    if not topics:
        raise ConfigError(f"{args.input} contains no messages")
    published = 0
    total = reader.message_count(topics)
    console = Console(stderr=True)
    with RosProcess() as process, message_bar(console, "replaying") as bar:
        task = bar.add_task("replay", total=total, name=Path(args.input).name)
        node = ReplayerNode(process.context, topics)
        process.add_node(node)
        if args.wait_for_subscribers > 0 and not process.spin_until(
            node.all_subscribed, timeout_s=args.wait_for_subscribers
        ):
            lonely = [
                t for t, p in node.publishers_by_topic.items() if p.get_subscription_count() == 0
            ]
            if lonely and not process.stop_requested.is_set():
                print(f"no subscriber for {', '.join(lonely)}; replaying anyway", flush=True)
        while not process.stop_requested.is_set():
            bar.reset(task, total=total)  # a loop plays the file again
            for message in paced(reader.messages(topics), args.speed, process.stop_requested.wait):
                node.publish(message)
                published += 1
                bar.advance(task)
            if not args.loop:
                break
        node.wait_for_acknowledgements(timeout_s=2.0)
        node.destroy_node()
    note = (
        " (recording truncated: played up to its last complete chunk)" if reader.truncated else ""
    )
    print(f"replayed {published} messages on {len(topics)} topics{note}", flush=True)
    return 0
