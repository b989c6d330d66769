"""`hdrc3 report`: an HTML page with figures from any recording (hdrc3/report_page.py)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rich.console import Console

from hdrc3.cli.progress import message_bar
from hdrc3.mission_report import read_mission
from hdrc3.report_page import write_report


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``report`` subcommand."""
    parser = subparsers.add_parser(
        "report", help="write an HTML report with figures from a recording (MCAP)"
    )
    parser.add_argument("recording", type=Path, help="an MCAP file from hdrc3 record / launch")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="output directory (default: RECORDING's stem + _report)",
    )
    parser.set_defaults(handler=_report)


def _report(args: argparse.Namespace) -> int:
    recording: Path = args.recording
    out: Path = args.out or recording.with_name(recording.stem + "_report")
    console = Console(stderr=True)
    with message_bar(console, "reading") as bar:
        task = bar.add_task("read", total=None, name=recording.name)

        def progress(done: int, total: int | None) -> None:
            bar.update(task, completed=done, total=total)

        data = read_mission(recording, progress)
    print(f"read {data.messages} messages on {len(data.topics)} topics", flush=True)
    for problem in data.problems:
        print(f"warning: {problem}", file=sys.stderr, flush=True)
    for flight in data.flights.values():
        print(
            f"{flight.agent}: {len(flight.track)} samples, {flight.distance:.0f} m flown, "
            f"{len(flight.events)} events",
            flush=True,
        )
    page = write_report(data, out)
    print(f"report: {page}", flush=True)
    return 0
