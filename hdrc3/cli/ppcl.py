"""``hdrc3 ppcl AGENT COMMAND [ARGS...]``: a Payload and Perception Control Language command.

Ownership: ``request RESOURCE`` / ``release RESOURCE`` (ptu, camera, ip, laser; ``--owner``,
default ``cli``). Modes and parameters (turn_to, look_at, zoom, ...) print the immediate answer
and wait for the completion event. Queries (ptu_activity_info, get_camera_info,
min/max_pan/tilt_value) print their result. Angles in degrees at this edge. Exit 0 for PPCL_OK
(and a finished completion), 1 for any other answer or outcome, 2 for bad input.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from hdrc3.cli.platform_call import call, check_timeout, numbers, wait
from hdrc3_base.errors import ConfigError
from hdrc3_platform_server.codes import EventKind, PpclCode, PpclCommand, PtuActivity
from hdrc3_platform_server.commands import PPCL, CliInput, PpclSpec

RESOURCES = {"ptu": 0, "camera": 1, "ip": 2, "laser": 3}
CAMERAS = {"color": 0, "thermal": 1}
QUERIES = (
    "ptu_activity_info",
    "get_camera_info",
    "min_pan_value",
    "max_pan_value",
    "min_tilt_value",
    "max_tilt_value",
)


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``ppcl`` command."""
    words = ["request RESOURCE", "release RESOURCE"]
    words += [f"{c.value} {' '.join(_words(s))}".strip() for c, s in PPCL.items()]
    words += list(QUERIES)
    parser = subparsers.add_parser(
        "ppcl",
        help="Payload and Perception Control Language command (chapter 6.2.3)",
        description="Commands: " + "; ".join(words) + ". RESOURCE: ptu, camera, ip, laser.",
    )
    parser.add_argument("agent", help="agent name (ROS namespace), e.g. uav0")
    parser.add_argument(
        "ppcl_command",
        metavar="COMMAND",
        choices=["request", "release", *(c.value for c in PPCL), *QUERIES],
    )
    parser.add_argument("args", nargs="*", metavar="ARG")
    parser.add_argument("--owner", default="cli", help="owner name for request/release")
    parser.add_argument("--camera", choices=sorted(CAMERAS), default="color")
    parser.add_argument("--no-wait", action="store_true", help="return after the immediate answer")
    parser.add_argument("--timeout", type=float, default=60.0, help="wall-clock seconds to wait")
    parser.set_defaults(handler=run)


def _words(spec: PpclSpec) -> list[str]:
    """The positional words of a command, optional ones in brackets."""
    return [
        f"[{a.cli}]" if a.source is CliInput.OPTIONAL else a.cli for a in spec.arguments if a.cli
    ]


def _numbers(command: str, texts: list[str], count: int, optional: int = 0) -> list[float]:
    if not count - optional <= len(texts) <= count:
        raise ConfigError(
            f"{command} takes {count - optional}..{count} argument(s), got {len(texts)}"
        )
    return list(numbers(command, texts))


def build_request(args: argparse.Namespace) -> tuple[Any, str, Any]:
    """(service type, service name, request) of one command; ConfigError on bad input."""
    from hdrc3_interfaces.srv import (
        PpclControl,
        PpclGetCameraInfo,
        PpclPtuActivityInfo,
        PpclPtuLimits,
    )

    cmd, texts, camera = args.ppcl_command, list(args.args), CAMERAS[args.camera]
    if cmd in ("request", "release"):
        if len(texts) != 1 or texts[0] not in RESOURCES:
            raise ConfigError(f"{cmd} takes one resource: {', '.join(RESOURCES)}")
        req = PpclControl.Request()
        req.resource, req.request, req.owner = RESOURCES[texts[0]], cmd == "request", args.owner
        return PpclControl, "ppcl/control", req
    if cmd in QUERIES:
        _numbers(cmd, texts, 0)
        if cmd == "ptu_activity_info":
            return PpclPtuActivityInfo, "ppcl/ptu_activity_info", PpclPtuActivityInfo.Request()
        if cmd == "get_camera_info":
            info = PpclGetCameraInfo.Request()
            info.camera_id = camera
            return PpclGetCameraInfo, "ppcl/get_camera_info", info
        return PpclPtuLimits, "ppcl/ptu_limits", PpclPtuLimits.Request()
    spec = PPCL[PpclCommand(cmd)]
    srv = spec.service_type()
    req = srv.Request()
    numeric = [a for a in spec.arguments if a.source in (CliInput.NUMBER, CliInput.OPTIONAL)]
    words = [a for a in spec.arguments if a.source is CliInput.AUTO_MANUAL]
    if words and (len(texts) != 1 or texts[0] not in ("auto", "manual")):
        raise ConfigError(f"{cmd} takes 'auto' or 'manual'")
    optional = sum(a.source is CliInput.OPTIONAL for a in numeric)
    v = [] if words else _numbers(cmd, texts, len(numeric), optional)
    given = dict(zip(numeric, v, strict=False))
    for a in spec.arguments:
        if a in given:
            a.write(req, a.from_cli(given[a]))
        elif a.source is CliInput.GIVEN:
            a.write(req, float(len(v) == len(numeric)))
        elif a.source is CliInput.CAMERA:
            a.write(req, float(camera))
        elif a.source is CliInput.AUTO_MANUAL:
            a.write(req, float(texts[0] == "auto"))
    return srv, f"ppcl/{cmd}", req


def _print_query(cmd: str, response: Any) -> None:
    if cmd == "ptu_activity_info":
        try:
            print(f"PPCL_{PtuActivity(int(response.activity)).name}")
        except ValueError:  # an activity of a newer server: shown as its number
            print(str(response.activity))
    elif cmd == "get_camera_info":
        r = response
        print(
            f"width {r.width} height {r.height} fx {r.fx:.2f} fy {r.fy:.2f} cx {r.cx:.1f} "
            f"cy {r.cy:.1f} zoom {r.zoom:.3f} hfov {math.degrees(r.hfov):.2f} deg"
        )
    else:
        value = {
            "min_pan_value": response.min_pan,
            "max_pan_value": response.max_pan,
            "min_tilt_value": response.min_tilt,
            "max_tilt_value": response.max_tilt,
        }[cmd]
        print(f"{math.degrees(value):.2f} deg ({value:.6f} rad)")


def run(args: argparse.Namespace) -> int:
    """Handler of ``hdrc3 ppcl``."""
    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_platform_server.client import PlatformClient, check_agent

    check_agent(args.agent)
    check_timeout(args.timeout)
    srv, name, req = build_request(args)
    cmd = args.ppcl_command
    label = f"ppcl_{cmd}"
    with RosProcess(args=[]) as process:
        client = PlatformClient(process, args.agent)
        response = call(client, label, (srv, name, req), PpclCode, "PPCL_", args.timeout)
        if response is None or int(response.result.code) != PpclCode.OK:
            return 1
        if cmd in QUERIES:
            _print_query(cmd, response)
            return 0
        if args.no_wait or int(response.result.command_id) == 0:
            return 0
        return wait(client, label, int(response.result.command_id), args.timeout, _kind_name)


def _kind_name(kind: EventKind) -> str:
    return kind.name
