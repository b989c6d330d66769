"""The `platform_server` node (the DRC): FCL/PPCL services, platform events, Data Interface.

A thin adapter around :class:`~hdrc3_platform_server.server.PlatformServerCore`. In the agent's
namespace it offers ``fcl/<command>`` and ``ppcl/<command>`` services, publishes
``platform_events`` (PlatformEvent), ``helicopter_state`` (HelicopterState) and ``camera_state``
(CameraState) at 25 Hz of sim time, and talks to the PFC/PPC over ``hcsm/events/*``. See the
package README for the semantics table.
"""

from __future__ import annotations

import math
import os
import sys
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rcl_interfaces.msg import ParameterDescriptor
from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from hdrc3_base.answer_memory import AnswerMemory, keyed, remembering
from hdrc3_base.ros_runtime import SERVICE_QOS, STATUS_QOS, STATUS_TOPIC, run_events_node
from hdrc3_base.stamps import set_stamp_s, stamp_s
from hdrc3_hcsm.ros_transport import RosTransport
from hdrc3_interfaces.msg import (
    CameraState,
    HelicopterState,
    HookCommand,
    HookState,
    LaunchStatus,
    PfcState,
    PlatformEvent,
    PowerStatus,
    SimRun,
    SupervisedProcess,
)
from hdrc3_interfaces.srv import (
    PpclControl,
    PpclGetCameraInfo,
    PpclHook,
    PpclPtuActivityInfo,
    PpclPtuLimits,
)
from hdrc3_platform_server.codes import FclCode, PpclCode
from hdrc3_platform_server.commands import FCL, PPCL, FclSpec, PpclSpec
from hdrc3_platform_server.completion import CompletionEvent
from hdrc3_platform_server.data_interface import HelicopterStateData
from hdrc3_platform_server.geo_frame import WorldFrame, frame_from_world
from hdrc3_platform_server.hook_api import HookSample, HookSetpoint
from hdrc3_platform_server.journal import CommandJournal
from hdrc3_platform_server.kernel_watch import KernelWatch, ProcessReport
from hdrc3_platform_server.platform_status import CameraSample, PfcSample
from hdrc3_platform_server.server import PlatformServerCore

