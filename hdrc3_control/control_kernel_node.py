"""The ``control_kernel`` node (the PFC): a thin ROS adapter around :class:`PfcKernel`.

Lockstep with ``world_sim`` in sim time: world_sim publishes the sensor samples of tick k, the
YACS status and then ``/clock`` = t_k; once both the clock and the status of t_k are in, the node
runs one kernel tick (Algorithm 1) and answers with exactly one ``yacs/command`` stamped t_k,
whatever the mode (manual, on the ground, between two functions); when world_sim re-announces
t_k (it never got the answer), the same answer goes out again. Events to and from the DRC
(platform_server) and the PPC travel over the HCSM ROS transport (``hcsm/events/<COMPUTER>``).

Topics (relative to the agent namespace): in ``sensors/{imu,attitude,gps/fix,gps/velocity,
barometer,ground_contact,rpm,power}``, ``pad_pose/fix`` (the landing pad camera's helicopter
fix, ``PoseWithCovarianceStamped`` in the world's ENU frame, §5.4), ``color_tracker/track`` (the
colour tracker's ``ColorTrack``: located TRACKING results are the car's ground fixes for
``fcl_track``), ``ppc/pad_vision`` (the PPC's latched ``PadVision`` report: whether a landing
can search for the pad's pattern, or must land on GPS at once), ``yacs/status``, ``pfc/ui``
(std_msgs/String: arm, brake, land), ``/clock``; out ``yacs/command``, ``pfc/state`` (PfcState,
every tick), ``pfc/aiding`` (std_msgs/String JSON, 5 Hz of sim time: the sources the Kalman
filter used lately and each source's verdict counts, :class:`~hdrc3_control.aiding.AidingLog`),
``hcsm/trace`` (fired transitions; parameter ``trace``, default on). Client of
``/world_sim/set_power`` for the Power Switch's requests.
Parameters: ``world`` (origin and terrain of the map), ``takeoff_height``, ``trace``,
``checkpoint`` (the warm-start record's file, "" = none: read at start, rewritten every second of
sim time while the navigation solution is good; ``warm_start.py``).
"""

from __future__ import annotations

import json
import math
import sys
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import pymap3d
from geometry_msgs.msg import PoseWithCovarianceStamped, TwistStamped
from rclpy.context import Context
from rclpy.executors import Executor
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, NavSatFix
from std_msgs.msg import String, UInt8

from hdrc3_base.errors import ConfigError
from hdrc3_base.raw_cdr import CdrReader, RawMessageError
from hdrc3_base.ros_runtime import SERVICE_QOS, SteppedNode, run_stepped_node
from hdrc3_base.stamps import nanoseconds, seconds, set_stamp_ns, stamp_ns, stamp_s
from hdrc3_control.commands import EstimatorHealth, VerticalMode
from hdrc3_control.kernel import PfcKernel, TickResult, UiCommand
from hdrc3_control.kernel_config import KernelConfig
from hdrc3_control.landing import landing_sites
from hdrc3_control.measurements import (
    AttitudeMeasurement,
    BaroMeasurement,
    GpsMeasurement,
    GroundContactMeasurement,
    ImuMeasurement,
    VisionPoseMeasurement,
)
from hdrc3_control.perception_kernel_node import COLOR_TRACK_TOPIC, LATCHED, PAD_VISION_TOPIC
from hdrc3_control.pfc_state import PlatformStatus, PowerReading
from hdrc3_control.takeoff import TakeoffConfig
from hdrc3_control.warm_start import read_warm_start, write_warm_start
from hdrc3_hcsm.ros_transport import RosTransport, TracePublisher
from hdrc3_hcsm.trace import TraceRecord
from hdrc3_interfaces.msg import (
    Attitude,
    Barometer,
    ColorTrack,
    GroundContact,
    PfcState,
    PowerStatus,
    RotorRpm,
    YacsCommand,
    YacsStatus,
)
from hdrc3_interfaces.srv import SimSetPower
from sim.geodesy import LocalFrame
from sim.world_loader import load_world, shipped_worlds

