"""``hdrc3 fcl AGENT COMMAND [ARGS...]``: call an FCL service and wait for its completion.

Prints the immediate answer, then (unless ``--no-wait``) progress events and the completion
event of the command. Exit 0 only for FCL_FINISHED, or FCL_OK for cancel, emergency_brake and
``--no-wait``; 1 for any other answer or outcome (busy, not accepted, failed, cancelled, timeout);
2 for bad input (unknown command, wrong argument count, unknown agent).
"""

from __future__ import annotations

import argparse
import math

from hdrc3_base.errors import ConfigError

COMMANDS: dict[str, tuple[str, ...]] = {
    "takeoff": (),
    "land": ("HEADING_DEG",),
    "yaw": ("HEADING_DEG",),
    "climb": ("ALTITUDE_M",),
    "traj3d_flyto": ("LON", "LAT", "ALT_M", "VELOCITY"),
    "traj3d": (
        "SX",
        "SY",
        "SZ",
        "EX",
        "EY",
        "EZ",
        "SDX",
        "SDY",
        "SDZ",
        "EDX",
        "EDY",
        "EDZ",
        "VELOCITY",
        "END_VELOCITY",
    ),
    "track": (),
    "emergency_brake": (),
    "cancel": (),
}
CODE_NAMES = {0: "FCL_OK", 1: "FCL_BUSY", 2: "FCL_NOT_ACCEPTED", 3: "FCL_FINISHED"}
KIND_NAMES = {0: "FCL_FINISHED", 1: "FAILED", 2: "CANCELLED", 3: "SEGMENT_REQUEST", 4: "INFO"}


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``fcl`` command."""
    usage = "; ".join(f"{c} {' '.join(a)}".strip() for c, a in COMMANDS.items())
    parser = subparsers.add_parser(
        "fcl",
        help="Flight Control Language command to an agent's Platform Server (chapter 6.2.2)",
        description=(
            "Commands: " + usage + ". Headings in degrees clockwise from north, altitudes in "
            "metres above the WGS84 ellipsoid, lon/lat in degrees, traj3d points in local ENU "
            "metres. Exit 0 only for FCL_FINISHED (FCL_OK for cancel/emergency_brake/--no-wait)."
        ),
    )
    parser.add_argument("agent", help="agent name (ROS namespace), e.g. uav0")
    parser.add_argument("fcl_command", metavar="COMMAND", choices=sorted(COMMANDS))
    parser.add_argument("args", nargs="*", metavar="ARG")
    parser.add_argument("--no-wait", action="store_true", help="return after the immediate answer")
    parser.add_argument(
        "--timeout", type=float, default=300.0, help="wall-clock seconds to wait (default 300)"
    )
    parser.set_defaults(handler=run)


def parse_numbers(command: str, texts: list[str]) -> tuple[float, ...]:
    """Arguments of ``command`` as numbers (ConfigError on wrong count or non-numbers)."""
    names = COMMANDS[command]
    if len(texts) != len(names):
        raise ConfigError(
            f"{command} takes {len(names)} argument(s) ({' '.join(names) or '-'}), got {len(texts)}"
        )
    try:
        return tuple(float(t) for t in texts)
    except ValueError:
        raise ConfigError(f"{command}: arguments must be numbers, got {texts}") from None


def build_request(command: str, values: tuple[float, ...]) -> tuple[object, object]:
    """The service type and request of one command."""
    from hdrc3_platform_server.codes import FclCommand
    from hdrc3_platform_server.node import FCL_SERVICES

    srv, _ = FCL_SERVICES[FclCommand(command)]
    req = srv.Request()
    if command in ("land", "yaw"):
        req.heading = math.radians(values[0])
    elif command == "climb":
        req.altitude = values[0]
    elif command == "traj3d_flyto":
        req.longitude, req.latitude, req.altitude, req.velocity = values
    elif command == "traj3d":
        s = req.segment
        s.start_point.x, s.start_point.y, s.start_point.z = values[0:3]
        s.end_point.x, s.end_point.y, s.end_point.z = values[3:6]
        s.start_direction.x, s.start_direction.y, s.start_direction.z = values[6:9]
        s.end_direction.x, s.end_direction.y, s.end_direction.z = values[9:12]
        req.velocity, req.end_velocity = values[12], values[13]
        s.target_velocity, s.end_velocity = values[12], values[13]
    return srv, req


def run(args: argparse.Namespace) -> int:
    """Handler of ``hdrc3 fcl``."""
    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_platform_server.client import PlatformClient, check_agent

    check_agent(args.agent)
    values = parse_numbers(args.fcl_command, args.args)
    if not (math.isfinite(args.timeout) and args.timeout > 0):
        raise ConfigError(f"--timeout must be > 0, got {args.timeout}")
    srv, req = build_request(args.fcl_command, values)
    label = f"fcl_{args.fcl_command}"
    with RosProcess(args=[]) as process:
        client = PlatformClient(process, args.agent)
        response = client.call(srv, f"fcl/{args.fcl_command}", req, min(args.timeout, 10.0))
        if response is None:
            print(f"{label}: no answer from the platform server", flush=True)
            return 1
        result = response.result
        code = CODE_NAMES.get(int(result.code), str(result.code))
        reason = f": {result.reason}" if result.reason else ""
        print(f"{label}: {code} (command {result.command_id}){reason}", flush=True)
        if int(result.code) != 0:
            return 1
        if args.no_wait or args.fcl_command in ("cancel", "emergency_brake"):
            return 0

        def progress(event: object) -> None:
            kind = KIND_NAMES.get(int(getattr(event, "kind", -1)), "?")
            text = getattr(event, "reason", "")
            print(
                f"{label}: {kind} (command {result.command_id}){': ' + text if text else ''}",
                flush=True,
            )

        final = client.wait_final(int(result.command_id), args.timeout, progress)
        if final is None:
            print(f"{label}: no completion event within {args.timeout:g} s", flush=True)
            return 1
        progress(final)
        return 0 if int(final.kind) == 0 else 1
