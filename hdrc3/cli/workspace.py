"""`hdrc3 workspace DIR`: a colcon workspace of hdrc3's packages (hdrc3/ros_workspace.py)."""

from __future__ import annotations

import argparse
from pathlib import Path

import hdrc3
from hdrc3.ros_workspace import read_project, write_workspace
from hdrc3_base.errors import ConfigError


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``workspace`` subcommand."""
    parser = subparsers.add_parser(
        "workspace",
        help="write a colcon workspace of hdrc3's packages (ros2 run hdrc3_control ...)",
        description="Writes DIR/src/<package>/ (package.xml, setup.py, setup.cfg, a link to the "
        "sources) for every hdrc3 package; then `cd DIR && colcon build` in a sourced ROS 2 "
        "Jazzy environment (hdrc3_interfaces from the underlay) and `ros2 run hdrc3_control "
        "control_kernel`.",
    )
    parser.add_argument("out", type=Path, metavar="DIR", help="the workspace directory")
    parser.add_argument(
        "--source",
        type=Path,
        default=None,
        help="the hdrc3 source checkout (default: the one this hdrc3 runs from)",
    )
    parser.set_defaults(handler=_workspace)


def _workspace(args: argparse.Namespace) -> int:
    root: Path = args.source or Path(hdrc3.__file__).resolve().parents[1]
    if not (root / "pyproject.toml").is_file():
        raise ConfigError(f"{root} is not an hdrc3 source checkout (no pyproject.toml): --source")
    packages = write_workspace(args.out, read_project(root))
    for package in packages:
        executables = ", ".join(sorted(package.executables)) or "(no executables)"
        print(f"{args.out / 'src' / package.name}: {executables}", flush=True)
    print(f"next: cd {args.out} && colcon build", flush=True)
    return 0
