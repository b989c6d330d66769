"""``hdrc3 fcl AGENT COMMAND [ARGS...]``: call an FCL service and wait for its completion.

Prints the immediate answer, then (unless ``--no-wait``) progress events and the completion
event of the command. Exit 0 only for FCL_FINISHED, or FCL_OK for cancel, emergency_brake and
``--no-wait``; 1 for any other answer or outcome (busy, not accepted, failed, cancelled, timeout);
2 for bad input (unknown command, wrong argument count, unknown agent). Commands, argument words
and units come from the registry (``hdrc3_platform_server.commands``).

``track`` (reactive car following) has no end of its own: it runs until ``hdrc3 fcl AGENT
cancel`` (CANCELLED) or until the car is lost (FAILED), so waiting for it ends with exit 1. With
``--no-wait`` it returns once the PFC has answered: 0 when it accepted (the aircraft follows the
car), 1 when it refused (e.g. no colour track: ``ppcl ip_color_tracker`` first).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from hdrc3.cli.platform_call import call, check_timeout, numbers, wait
from hdrc3_base.errors import ConfigError
from hdrc3_platform_server.codes import EventKind, FclCode, FclCommand
from hdrc3_platform_server.commands import FCL

if TYPE_CHECKING:
    from hdrc3_platform_server.client import PlatformClient
    from hdrc3_platform_server.completion import CompletionEvent


def _words(command: str) -> tuple[str, ...]:
    return tuple(a.cli for a in FCL[FclCommand(command)].arguments)


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``fcl`` command."""
    usage = "; ".join(f"{c.value} {' '.join(_words(c.value))}".strip() for c in FCL)
    parser = subparsers.add_parser(
        "fcl",
        help="Flight Control Language command to an agent's Platform Server (chapter 6.2.2)",
        description=(
            "Commands: " + usage + ". Headings in degrees clockwise from north, altitudes in "
            "metres above the WGS84 ellipsoid, lon/lat in degrees, traj3d points in local ENU "
            "metres. Exit 0 only for FCL_FINISHED (FCL_OK for cancel/emergency_brake/--no-wait). "
            "track follows the car the colour tracker tracks (ppcl ip_color_tracker X Y first) "
            "until 'fcl AGENT cancel' (CANCELLED) or the car is lost (FAILED); with --no-wait it "
            "returns once the PFC accepted it (exit 0) or refused it (exit 1)."
        ),
    )
    parser.add_argument("agent", help="agent name (ROS namespace), e.g. uav0")
    parser.add_argument("fcl_command", metavar="COMMAND", choices=sorted(c.value for c in FCL))
    parser.add_argument("args", nargs="*", metavar="ARG")
    parser.add_argument(
        "--no-wait",
        action="store_true",
        help="return after the immediate answer (track: after the PFC's acceptance)",
    )
    parser.add_argument(
        "--timeout", type=float, default=300.0, help="wall-clock seconds to wait (default 300)"
    )
    parser.set_defaults(handler=run)


def parse_numbers(command: str, texts: list[str]) -> tuple[float, ...]:
    """Arguments of ``command`` as numbers (ConfigError on wrong count or non-numbers)."""
    names = _words(command)
    if len(texts) != len(names):
        raise ConfigError(
            f"{command} takes {len(names)} argument(s) ({' '.join(names) or '-'}), got {len(texts)}"
        )
    return numbers(command, texts)


def build_request(command: str, values: tuple[float, ...]) -> tuple[Any, Any]:
    """The service type and request of one command (CLI units converted to the service's)."""
    spec = FCL[FclCommand(command)]
    srv = spec.service_type()
    req = srv.Request()
    for argument, value in zip(spec.arguments, values, strict=True):
        argument.write(req, argument.from_cli(value))
    return srv, req


def _kind_name(kind: EventKind) -> str:
    # a finished FCL command is the chapter's FCL_FINISHED return (FclReturn.FCL_FINISHED)
    return f"FCL_{FclCode.FINISHED.name}" if kind is EventKind.FINISHED else kind.name


def run(args: argparse.Namespace) -> int:
    """Handler of ``hdrc3 fcl``."""
    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_platform_server.client import PlatformClient, check_agent

    check_agent(args.agent)
    values = parse_numbers(args.fcl_command, args.args)
    check_timeout(args.timeout)
    srv, req = build_request(args.fcl_command, values)
    label = FclCommand(args.fcl_command).label
    with RosProcess(args=[]) as process:
        client = PlatformClient(process, args.agent)
        service = (srv, f"fcl/{args.fcl_command}", req)
        response = call(client, label, service, FclCode, "FCL_", args.timeout)
        if response is None or int(response.result.code) != FclCode.OK:
            return 1
        command_id = int(response.result.command_id)
        if args.no_wait and FclCommand(args.fcl_command) is FclCommand.TRACK:
            return wait_accepted(client, label, command_id, args.timeout)
        if args.no_wait or FCL[FclCommand(args.fcl_command)].returns_ok:
            return 0
        return wait(client, label, command_id, args.timeout, _kind_name)


ACCEPTED_PREFIX = "accepted"
"""Reason of the progress event the Platform Server sends for the PFC's acceptance."""


class _Answered(Exception):
    """The PFC's first word about a command arrived (ends :func:`wait_accepted`'s wait)."""


def wait_accepted(client: PlatformClient, label: str, command_id: int, timeout: float) -> int:
    """Wait for the PFC's acceptance (exit 0) or the command's end (exit 1)."""

    def show(event: CompletionEvent) -> None:
        reason = f": {event.reason}" if event.reason else ""
        print(f"{label}: {_kind_name(event.kind)} (command {command_id}){reason}", flush=True)
        # the Platform Server's progress event for the PFC's Cmd-Accepted-EV
        if event.kind is EventKind.INFO and event.reason.startswith(ACCEPTED_PREFIX):
            raise _Answered

    try:
        final = client.wait_final(command_id, timeout, show)
    except _Answered:
        return 0
    if final is None:
        print(f"{label}: no answer from the PFC within {timeout:g} s", flush=True)
        return 1
    show(final)
    return 1
