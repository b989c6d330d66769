"""The `hdrc3` command: one argparse parser, one module per subcommand.

Each subcommand module exposes ``register(subparsers)``, which adds its parser and sets
``handler`` (a callable taking the parsed namespace and returning the exit code) as default.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from hdrc3 import __version__
from hdrc3_base.errors import Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults

# Subcommand modules, in the order `hdrc3 --help` lists them.
COMMAND_MODULES: tuple[str, ...] = (
    "hdrc3.cli.launch",
    "hdrc3.cli.record",
    "hdrc3.cli.replay",
    "hdrc3.cli.report",
    "hdrc3.cli.live",
    "hdrc3.cli.doctor",
    "hdrc3.cli.demo",
    "hdrc3.cli.hcsm",
    "hdrc3.cli.world",
    "hdrc3.cli.plan",
    "hdrc3.cli.path",
    "hdrc3.cli.tst",
    "hdrc3.cli.talf",
    "hdrc3.cli.keys",
    "hdrc3.cli.delegate",
    "hdrc3.cli.monitor",
    "hdrc3.cli.fcl",
    "hdrc3.cli.ppcl",
    "hdrc3.cli.state",
    "hdrc3.cli.rc",
    "hdrc3.cli.workspace",
)


def build_parser() -> argparse.ArgumentParser:
    """Build the full `hdrc3` argument parser."""
    parser = argparse.ArgumentParser(
        prog="hdrc3", description="HDRC3 autonomy stack for unmanned helicopters (ROS 2 Jazzy)."
    )
    parser.add_argument("--version", action="version", version=f"hdrc3 {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module_name in COMMAND_MODULES:
        importlib.import_module(module_name).register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the `hdrc3` command; bad input ends in a one-line error and exit code 2."""
    apply_dds_defaults()
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code: int = args.handler(args)
    except Hdrc3Error as exc:
        print(f"hdrc3 {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    return code


if __name__ == "__main__":
    sys.exit(main())
