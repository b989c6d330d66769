"""``hdrc3 state AGENT [--once] [--camera]``: print the Data Interface as JSON lines.

One JSON object per message, keys named exactly as the fields of chapter section 6.2.4
(``latitude``, ``longitude``, ``altitude``, ``velocity_north``, ..., ``pfc_time``; with
``--camera``: ``id``, ``pan``, ``tilt``, ``zoom``, ``ipc_time``). Times are seconds.
Exit 0 after ``--once`` or Ctrl-C, 1 if nothing arrived within ``--timeout``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from typing import Any

from hdrc3_base.errors import ConfigError
from hdrc3_base.stamps import stamp_s


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``state`` command."""
    parser = subparsers.add_parser(
        "state", help="print an agent's Data Interface (chapter 6.2.4) as JSON lines"
    )
    parser.add_argument("agent", help="agent name (ROS namespace), e.g. uav0")
    parser.add_argument("--once", action="store_true", help="print one sample and exit")
    parser.add_argument("--camera", action="store_true", help="camera state instead")
    parser.add_argument(
        "--timeout",
        type=float,
        default=10.0,
        help="wall-clock seconds to wait for the first sample",
    )
    parser.set_defaults(handler=run)


def to_record(msg: Any, camera: bool) -> dict[str, Any]:
    """The §6.2.4 fields of a HelicopterState / CameraState message."""
    from hdrc3_platform_server.data_interface import CAMERA_FIELDS, HELICOPTER_FIELDS

    fields = CAMERA_FIELDS if camera else HELICOPTER_FIELDS
    out: dict[str, Any] = {}
    for name in fields:
        value = getattr(msg, name)
        if name in ("pfc_time", "ipc_time"):
            value = stamp_s(value)
        elif isinstance(value, str):
            pass
        elif isinstance(value, bool | int):
            value = value if isinstance(value, bool) else int(value)
        else:
            value = float(value)
        out[name] = value
    return out


def run(args: argparse.Namespace) -> int:
    """Handler of ``hdrc3 state``."""
    from rclpy.node import Node

    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_interfaces.msg import CameraState, HelicopterState
    from hdrc3_platform_server.client import check_agent
    from hdrc3_platform_server.node import STATE_QOS

    agent = check_agent(args.agent)
    if not (math.isfinite(args.timeout) and args.timeout > 0):
        raise ConfigError(f"--timeout must be > 0, got {args.timeout}")
    msg_type = CameraState if args.camera else HelicopterState
    topic = f"/{agent}/{'camera_state' if args.camera else 'helicopter_state'}"
    count = 0
    with RosProcess(args=[]) as process:
        node = Node(f"hdrc3_state_{int(time.monotonic() * 1000) % 100000}", context=process.context)
        process.add_node(node)

        def on_msg(msg: Any) -> None:
            nonlocal count
            if args.once and count:
                return
            count += 1
            try:
                print(json.dumps(to_record(msg, args.camera)), flush=True)
            except BrokenPipeError:  # the reader went away (e.g. `| head`): stop quietly
                process.stop_requested.set()

        node.create_subscription(msg_type, topic, on_msg, STATE_QOS)
        if not process.spin_until(lambda: count > 0, args.timeout):
            print(f"no data on {topic} within {args.timeout:g} s", flush=True)
            return 1
        if not args.once:
            process.spin_until_stopped(0.05)
    return 0