NODE_NAME = "platform_server"
EVENT_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=1000,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
"""Platform events: the last 1,000 are kept for late subscribers. A restarted server publishes
the terminal events of the commands accepted before the restart before its clients have matched
its new publisher: with a volatile publisher they would be lost (readers with this QoS get them)."""
STATE_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
"""Deep enough that a 50 Hz state stream at 10x real time survives a 200 ms stall of a reader."""
RUN_QOS = QoSProfile(
    reliability=ReliabilityPolicy.RELIABLE,
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
"""``/world_sim/run`` is latched: a server that starts later learns the world's run id at once."""
TICK_PERIOD_S = 0.02
"""Wall-clock period of the DRC loop when no PFC data drives it (replies, timeouts)."""


def _refusal(code: int) -> Callable[[Any, str], None]:
    """Writes ``code`` (the family's NOT_ACCEPTED) and a reason into an FCL/PPCL response."""

    def refuse(response: Any, reason: str) -> None:
        response.result.code = code
        response.result.reason = reason

    return refuse


def _id_start() -> int:
    # Ids of a restarted server must not collide with late replies about the old one's.
    return (int.from_bytes(os.urandom(3), "little") << 24) + 1


class PlatformServerNode(Node):
    """ROS adapter of the Platform Server core."""

    def __init__(self, context: Context | None = None) -> None:
        super().__init__(NODE_NAME, context=context)
        self.declare_parameter("world", "revinge", ParameterDescriptor(description="world file"))
        for name in ("origin_latitude", "origin_longitude", "origin_altitude"):
            self.declare_parameter(name, math.nan)
        self.declare_parameter("agents", [""])
        self.declare_parameter("speed", 1.0)
        self.declare_parameter(
            "sim_time", True, ParameterDescriptor(description="run on /clock (world_sim)")
        )
        if self.get_parameter("sim_time").value:
            self.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        self.declare_parameter(
            "checkpoint",
            "",
            ParameterDescriptor(description="file of the open commands kept across restarts"),
        )
        checkpoint = str(self.get_parameter("checkpoint").value)
        self.frame = self._frame()
        self.transport = RosTransport(self, "DRC")
        self.events_pub = self.create_publisher(PlatformEvent, "platform_events", EVENT_QOS)
        self.heli_pub = self.create_publisher(HelicopterState, "helicopter_state", STATE_QOS)
        self.camera_pub = self.create_publisher(CameraState, "camera_state", STATE_QOS)
        self.hook_pub = self.create_publisher(HookCommand, "hook/command", STATE_QOS)
        self.core = PlatformServerCore(
            self.frame,
            self.transport,
            self._publish_event,
            id_start=_id_start(),
            journal=CommandJournal(Path(checkpoint) if checkpoint else None),
            hook=self._send_hook,
        )
        self.create_subscription(HookState, "sensors/carrying", self._on_carrying, STATE_QOS)
        self.create_subscription(PfcState, "pfc/state", self._on_pfc, STATE_QOS)
        self.create_subscription(CameraState, "ppc/camera_state", self._on_camera, STATE_QOS)
        self.create_subscription(PowerStatus, "sensors/power", self._on_power, STATE_QOS)
        self._run_id: str | None = None
        self.answers: AnswerMemory[Any] = AnswerMemory()
        self.create_subscription(SimRun, "/world_sim/run", self._on_world_run, RUN_QOS)
        self._kernels = KernelWatch(self.get_namespace().strip("/"))
        self.create_subscription(LaunchStatus, STATUS_TOPIC, self._on_launch_status, STATUS_QOS)
        for spec in FCL.values():
            name = f"fcl/{spec.command.value}"
            self._service(spec.service_type(), name, self._fcl_handler(spec), FclCode.NOT_ACCEPTED)
        for pspec in PPCL.values():
            name = f"ppcl/{pspec.command.value}"
            self._service(
                pspec.service_type(), name, self._ppcl_handler(pspec), PpclCode.NOT_ACCEPTED
            )
        ppcl_others: tuple[tuple[Any, str, Callable[[Any, Any], Any]], ...] = (
            (PpclControl, "ppcl/control", self._on_control),
            (PpclPtuActivityInfo, "ppcl/ptu_activity_info", self._on_activity),
            (PpclGetCameraInfo, "ppcl/get_camera_info", self._on_camera_info),
            (PpclPtuLimits, "ppcl/ptu_limits", self._on_limits),
            (PpclHook, "ppcl/hook", self._on_hook),
        )
        for srv_type, name, handler in ppcl_others:
            self._service(srv_type, name, handler, PpclCode.NOT_ACCEPTED)
        self.create_timer(TICK_PERIOD_S, self._tick, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._heli = HelicopterState()
        self._heli.header.frame_id = "wgs84"
        self.get_logger().info(
            f"platform server up: origin {self.frame.latitude:.6f}, {self.frame.longitude:.6f}, "
            f"{self.frame.altitude:.1f} m"
        )

    def _service(
        self, srv_type: Any, name: str, handler: Callable[[Any, Any], Any], refused: int
    ) -> None:
        """Serve ``name``; ``refused`` is the family's NOT_ACCEPTED code (for a bad request key)."""
        # deep request/answer queues: a burst of calls is queued and answered, never dropped
        serve = handler
        if keyed(srv_type.Request):
            serve = remembering(self.answers, name, handler, _refusal(refused))
        self.create_service(srv_type, name, serve, qos_profile=SERVICE_QOS)

    def _frame(self) -> WorldFrame:
        lat = float(self.get_parameter("origin_latitude").value)
        lon = float(self.get_parameter("origin_longitude").value)
        alt = float(self.get_parameter("origin_altitude").value)
        if all(math.isfinite(v) for v in (lat, lon, alt)):
            return WorldFrame(lat, lon, alt)
        return frame_from_world(str(self.get_parameter("world").value))

    def _now(self) -> float:
        """DRC time: the node's (sim) clock; until /clock arrives, the latest PFC time."""
        now = self.get_clock().now().nanoseconds * 1e-9
        if now > 0.0:
            return now
        pfc = self.core.status.pfc
        return pfc.pfc_time if pfc is not None else 0.0

    # --- inputs ---------------------------------------------------------------------------
    def _on_pfc(self, msg: Any) -> None:
        p, v = msg.position_enu, msg.velocity_enu
        pfc_time = stamp_s(msg.pfc_time)
        now = self.get_clock().now().nanoseconds * 1e-9
        sample = PfcSample(
            pfc_time=pfc_time,
            received=now if now > 0.0 else pfc_time,
            position_enu=(float(p[0]), float(p[1]), float(p[2])),
            velocity_enu=(float(v[0]), float(v[1]), float(v[2])),
            latitude=float(msg.latitude),
            longitude=float(msg.longitude),
            altitude=float(msg.altitude),
            roll=float(msg.roll),
            pitch=float(msg.pitch),
            heading=float(msg.heading),
            rpm=float(msg.rpm),
            on_ground=bool(msg.on_ground),
            auto_flag=bool(msg.auto_flag),
            mode=int(msg.mode),
            command_id=int(msg.command_id),
            failsafe=int(msg.failsafe),
            failsafe_reason=str(msg.failsafe_reason),
        )
        data = self.core.on_pfc(sample)
        if data is not None:
            self._publish_di(data)

    def _on_camera(self, msg: Any) -> None:
        self.core.on_camera(
            CameraSample(
                int(msg.id),
                float(msg.pan),
                float(msg.tilt),
                float(msg.zoom),
                stamp_s(msg.ipc_time),
                self._now(),
            )
        )

    def _on_carrying(self, msg: Any) -> None:
        self.core.on_hook(
            HookSample(
                stamp_s(msg.header.stamp),
                bool(msg.carrying),
                str(msg.object_id),
                bool(msg.magnet),
                int(msg.winch),
                float(msg.cable_length),
                float(msg.tension),
            )
        )

    def _send_hook(self, setpoint: HookSetpoint) -> None:
        msg = HookCommand(cable_length=setpoint.cable_length, magnet=setpoint.magnet)
        set_stamp_s(msg.header.stamp, self._now())
        self.hook_pub.publish(msg)

    def _on_hook(self, request: Any, response: Any) -> Any:
        def fill() -> None:
            answer = self.core.submit_hook(
                int(request.action), float(request.length), str(request.object_id), self._now()
            )
            response.result.code = int(answer.code)
            response.result.reason = answer.reason
            response.result.command_id = answer.command_id

        self._guard(fill, self._ppcl_fail(response))
        return response

    def _on_power(self, msg: Any) -> None:
        self.core.status.power_status = int(msg.status)

    def _on_world_run(self, msg: Any) -> None:
        # RESET with a world this server has not seen: commands on the old world fail. The first
        # message a server gets tells it only which world it joins (sim/WORLD_SIM.md).
        known, self._run_id = self._run_id, str(msg.run_id)
        if msg.kind == SimRun.RESET and known is not None and known != self._run_id:
            self.core.on_world_reset(str(msg.reason) or "the world started over", self._now())

    def _on_launch_status(self, msg: Any) -> None:
        alive = (SupervisedProcess.STATE_STARTING, SupervisedProcess.STATE_RUNNING)
        reports = [
            ProcessReport(str(p.node_name), p.state in alive, int(p.restarts), p.last_exit_code)
            for p in msg.processes
        ]
        for exited in self._kernels.update(reports):
            self.get_logger().warning(exited.reason)
            self.core.on_kernel_exit(exited, self._now())

    def _tick(self) -> None:
        self.core.tick(self._now())

    # --- outputs --------------------------------------------------------------------------
    def _publish_event(self, event: CompletionEvent) -> None:
        msg = PlatformEvent()
        set_stamp_s(msg.header.stamp, event.time)
        msg.command_id = event.command_id
        msg.command = event.command
        msg.kind = int(event.kind)
        msg.reason = event.reason
        self.events_pub.publish(msg)

    def _publish_di(self, data: HelicopterStateData) -> None:
        m = self._heli
        set_stamp_s(m.header.stamp, data.pfc_time)
        for name, value in data.as_dict().items():
            if name == "pfc_time":
                set_stamp_s(m.pfc_time, value)
            else:
                setattr(m, name, value)
        self.heli_pub.publish(m)
        for cam in self.core.camera_states():
            c = CameraState()
            set_stamp_s(c.header.stamp, data.pfc_time)
            c.id, c.pan, c.tilt, c.zoom = cam.id, cam.pan, cam.tilt, cam.zoom
            set_stamp_s(c.ipc_time, cam.ipc_time)
            self.camera_pub.publish(c)

    # --- services -------------------------------------------------------------------------
    def _guard(self, fill: Callable[[], None], fail: Callable[[str], None]) -> None:
        try:
            fill()
        except Exception as exc:  # the server must keep answering: report, never crash
            self.get_logger().error(f"internal error: {exc}\n{traceback.format_exc()}")
            fail(f"internal error: {exc}")

    def _fcl_handler(self, spec: FclSpec) -> Callable[[Any, Any], Any]:
        def handle(request: Any, response: Any) -> Any:
            def fill() -> None:
                answer = self.core.submit_fcl(spec.command, spec.values(request), self._now())
                response.result.code = int(answer.code)
                response.result.reason = answer.reason
                response.result.command_id = answer.command_id

            def fail(reason: str) -> None:
                response.result.code = int(FclCode.NOT_ACCEPTED)
                response.result.reason = reason

            self._guard(fill, fail)
            return response

        return handle

    def _ppcl_fail(self, response: Any) -> Callable[[str], None]:
        def fail(reason: str) -> None:
            response.result.code = int(PpclCode.NOT_ACCEPTED)
            response.result.reason = reason

        return fail

    def _ppcl_handler(self, spec: PpclSpec) -> Callable[[Any, Any], Any]:
        def handle(request: Any, response: Any) -> Any:
            def fill() -> None:
                answer = self.core.submit_ppcl(spec.command, spec.values(request), self._now())
                response.result.code = int(answer.code)
                response.result.reason = answer.reason
                response.result.command_id = answer.command_id

            self._guard(fill, self._ppcl_fail(response))
            return response

        return handle

    def _on_control(self, request: Any, response: Any) -> Any:
        def fill() -> None:
            answer = self.core.ppcl.control(
                int(request.resource), bool(request.request), str(request.owner)
            )
            response.result.code = int(answer.code)
            response.result.reason = answer.reason

        self._guard(fill, self._ppcl_fail(response))
        return response

    def _on_activity(self, request: Any, response: Any) -> Any:
        response.result.code = int(PpclCode.OK)
        response.activity = int(self.core.ppcl.activity)
        return response

    def _on_camera_info(self, request: Any, response: Any) -> Any:
        def fill() -> None:
            answer, info = self.core.ppcl.camera_info(int(request.camera_id))
            response.result.code = int(answer.code)
            response.result.reason = answer.reason
            if info is not None:
                response.width, response.height = info.width, info.height
                response.fx, response.fy, response.cx, response.cy = (
                    info.fx,
                    info.fy,
                    info.cx,
                    info.cy,
                )
                response.zoom, response.hfov = info.zoom, info.hfov

        self._guard(fill, self._ppcl_fail(response))
        return response

    def _on_limits(self, request: Any, response: Any) -> Any:
        lim = self.core.ppcl.ptu
        response.result.code = int(PpclCode.OK)
        response.min_pan, response.max_pan = lim.min_pan, lim.max_pan
        response.min_tilt, response.max_tilt = lim.min_tilt, lim.max_tilt
        return response


def main() -> int:
    """Console script `hdrc3-platform-server`: exit 0 on SIGINT/SIGTERM, 2 on bad parameters."""
    return run_events_node(PlatformServerNode, "hdrc3-platform-server")


if __name__ == "__main__":
    sys.exit(main())
