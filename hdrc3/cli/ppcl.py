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

from hdrc3_base.errors import ConfigError

RESOURCES = {"ptu": 0, "camera": 1, "ip": 2, "laser": 3}
CAMERAS = {"color": 0, "thermal": 1}
MODE_ARGS: dict[str, tuple[str, ...]] = {
    "look_at": ("LON", "LAT", "[ALT_M]"),
    "turn_to": ("PAN_DEG", "TILT_DEG"),
    "ptu_abort": (),
    "ip_color_tracker": ("X_PX", "Y_PX"),
    "ip_state_estimation": (),
    "ip_abort": (),
    "zoom": ("VALUE_0_1",),
    "exposure": ("auto|manual",),
    "iris": ("VALUE_0_1",),
    "shutter": ("SECONDS",),
    "laser_angular_resolution": ("DEG",),
    "laser_distance_resolution": ("METRES",),
    "laser_rotation_speed": ("RAD_PER_S",),
    "laser_rotation_angle": ("DEG",),
    "laser_start_data_collection": (),
    "laser_stop_data_collection": (),
}
QUERIES = (
    "ptu_activity_info",
    "get_camera_info",
    "min_pan_value",
    "max_pan_value",
    "min_tilt_value",
    "max_tilt_value",
)
CODE_NAMES = {0: "PPCL_OK", 1: "PPCL_CONTROL_DENIED", 2: "PPCL_NOT_ACCEPTED", 3: "PPCL_BUSY"}
KIND_NAMES = {0: "FINISHED", 1: "FAILED", 2: "CANCELLED", 3: "SEGMENT_REQUEST", 4: "INFO"}
ACTIVITY_NAMES = {0: "PPCL_LOOK_AT_POINT", 1: "PPCL_TURNTO", 2: "PPCL_IDLE"}


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``ppcl`` command."""
    words = ["request RESOURCE", "release RESOURCE"]
    words += [f"{c} {' '.join(a)}".strip() for c, a in MODE_ARGS.items()]
    words += list(QUERIES)
    parser = subparsers.add_parser(
        "ppcl",
        help="Payload and Perception Control Language command (chapter 6.2.3)",
        description="Commands: " + "; ".join(words) + ". RESOURCE: ptu, camera, ip, laser.",
    )
    parser.add_argument("agent", help="agent name (ROS namespace), e.g. uav0")
    parser.add_argument(
        "ppcl_command", metavar="COMMAND", choices=["request", "release", *MODE_ARGS, *QUERIES]
    )
    parser.add_argument("args", nargs="*", metavar="ARG")
    parser.add_argument("--owner", default="cli", help="owner name for request/release")
    parser.add_argument("--camera", choices=sorted(CAMERAS), default="color")
    parser.add_argument("--no-wait", action="store_true", help="return after the immediate answer")
    parser.add_argument("--timeout", type=float, default=60.0, help="wall-clock seconds to wait")
    parser.set_defaults(handler=run)


def _numbers(command: str, texts: list[str], count: int, optional: int = 0) -> list[float]:
    if not count - optional <= len(texts) <= count:
        raise ConfigError(
            f"{command} takes {count - optional}..{count} argument(s), got {len(texts)}"
        )
    try:
        return [float(t) for t in texts]
    except ValueError:
        raise ConfigError(f"{command}: arguments must be numbers, got {texts}") from None


def build_request(args: argparse.Namespace) -> tuple[Any, str, Any]:
    """(service type, service name, request) of one command; ConfigError on bad input."""
    from hdrc3_interfaces.srv import (
        PpclControl,
        PpclGetCameraInfo,
        PpclPtuActivityInfo,
        PpclPtuLimits,
    )
    from hdrc3_platform_server.codes import PpclCommand
    from hdrc3_platform_server.node import PPCL_SERVICES

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
    srv, _ = PPCL_SERVICES[PpclCommand(cmd)]
    req = srv.Request()
    if cmd == "exposure":
        if len(texts) != 1 or texts[0] not in ("auto", "manual"):
            raise ConfigError("exposure takes 'auto' or 'manual'")
        req.camera_id, req.auto_exposure = camera, texts[0] == "auto"
        return srv, f"ppcl/{cmd}", req
    count = len([a for a in MODE_ARGS[cmd]])
    optional = sum(a.startswith("[") for a in MODE_ARGS[cmd])
    v = _numbers(cmd, texts, count, optional)
    if cmd == "look_at":
        req.longitude, req.latitude = v[0], v[1]
        req.has_altitude = len(v) == 3
        req.altitude = v[2] if len(v) == 3 else 0.0
    elif cmd == "turn_to":
        req.pan, req.tilt = math.radians(v[0]), math.radians(v[1])
    elif cmd == "ip_color_tracker":
        req.x, req.y = v
    elif cmd in ("zoom", "iris", "shutter"):
        req.camera_id, req.value = camera, v[0]
    elif cmd == "laser_rotation_angle":
        req.value = math.radians(v[0])
    elif v:
        req.value = v[0]
    return srv, f"ppcl/{cmd}", req


def _print_query(cmd: str, response: Any) -> None:
    if cmd == "ptu_activity_info":
        print(ACTIVITY_NAMES.get(int(response.activity), str(response.activity)))
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
    if not (math.isfinite(args.timeout) and args.timeout > 0):
        raise ConfigError(f"--timeout must be > 0, got {args.timeout}")
    srv, name, req = build_request(args)
    cmd = args.ppcl_command
    label = f"ppcl_{cmd}"
    with RosProcess(args=[]) as process:
        client = PlatformClient(process, args.agent)
        response = client.call(srv, name, req, min(args.timeout, 10.0))
        if response is None:
            print(f"{label}: no answer from the platform server", flush=True)
            return 1
        result = response.result
        code = CODE_NAMES.get(int(result.code), str(result.code))
        reason = f": {result.reason}" if result.reason else ""
        print(f"{label}: {code} (command {result.command_id}){reason}", flush=True)
        if int(result.code) != 0:
            return 1
        if cmd in QUERIES:
            _print_query(cmd, response)
            return 0
        if args.no_wait or int(result.command_id) == 0:
            return 0

        def show(event: Any) -> None:
            kind = KIND_NAMES.get(int(event.kind), "?")
            text = f": {event.reason}" if event.reason else ""
            print(f"{label}: {kind} (command {result.command_id}){text}", flush=True)

        final = client.wait_final(int(result.command_id), args.timeout, show)
        if final is None:
            print(f"{label}: no completion event within {args.timeout:g} s", flush=True)
            return 1
        show(final)
        return 0 if int(final.kind) == 0 else 1