NODE_NAME = "control_kernel"
STAMP = ("header.stamp.sec", "header.stamp.nanosec")
CLOCK = CdrReader(Clock, ("clock.sec", "clock.nanosec"))
"""The per-tick inputs are read from the raw bytes (:mod:`hdrc3_base.raw_cdr`): building each
rclpy message cost 15-56 us, reading the few fields used 1-3 us."""
STATUS = CdrReader(YacsStatus, (*STAMP, "mode", "rc_link_ok", "engine_running", "rotor_rpm"))
IMU = CdrReader(
    Imu,
    (
        *STAMP,
        *(f"angular_velocity.{a}" for a in "xyz"),
        *(f"linear_acceleration.{a}" for a in "xyz"),
    ),
)
ATTITUDE = CdrReader(Attitude, (*STAMP, "roll", "pitch", "heading"))
GROUND_CONTACT = CdrReader(GroundContact, (*STAMP, "on_ground"))
PERIOD = 0.02
"""Control period, s (50 Hz)."""
SENSOR_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
IMU_QOS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
COMMAND_QOS = QoSProfile(depth=20, reliability=ReliabilityPolicy.RELIABLE)
TRACK_QOS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
"""The colour tracker's results (its publisher: reliable, depth 50)."""
CLOCK_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
WARM_START_PERIOD_NS = 1_000_000_000
AIDING_PERIOD_NS = 200_000_000
"""Sim time between two ``pfc/aiding`` reports."""
VISION_FRAME = "world_enu"
"""Sim time between two warm-start records."""
DRAIN_LIMIT = 64
"""Ready callbacks served before a tick runs (the period's samples: 4 IMU, 1 attitude, ...)."""
_HEALTH = {
    EstimatorHealth.OK: PfcState.HEALTH_OK,
    EstimatorHealth.DEGRADED: PfcState.HEALTH_DEGRADED,
    EstimatorHealth.LOST: PfcState.HEALTH_LOST,
}


class FiringTrace:
    """Trace sink that publishes only the micro steps in which transitions fired."""

    def __init__(self, publisher: TracePublisher) -> None:
        self.publisher = publisher

    def record(self, record: TraceRecord) -> None:
        """Forward ``record`` if it fired a transition (most pulse steps fire none)."""
        if record.transitions:
            self.publisher.record(record)


class ControlKernelNode(SteppedNode):
    """ROS face of one PfcKernel."""

    def __init__(self, context: Context) -> None:
        """Read parameters (ConfigError on bad ones), build the kernel and every interface."""
        super().__init__(NODE_NAME, context=context)
        self.set_parameters([Parameter("use_sim_time", value=True)])
        world_name = str(self.declare_parameter("world", "revinge").value)
        height = float(self.declare_parameter("takeoff_height", 10.0).value)
        trace_on = bool(self.declare_parameter("trace", True).value)
        checkpoint = str(self.declare_parameter("checkpoint", "").value)
        self._warm_path = Path(checkpoint) if checkpoint else None
        self._warm_written_ns = -WARM_START_PERIOD_NS
        self._warm_failed = False
        if world_name not in shipped_worlds() and not world_name.endswith(".toml"):
            raise ConfigError(
                f"unknown world {world_name!r} (shipped: {', '.join(shipped_worlds())})"
            )
        if not (math.isfinite(height) and 3.0 <= height <= 100.0):
            raise ConfigError(f"takeoff_height must be within 3 .. 100 m, got {height}")
        world = load_world(world_name)
        self.origin = world.origin
        self._frame = LocalFrame(world.origin)
        """ENU -> WGS84 for pfc/state every tick (pymap3d costs ~150 us a call, this ~3 us)."""
        sites = landing_sites(world.pads, world.terrain.height)
        self.agent = self.get_namespace().strip("/")
        self.transport = RosTransport(self, "PFC")
        trace = FiringTrace(TracePublisher(self, "hcsm/trace")) if trace_on else None
        self._make_kernel: Callable[[], PfcKernel] = lambda: PfcKernel(
            KernelConfig(takeoff=TakeoffConfig(height=height)),
            terrain=world.terrain.height,
            transport=self.transport,
            trace=trace,
            landing_sites=sites,
        )
        warm = read_warm_start(self._warm_path) if self._warm_path is not None else None
        self.kernel = PfcKernel(
            KernelConfig(takeoff=TakeoffConfig(height=height)),
            terrain=world.terrain.height,
            transport=self.transport,
            trace=trace,
            landing_sites=sites,
            warm_start=warm.record if warm is not None else None,
        )
        if warm is not None and warm.record is None:
            self.get_logger().info(f"cold start: {warm.reason}")
        self._warm_logged = False
        self.command_pub = self.create_publisher(YacsCommand, "yacs/command", COMMAND_QOS)
        self.state_pub = self.create_publisher(PfcState, "pfc/state", SENSOR_QOS)
        self.aiding_pub = self.create_publisher(String, "pfc/aiding", SENSOR_QOS)
        self._aiding_ns = -AIDING_PERIOD_NS
        self.vision_refused = 0
        """Fixes dropped by the adapter (wrong frame, bad covariance)."""
        self.power_client = self.create_client(
            SimSetPower, "/world_sim/set_power", qos_profile=SERVICE_QOS
        )
        self._gps_fix: dict[int, tuple[float, float, float]] = {}
        self._gps_vel: dict[int, tuple[float, float, float]] = {}
        self._clock_ns: int | None = None
        self._status_ns: int | None = None
        self._answered_ns = -1
        self.answers_resent = 0
        """Answers sent again for a re-announced tick (world_sim had not received them)."""
        self.overruns = 0
        self.step_time = 0.0
        self.ticks = 0
        self._command = YacsCommand()
        self._state = PfcState()
        self._state.header.frame_id = "world_enu"
        self.callbacks = 0
        """Callbacks served so far (the loop drains the ready ones before a tick)."""

        self.malformed = 0
        """Raw messages that could not be read (dropped, logged)."""

        def sub(
            msg_type: Any, topic: str, callback: Callable[[Any], None], qos: QoSProfile
        ) -> None:
            def counted(msg: Any) -> None:
                self.callbacks += 1
                callback(msg)

            self.create_subscription(msg_type, topic, counted, qos)

        def raw_sub(
            msg_type: Any, topic: str, callback: Callable[[bytes], None], qos: QoSProfile
        ) -> None:
            # every tick's messages, read from the bytes (raw_cdr): building the Python
            # message costs 15-56 us each, reading the few fields used 1-2 us
            def counted(data: bytes) -> None:
                self.callbacks += 1
                try:
                    callback(data)
                except RawMessageError as exc:
                    self.malformed += 1
                    self.get_logger().warning(
                        f"{topic}: dropped an unreadable message ({self.malformed} so far): {exc}",
                        throttle_duration_sec=5.0,
                    )

            self.create_subscription(msg_type, topic, counted, qos, raw=True)

        raw_sub(Clock, "/clock", self._on_clock, CLOCK_QOS)
        raw_sub(YacsStatus, "yacs/status", self._on_status, SENSOR_QOS)
        raw_sub(Imu, "sensors/imu", self._on_imu, IMU_QOS)
        raw_sub(Attitude, "sensors/attitude", self._on_attitude, SENSOR_QOS)
        sub(NavSatFix, "sensors/gps/fix", self._on_fix, SENSOR_QOS)
        sub(TwistStamped, "sensors/gps/velocity", self._on_gps_velocity, SENSOR_QOS)
        sub(Barometer, "sensors/barometer", self._on_baro, SENSOR_QOS)
        raw_sub(GroundContact, "sensors/ground_contact", self._on_ground, SENSOR_QOS)
        sub(RotorRpm, "sensors/rpm", self._on_rpm, SENSOR_QOS)
        sub(PowerStatus, "sensors/power", self._on_power, SENSOR_QOS)
        sub(String, "pfc/ui", self._on_ui, SENSOR_QOS)
        sub(PoseWithCovarianceStamped, "pad_pose/fix", self._on_vision, SENSOR_QOS)
        sub(ColorTrack, COLOR_TRACK_TOPIC, self._on_color_track, TRACK_QOS)
        sub(UInt8, PAD_VISION_TOPIC, self._on_pad_vision, LATCHED)

    # ------------------------------------------------------------------ inputs
    def _on_clock(self, data: bytes) -> None:
        ns = nanoseconds(*CLOCK.read(data))
        if ns == self._clock_ns == self._answered_ns:
            # world_sim re-announces a tick it still waits for: our answer never reached it (a
            # writer that has not matched world_sim's reader yet sends it to nobody, as at a
            # launch's first tick). The same answer again; an answer it had is a duplicate.
            self.command_pub.publish(self._command)
            self.answers_resent += 1
        self._clock_ns = ns

    def _on_status(self, data: bytes) -> None:
        sec, nanosec, mode, rc_link_ok, engine_running, rotor_rpm = STATUS.read(data)
        self._status_ns = nanoseconds(sec, nanosec)
        self.kernel.feed_status(
            PlatformStatus(
                seconds(sec, nanosec),
                mode == YacsStatus.MODE_AUTONOMOUS,
                rc_link_ok,
                engine_running,
                rotor_rpm,
            )
        )

    def _on_imu(self, data: bytes) -> None:
        sec, nanosec, wx, wy, wz, ax, ay, az = IMU.read(data)
        t = seconds(sec, nanosec)
        self.kernel.feed(ImuMeasurement(t, (ax, ay, az), (wx, wy, wz)))

    def _on_attitude(self, data: bytes) -> None:
        sec, nanosec, roll, pitch, heading = ATTITUDE.read(data)
        t = seconds(sec, nanosec)
        self.kernel.feed(AttitudeMeasurement(t, roll, pitch, heading))

    def _on_fix(self, msg: Any) -> None:
        o = self.origin
        e, n, u = pymap3d.geodetic2enu(
            msg.latitude, msg.longitude, msg.altitude, o.latitude, o.longitude, o.altitude
        )
        self._gps_pair(stamp_ns(msg.header.stamp), fix=(float(e), float(n), float(u)))

    def _on_gps_velocity(self, msg: Any) -> None:
        v = msg.twist.linear
        self._gps_pair(stamp_ns(msg.header.stamp), vel=(v.x, v.y, v.z))

    def _gps_pair(
        self,
        ns: int,
        fix: tuple[float, float, float] | None = None,
        vel: tuple[float, float, float] | None = None,
    ) -> None:
        """A GPS sample is the fix and the velocity of the same stamp (two topics)."""
        if fix is not None:
            self._gps_fix[ns] = fix
        if vel is not None:
            self._gps_vel[ns] = vel
        if ns in self._gps_fix and ns in self._gps_vel:
            position, velocity = self._gps_fix.pop(ns), self._gps_vel.pop(ns)
            self.kernel.feed(GpsMeasurement(ns * 1e-9, position, velocity))
        for pending in (self._gps_fix, self._gps_vel):
            for old in [k for k in pending if k < ns - 1_000_000_000]:
                del pending[old]

    def _on_baro(self, msg: Any) -> None:
        t = stamp_s(msg.header.stamp)
        self.kernel.feed(BaroMeasurement(t, msg.altitude - self.origin.altitude))

    def _on_ground(self, data: bytes) -> None:
        sec, nanosec, on_ground = GROUND_CONTACT.read(data)
        t = seconds(sec, nanosec)
        self.kernel.feed(GroundContactMeasurement(t, on_ground, 0.0))

    def _on_vision(self, msg: Any) -> None:
        p, cov = msg.pose.pose.position, msg.pose.covariance
        variance = (float(cov[0]) + float(cov[7]) + float(cov[14])) / 3.0
        if msg.header.frame_id != VISION_FRAME or not (math.isfinite(variance) and variance > 0):
            self.vision_refused += 1
            if self.vision_refused == 1:
                self.get_logger().warning(
                    f"vision fix refused: frame {msg.header.frame_id!r} (want {VISION_FRAME!r}),"
                    f" variance {variance}"
                )
            return
        position = (float(p.x), float(p.y), float(p.z))
        t = stamp_s(msg.header.stamp)
        self.kernel.feed(VisionPoseMeasurement(t, position, math.sqrt(variance)))

    def _on_pad_vision(self, msg: Any) -> None:
        if not self.kernel.pad_vision(int(msg.data)):
            self.get_logger().warning(f"unknown pad vision state {msg.data} on {PAD_VISION_TOPIC}")

    def _on_color_track(self, msg: Any) -> None:
        if msg.status != ColorTrack.STATUS_TRACKING or not msg.located:
            return
        p = msg.position
        self.kernel.target_fix(stamp_s(msg.header.stamp), float(p.x), float(p.y), float(p.z))

    def _on_rpm(self, msg: Any) -> None:
        self.kernel.feed_rpm(float(msg.rpm))

    def _on_power(self, msg: Any) -> None:
        self.kernel.feed_power(PowerReading(stamp_s(msg.header.stamp), int(msg.status)))

    def _on_ui(self, msg: Any) -> None:
        try:
            command = UiCommand(str(msg.data).strip().lower())
        except ValueError:
            known = ", ".join(c.value for c in UiCommand)
            self.get_logger().warning(f"unknown UI command {msg.data!r} (known: {known})")
            return
        self.kernel.post_ui(command)

    # ------------------------------------------------------------------ the loop
    def tick_due(self) -> bool:
        """True once the clock and the YACS status of a new tick have both arrived."""
        ns = self._clock_ns
        if ns is not None and ns < self._answered_ns and ns == self._status_ns:
            # world_sim was reset (sim time restarts at 0): a new flight, a fresh PFC
            self.get_logger().warning(
                f"sim time went back from {self._answered_ns * 1e-9:.2f} s to {ns * 1e-9:.2f} s: "
                "restarting the control kernel"
            )
            self.kernel = self._make_kernel()
            self._answered_ns = -1
        return ns is not None and ns == self._status_ns and ns > self._answered_ns

    def run_tick(self) -> None:
        """One control tick at the current sim time; answer it with one YACS command."""
        ns = self._clock_ns
        assert ns is not None
        if self._answered_ns >= 0:
            # ticks we never saw (a free-running sim outran us): counted, not replayed
            self.overruns += max(0, round((ns - self._answered_ns) / 20_000_000) - 1)
        started = time.perf_counter()  # wall time only for the overrun diagnostics
        result = self.kernel.tick(ns * 1e-9)
        self._publish_command(ns, result)
        self._answered_ns = ns
        self.step_time = time.perf_counter() - started
        if self.step_time > PERIOD:
            self.overruns += 1
        self.ticks += 1
        for request in result.power_requests:
            self._request_power(request.devices)
        self._publish_state(ns, result)
        self._keep_warm_start(ns)
        if ns - self._aiding_ns >= AIDING_PERIOD_NS:
            self._aiding_ns = ns
            report = self.kernel.aiding_report()
            self.aiding_pub.publish(String(data=json.dumps({"time": ns * 1e-9, **report})))

    def _keep_warm_start(self, ns: int) -> None:
        """Log what the first tick did with the record; rewrite it every period of sim time."""
        if not self._warm_logged and self._warm_path is not None:
            self._warm_logged = True
            self.get_logger().info(self.kernel.warm_start_note)
        if self._warm_path is None or ns - self._warm_written_ns < WARM_START_PERIOD_NS:
            return
        record = self.kernel.warm_start_record()
        if record is None:
            return
        self._warm_written_ns = ns
        try:
            write_warm_start(self._warm_path, record)
        except OSError as exc:
            if not self._warm_failed:  # once: the flight goes on without the record
                self.get_logger().warning(f"cannot write the warm-start record: {exc}")
            self._warm_failed = True

    def _publish_command(self, ns: int, result: TickResult) -> None:
        cmd, m = result.command, self._command
        set_stamp_ns(m.header.stamp, ns)
        m.roll, m.pitch, m.yaw_rate, m.vertical = cmd.roll, cmd.pitch, cmd.yaw_rate, cmd.vertical
        m.vertical_mode = (
            YacsCommand.COLLECTIVE
            if cmd.vertical_mode is VerticalMode.COLLECTIVE
            else YacsCommand.VERTICAL_RATE
        )
        m.engine_off = cmd.engine_off
        self.command_pub.publish(m)

    def _request_power(self, devices: int) -> None:
        if not self.power_client.service_is_ready():
            self.get_logger().warning("power management unit (/world_sim/set_power) not available")
            return
        self.power_client.call_async(
            SimSetPower.Request(agent=self.agent, devices=devices, on=True)
        )

    def _publish_state(self, ns: int, result: TickResult) -> None:
        s, m = result.snapshot, self._state
        set_stamp_ns(m.header.stamp, ns)
        set_stamp_ns(m.pfc_time, ns)
        m.position_enu = list(s.position)
        m.velocity_enu = list(s.velocity)
        point = self._frame.to_geodetic(*s.position)
        m.latitude, m.longitude, m.altitude = point.latitude, point.longitude, point.altitude
        m.roll, m.pitch, m.heading = s.roll, s.pitch, s.heading
        m.body_rates = list(s.rates)
        m.rpm = s.rotor_rpm
        m.on_ground, m.auto_flag, m.engine_running = s.on_ground, s.auto, s.engine_running
        m.estimator_initialised = s.estimator_initialised
        m.estimator_health = _HEALTH[s.health]
        m.position_sigma = s.position_sigma if math.isfinite(s.position_sigma) else -1.0
        m.mode = int(s.mode)
        m.control_function, m.mode_switch_state = s.control_function, s.mode_switch_state
        m.command_id = s.command_id
        m.failsafe, m.failsafe_reason = int(s.failsafe), s.failsafe_reason
        m.overruns, m.step_time, m.ticks = self.overruns, self.step_time, self.ticks
        self.state_pub.publish(m)

    def run(self, executor: Executor, stop: threading.Event) -> None:
        """Serve callbacks; run a tick as soon as one is due (never inside a callback)."""
        while not stop.is_set() and self.context.ok():
            executor.spin_once(timeout_sec=0.1)
            if self.tick_due():
                # samples of this tick may still be queued behind the clock (other topics)
                for _ in range(DRAIN_LIMIT):
                    before = self.callbacks
                    executor.spin_once(timeout_sec=0.0)
                    if self.callbacks == before:
                        break
                self.run_tick()


def main(argv: Sequence[str] | None = None) -> int:
    """Console script `hdrc3-control-kernel`: exit 0 on SIGINT/SIGTERM, 2 on bad parameters."""
    return run_stepped_node(
        ControlKernelNode, "control_kernel", list(sys.argv if argv is None else argv)
    )


if __name__ == "__main__":
    sys.exit(main())
