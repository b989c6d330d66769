"""The `world_sim` node: hosts the aircraft of one world, publishes /clock, sensors and truth.

A thin ROS adapter around :class:`sim.world_sim.WorldSim` (simulation),
:class:`sim.lockstep.LockstepBarrier` (who must answer a tick), :class:`sim.pacer.Pacer`
(real-time factor) and :class:`sim.sim_services.SimServices` (validated requests). The node runs
its own loop instead of timers so that a tick advances the instant the last controller answers.
See ``sim/WORLD_SIM.md`` for topics, services and the lockstep protocol.
"""

from __future__ import annotations

import math
import sys
import threading
import time
import uuid
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from geometry_msgs.msg import PointStamped
from rcl_interfaces.msg import ParameterDescriptor, ParameterType
from rclpy.context import Context
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header

from hdrc3_base.errors import ConfigError, Hdrc3Error
from hdrc3_base.ros_runtime import SERVICE_QOS, SteppedNode, run_stepped_node
from hdrc3_base.stamps import set_stamp_ns
from hdrc3_interfaces.msg import (
    CameraCommand,
    HookCommand,
    HookState,
    LaserCommand,
    PtuCommand,
    SimRun,
    WindState,
    WorldObject,
    WorldObjects,
    YacsCommand,
    YacsStatus,
)
from hdrc3_interfaces.srv import (
    SimInjectFault,
    SimPause,
    SimReset,
    SimSetPower,
    SimSetRc,
    SimSetWind,
    SimSpawnObject,
    SimTeleport,
)
from sim.agent_topics import (
    AgentTopics,
    stamp_header,
)
from sim.checkpoint import Checkpoints, RunEvent, RunKind, RunState, new_run_id
from sim.lockstep import LockstepBarrier, Offer, Verdict
from sim.pacer import Pacer
from sim.rc_transmitter import FlightModeSwitch
from sim.render_gate import DEFAULT_LAG_S, RenderGate
from sim.sim_services import RcRequest, SimCode, SimResult, SimServices
from sim.wind import WindSettings
from sim.world_loader import load_world, shipped_worlds
from sim.world_sim import TICK_S, SimConfig, WorldSim
from sim.yacs import CommandSource, VerticalMode
from sim.yacs import YacsCommand as Command

NODE_NAME = "world_sim"
WIND_EVERY = 5
"""Ticks between /world_sim/wind messages (10 Hz sim time)."""
PAYLOAD_EVERY = 5
"""Ticks between carrying-sensor samples and looks for moved objects (10 Hz sim time): a car
driving at 10 m/s moves 1 m between two /world_sim/objects messages."""
MOVED = 0.01
"""m (or rad of heading) a box, carrier or car moves before /world_sim/objects is sent again."""
STALL_S = 0.5
"""Wall seconds without the awaited commands after which a tick is re-announced."""
WAIT_STEP_S = 0.1
"""Longest single wait for a callback: bounds the reaction to a stop request."""
FREE_SPIN_EVERY = 5
"""Free-running ticks between two looks at pending requests (0.1 s of sim time)."""
# Keep-last never blocks the sim. The depth (10 s of samples) is the writer history a reliable
# reader's lost deliveries are resent from: a reader process starved of CPU (its DDS threads too)
# drops deliveries, and with 1 s of history the resend found them gone (measured: 185-360 of 400
# IMU samples lost in 2 s with the reader niced against 4 CPU hogs; none with 10 s).
SENSOR_QOS = QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE)
IMU_QOS = QoSProfile(depth=2000, reliability=ReliabilityPolicy.RELIABLE)
COMMAND_QOS = QoSProfile(depth=20, reliability=ReliabilityPolicy.RELIABLE)
LATCHED_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
"""/clock, /world_sim/objects and /world_sim/run: a late joiner gets the current value at once."""
MAX_CHECKPOINT_PERIOD_S = 60.0
RENDER_PROGRESS_TOPIC = "/world_render/progress"
"""world_render's handled exposures: ``std_msgs/Header``, frame_id = agent (``RenderGate``)."""
RENDER_PROGRESS_QOS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
RENDER_STALL_S = 2.0
"""Wall time a tick waits at most for a renderer that does not report (then it runs anyway)."""
"""Longest accepted checkpoint period, sim seconds."""


_SOURCES = {
    CommandSource.COMPUTER: YacsStatus.SOURCE_COMPUTER,
    CommandSource.PILOT: YacsStatus.SOURCE_PILOT,
    CommandSource.FAILSAFE: YacsStatus.SOURCE_FAILSAFE,
}


class WorldSimNode(SteppedNode):
    """ROS face of one WorldSim."""

    def __init__(self, context: Context) -> None:
        """Read and validate parameters (ConfigError), build the world, create every interface."""
        super().__init__(NODE_NAME, context=context)
        strings = ParameterDescriptor(type=ParameterType.PARAMETER_STRING_ARRAY)
        agents = self._parameter("agents", ["uav0"], strings)
        world_name = str(self._parameter("world", "revinge"))
        speed = self._float("speed", 1.0)
        seed = int(self._parameter("seed", 0))
        if seed < 0:
            raise ConfigError(f"parameter seed: expected an integer >= 0, got {seed}")
        required = self._parameter("lockstep", [""], strings)
        self.pace_lockstep = bool(self._parameter("pace_lockstep", False))
        wind = list(self._parameter("wind", [0.0, 0.0, 0.0]))
        gust = self._float("gust_intensity", 0.0)
        payload = self._float("payload", 0.0)
        if world_name not in shipped_worlds() and not world_name.endswith(".toml"):
            raise ConfigError(
                f"unknown world {world_name!r} (shipped: {', '.join(shipped_worlds())})"
            )
        if len(wind) != 3:
            raise ConfigError(f"wind must be [east, north, up] m/s, got {wind}")
        settings = WindSettings((float(wind[0]), float(wind[1]), float(wind[2])), gust)
        problem = settings.problem()
        if problem is not None:
            raise ConfigError(problem)
        self.pacer = Pacer(speed)
        world = load_world(world_name)
        names = tuple(str(a) for a in agents)
        self.sim = WorldSim(SimConfig(world, names, seed, settings, payload=payload))
        self.barrier: LockstepBarrier[Command | None] = LockstepBarrier(
            names, [str(r) for r in required if r]
        )
        self.requests = SimServices(self.sim, self.barrier)
        self.checkpoints = self._checkpoints()
        self.process_id = uuid.uuid4().hex[:16]
        self.start_event = self.checkpoints.start(self.sim)
        self.run_state = self.start_event.run
        if self.start_event.kind is RunKind.RESUMED:  # pause and lockstep set as they were
            self.requests.paused = self.run_state.paused
            self.barrier.set_required(self.run_state.lockstep)
        self._restart = False
        self._run_pub = self.create_publisher(SimRun, "/world_sim/run", LATCHED_QOS)
        self._clock_pub = self.create_publisher(Clock, "/clock", LATCHED_QOS)
        self._clock_msg = Clock()
        self._wind_pub = self.create_publisher(WindState, "/world_sim/wind", SENSOR_QOS)
        self._wind = WindState()
        self._wind.header.frame_id = "world_enu"
        self._objects_pub = self.create_publisher(WorldObjects, "/world_sim/objects", LATCHED_QOS)
        self._published_poses: dict[str, tuple[float, float, float, float, str]] = {}
        self._carrying_pubs = {
            name: self.create_publisher(HookState, f"/{name}/sensors/carrying", SENSOR_QOS)
            for name in names
        }
        self._hook_camera_pubs = {
            name: self.create_publisher(PointStamped, f"/{name}/sensors/hook_camera", SENSOR_QOS)
            for name in names
        }
        self.topics = {name: AgentTopics(self, name, SENSOR_QOS, IMU_QOS) for name in names}
        self.render_gate = RenderGate.from_seconds(self._float("render_lag", DEFAULT_LAG_S))
        self._render_wait_since = 0.0
        self._render_sub = self.create_subscription(
            Header, RENDER_PROGRESS_TOPIC, self._on_render_progress, RENDER_PROGRESS_QOS
        )
        self._command_subs = {}
        for name in names:
            self._command_subs[name] = self.create_subscription(
                YacsCommand,
                self.topics[name].command_topic,
                self._command_callback(name),
                COMMAND_QOS,
            )
            self.create_service(
                SimSetRc, f"/{name}/rc/set", self._rc_callback(name), qos_profile=SERVICE_QOS
            )
            self._payload_subscriptions(name)
        self._create_services()

    def _parameter(
        self, name: str, default: Any, descriptor: ParameterDescriptor | None = None
    ) -> Any:
        """Declare and read one parameter; a value of the wrong type is a ConfigError."""
        try:
            return self.declare_parameter(name, default, descriptor or ParameterDescriptor()).value
        except (InvalidParameterTypeException, InvalidParameterValueException) as exc:
            raise ConfigError(f"parameter {name}: {exc}") from exc

    def _checkpoints(self) -> Checkpoints:
        """The ``checkpoint`` file ("" = none) written every ``checkpoint_period`` sim seconds."""
        path = str(self._parameter("checkpoint", ""))
        period = self._float("checkpoint_period", 0.5)
        if not (math.isfinite(period) and TICK_S <= period <= MAX_CHECKPOINT_PERIOD_S):
            raise ConfigError(
                f"parameter checkpoint_period: expected {TICK_S} .. {MAX_CHECKPOINT_PERIOD_S} s, "
                f"got {period}"
            )
        if path and not Path(path).parent.is_dir():
            raise ConfigError(f"parameter checkpoint: directory of {path} does not exist")
        return Checkpoints(Path(path) if path else None, round(period / TICK_S))

    def _float(self, name: str, default: float) -> float:
        """A float parameter that also accepts integers (``speed:=2``)."""
        value = self._parameter(name, default, ParameterDescriptor(dynamic_typing=True))
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"parameter {name}: expected a number, got {value!r}")
        return float(value)

    def _on_render_progress(self, msg: Any) -> None:
        stamp = msg.stamp.sec * 1_000_000_000 + msg.stamp.nanosec
        self.render_gate.report(str(msg.frame_id), stamp)

    # -------------------------------------------------------------- commands
    def _command_callback(self, agent: str) -> Callable[[Any], None]:
        def on_command(msg: Any) -> None:
            command: Command | None
            try:
                if msg.vertical_mode not in (YacsCommand.VERTICAL_RATE, YacsCommand.COLLECTIVE):
                    raise ConfigError(f"unknown vertical_mode {msg.vertical_mode}")
                mode = (
                    VerticalMode.COLLECTIVE
                    if msg.vertical_mode == YacsCommand.COLLECTIVE
                    else VerticalMode.VERTICAL_RATE
                )
                command = Command(
                    msg.roll, msg.pitch, msg.yaw_rate, msg.vertical, mode, bool(msg.engine_off)
                )
            except ConfigError as exc:
                command = None
                self.sim.agents[agent].rejected_commands += 1
                self.get_logger().warning(
                    f"{agent}: command rejected, holding the previous one: {exc}",
                    throttle_duration_sec=5.0,
                )
            stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
            verdict = self.barrier.offer(Offer(agent, stamp, command))
            if verdict is not Verdict.ACCEPTED:
                self.get_logger().debug(f"{agent}: command stamped {stamp} ns {verdict.value}")

        return on_command

    def _payload_subscriptions(self, agent: str) -> None:
        """PTU, camera and laser commands of the perception kernel (applied at the next tick)."""
        requests = self.requests

        def report(result: SimResult) -> None:
            if not result.ok:
                self.get_logger().warning(
                    f"{agent}: payload command refused: {result.reason}", throttle_duration_sec=5.0
                )

        def on_ptu(msg: Any) -> None:
            report(requests.ptu_command(agent, msg.pan, msg.tilt))

        def on_camera(msg: Any) -> None:
            report(requests.camera_command(agent, msg.camera_id, msg.zoom))

        def on_laser(msg: Any) -> None:
            report(
                requests.laser_command(
                    agent,
                    msg.angular_resolution,
                    msg.distance_resolution,
                    msg.rotation_speed,
                    msg.hold_angle,
                    msg.rotation_angle,
                    power=msg.collect,
                )
            )

        def on_hook(msg: Any) -> None:
            report(requests.hook_command(agent, msg.cable_length, msg.magnet))

        ns = f"/{agent}"
        self.create_subscription(HookCommand, f"{ns}/hook/command", on_hook, COMMAND_QOS)
        self.create_subscription(PtuCommand, f"{ns}/ptu/command", on_ptu, COMMAND_QOS)
        self.create_subscription(CameraCommand, f"{ns}/camera/command", on_camera, COMMAND_QOS)
        self.create_subscription(LaserCommand, f"{ns}/laser/command", on_laser, COMMAND_QOS)

    # -------------------------------------------------------------- services
    def _create_services(self) -> None:
        s = self.requests

        def reply(result: SimResult, response: Any) -> Any:
            response.result.code = int(result.code)
            response.result.reason = result.reason
            if not result.ok:
                self.get_logger().info(f"request refused: {result.reason}")
            return response

        def guarded(request: Callable[[], SimResult]) -> SimResult:
            # rebuilding an aircraft can fail inside JSBSim: a refused request, not a dead node
            try:
                return request()
            except Hdrc3Error as exc:
                return SimResult(SimCode.WRONG_STATE, str(exc))

        def reset(req: Any, res: Any) -> Any:
            result = guarded(lambda: s.reset(req.agent, list(req.lockstep_agents)))
            if result.ok and not req.agent:
                self._restart = True
                self.pacer.restart()
                self._publish_objects()
            return reply(result, res)

        def pause(req: Any, res: Any) -> Any:
            return reply(s.pause(req.paused), res)

        def teleport(req: Any, res: Any) -> Any:
            wgs84 = req.frame == SimTeleport.Request.FRAME_WGS84
            if req.frame not in (SimTeleport.Request.FRAME_ENU, SimTeleport.Request.FRAME_WGS84):
                return reply(SimResult(SimCode.INVALID_ARGUMENT, f"unknown frame {req.frame}"), res)
            result = guarded(
                lambda: s.teleport(req.agent, wgs84, req.x, req.y, req.height, req.heading)
            )
            return reply(result, res)

        def inject_fault(req: Any, res: Any) -> Any:
            return reply(s.inject_fault(req.agent, req.sensor, req.mode, list(req.magnitude)), res)

        def spawn(req: Any, res: Any) -> Any:
            result = s.spawn_object(req.id, req.kind, req.east, req.north, req.heading)
            if result.ok:
                self._publish_objects()
            return reply(result, res)

        def set_wind(req: Any, res: Any) -> Any:
            mean = (req.mean.x, req.mean.y, req.mean.z)
            return reply(s.set_wind(mean, req.gust_intensity), res)

        def set_power(req: Any, res: Any) -> Any:
            return reply(s.set_power(req.agent, req.devices, req.on), res)

        base = f"/{NODE_NAME}"
        for srv_type, name, handler in (
            (SimReset, "reset", reset),
            (SimPause, "pause", pause),
            (SimTeleport, "teleport", teleport),
            (SimInjectFault, "inject_fault", inject_fault),
            (SimSpawnObject, "spawn_object", spawn),
            (SimSetWind, "set_wind", set_wind),
            (SimSetPower, "set_power", set_power),
        ):
            self.create_service(srv_type, f"{base}/{name}", handler, qos_profile=SERVICE_QOS)
        self._reply = reply

    def _rc_callback(self, agent: str) -> Callable[[Any, Any], Any]:
        def on_rc(req: Any, res: Any) -> Any:
            sticks = (req.roll, req.pitch, req.yaw, req.throttle) if req.set_sticks else None
            request = RcRequest(req.mode, req.engine, req.link, sticks)
            return self._reply(self.requests.set_rc(agent, request), res)

        return on_rc

    # ------------------------------------------------------------ publishing
    def _publish_run(self, event: RunEvent) -> None:
        """Announce how the world (re)started on /world_sim/run (latched)."""
        msg = SimRun()
        msg.kind = int(event.kind)
        msg.run_id = event.run.run_id
        msg.process_id = self.process_id
        set_stamp_ns(msg.stamp, event.stamp_ns)
        set_stamp_ns(msg.checkpoint_stamp, event.checkpoint_ns)
        msg.reason = event.reason
        self._run_pub.publish(msg)
        if event.kind is not RunKind.STARTED:
            self.get_logger().warning(event.reason)

    def _checkpoint(self) -> None:
        """Write the state of the current tick if due (before the tick is published)."""
        if not self.checkpoints.due(self.sim.tick):
            return
        barrier = self.barrier
        lockstep = tuple(sorted(barrier.required)) if barrier.explicit else ()
        self.run_state = RunState(self.run_state.run_id, self.requests.paused, lockstep)
        problem = self.checkpoints.write(self.sim, self.run_state)
        if problem is not None:
            self.get_logger().error(problem, throttle_duration_sec=10.0)

    def _publish_objects(self) -> None:
        """Every dynamic object; boxes, carriers and driving cars where they are now."""
        msg = WorldObjects()
        stamp_header(msg.header, self.sim.time_ns)
        poses = self.sim.object_poses()
        terrain = self.sim.world.terrain
        published = {}
        for obj in self.sim.objects.values():
            pose = poses.get(obj.id)
            item = WorldObject(id=obj.id, kind=obj.kind.value, size=list(obj.size))
            if pose is None:
                item.east, item.north, item.heading = obj.east, obj.north, obj.heading
                item.up = terrain.height(obj.east, obj.north)
            else:
                item.east, item.north, item.up = pose.east, pose.north, pose.up
                item.heading, item.held_by = pose.heading, pose.held_by
                published[obj.id] = (pose.east, pose.north, pose.up, pose.heading, pose.held_by)
            msg.objects.append(item)
        self._published_poses = published
        self._objects_pub.publish(msg)

    def _objects_moved(self) -> bool:
        """True when an object moved (or changed hands) since the last objects message."""
        last = self._published_poses
        for oid, p in self.sim.object_poses().items():
            old = last.get(oid)
            if old is None or old[4] != p.held_by:
                return True
            if max(abs(old[0] - p.east), abs(old[1] - p.north), abs(old[2] - p.up)) > MOVED:
                return True
            if abs((old[3] - p.heading + math.pi) % math.tau - math.pi) > MOVED:
                return True
        return False

    def _publish_carrying(self, name: str, ns: int) -> None:
        r = self.sim.carrying(name)
        msg = HookState(
            carrying=r.carrying,
            object_id=r.object_id,
            magnet=r.magnet,
            winch=int(r.winch),
            cable_length=r.cable_length,
            tension=r.tension,
        )
        stamp_header(msg.header, ns)
        self._carrying_pubs[name].publish(msg)
        camera = self._hook_camera_pubs[name]
        if camera.get_subscription_count():
            for tag, (east, north, up) in self.sim.hook_camera(name):
                seen = PointStamped()
                stamp_header(seen.header, ns)
                seen.header.frame_id = tag
                seen.point.x, seen.point.y, seen.point.z = east, north, up
                camera.publish(seen)

    def _publish_status(self, topics: AgentTopics, name: str, ns: int) -> None:
        sim = self.sim
        status = sim.status(name)
        m = topics.m_status
        stamp_header(m.header, ns)
        m.mode = (
            YacsStatus.MODE_AUTONOMOUS
            if status.mode is FlightModeSwitch.AUTONOMOUS
            else YacsStatus.MODE_MANUAL
        )
        m.rc_link_ok = status.rc_link_ok
        m.engine_switch = sim.agents[name].aircraft.rc.state.engine_on
        m.engine_running = status.engine_running
        m.rotor_rpm = status.rotor_rpm
        m.source = _SOURCES[status.source]
        m.rejected_commands = sim.agents[name].rejected_commands
        topics.status.publish(m)

    def publish_tick(self, repeat: bool = False) -> None:
        """Outputs of the current tick: control samples and status, /clock, then the rest.

        The lockstepped controllers read the control samples (IMU, attitude, GPS, ...) and
        ``yacs/status``, and answer once ``/clock`` is in: those go out first, then ``/clock``;
        the payload's samples (PTU, camera exposures and poses, laser), ground truth, carrying,
        objects and wind follow while the controllers compute their answer.
        ``repeat`` re-announces a stalled tick for late joiners: status, /clock and truth again
        with the same stamp, but no sensor sample twice.
        """
        sim = self.sim
        ns = sim.time_ns
        readings = {} if repeat else sim.take_readings()
        for name, topics in self.topics.items():
            if not repeat:
                topics.publish_control(readings[name])
            if topics.status.get_subscription_count():
                self._publish_status(topics, name, ns)
        set_stamp_ns(self._clock_msg.clock, ns)
        self._clock_pub.publish(self._clock_msg)
        # exposure poses only while world_render runs (its progress publisher is the sign)
        poses = self._render_sub.get_publisher_count() > 0
        for name, topics in self.topics.items():
            if not repeat:
                topics.publish_payload(readings[name], poses)
                if topics.last_exposure_ns is not None:
                    self.render_gate.announce(name, topics.last_exposure_ns)
            topics.publish_truth(sim.truth(name), ns)
            if not repeat and sim.tick % PAYLOAD_EVERY == 0:
                self._publish_carrying(name, ns)
        if not repeat and sim.tick % PAYLOAD_EVERY == 0 and self._objects_moved():
            self._publish_objects()
        if sim.tick % WIND_EVERY == 0 and self._wind_pub.get_subscription_count():
            w = self._wind
            stamp_header(w.header, ns)
            w.mean.x, w.mean.y, w.mean.z = sim.wind.mean
            w.gust.x, w.gust.y, w.gust.z = sim.wind.gust
            w.gust_intensity = sim.wind.settings.gust_intensity
            self._wind_pub.publish(w)

    # ------------------------------------------------------------------ loop
    def connected(self) -> list[str]:
        """Agents whose command topic has a publisher (automatic lockstep)."""
        return [n for n, sub in self._command_subs.items() if sub.get_publisher_count() > 0]

    def _wait_for_tick(self, executor: Any, stop: threading.Event) -> bool:
        """Serve callbacks until the next tick may run; False on stop or restart."""
        barrier = self.barrier
        waiting = barrier.begin_tick(self.sim.time_ns, () if barrier.explicit else self.connected())
        paced = not waiting or self.pace_lockstep
        checked = time.monotonic()
        self._render_wait_since = checked
        while True:
            if stop.is_set() or not self.context.ok() or self._restart:
                return False
            if self.requests.paused:
                executor.spin_once(timeout_sec=WAIT_STEP_S)
                self.pacer.restart()
                continue
            if not barrier.ready():
                executor.spin_once(timeout_sec=WAIT_STEP_S)
                now = time.monotonic()
                if now - checked > STALL_S:
                    checked = now
                    self._check_controllers()
                    self.publish_tick(repeat=True)
                continue
            if self._render_behind():
                executor.spin_once(timeout_sec=WAIT_STEP_S)
                continue
            if paced:
                wait = self.pacer.wait_time(self.sim.time + TICK_S, time.monotonic())
                if wait > 0.0:
                    executor.spin_once(timeout_sec=min(wait, WAIT_STEP_S))
                    continue
            if not waiting and self.sim.tick % FREE_SPIN_EVERY == 0:
                # serve requests between free-running ticks (a spin costs ~80 us)
                executor.spin_once(timeout_sec=0.0)
                if self._restart:
                    return False
            return True

    def _render_behind(self) -> bool:
        """True while world_render lags too far behind the exposures (``RenderGate``).

        After :data:`RENDER_STALL_S` of wall time since this tick's wait began without catching
        up, the tick runs anyway (a stuck renderer must not stop the world).
        """
        gate = self.render_gate
        if not gate.announced or self._render_sub.get_publisher_count() == 0:
            return False
        behind = gate.behind()
        if not behind:
            return False
        now = time.monotonic()
        if now - self._render_wait_since > RENDER_STALL_S:
            gate.stalls += 1
            self.get_logger().warning(
                f"world_render did not catch up with {', '.join(behind)} within "
                f"{RENDER_STALL_S} s: running on ({gate.stalls} stalled ticks)",
                throttle_duration_sec=10.0,
            )
            self._render_wait_since = now
            return False
        return True

    def _check_controllers(self) -> None:
        """While stuck: drop vanished controllers (automatic mode) or say whom we wait for."""
        barrier = self.barrier
        if barrier.explicit:
            missing = ", ".join(barrier.missing())
            self.get_logger().info(
                f"t={self.sim.time:.2f} s: waiting for the command of {missing}",
                throttle_duration_sec=5.0,
            )
            return
        present = set(self.connected())
        for agent in barrier.missing():
            if agent not in present:
                barrier.release(agent)

    def run(self, executor: Any, stop: threading.Event) -> None:
        """Tick until ``stop`` is set."""
        self._checkpoint()
        self._publish_run(self.start_event)
        self._publish_objects()
        self.publish_tick()
        while not stop.is_set() and self.context.ok():
            if not self._wait_for_tick(executor, stop):
                if self._restart:
                    self._restart = False
                    self._full_reset_done()
                continue
            for agent, command in self.barrier.commands().items():
                if command is not None:
                    self.sim.command(agent, command)
            self.sim.advance()
            self._checkpoint()
            self.publish_tick()

    def _full_reset_done(self) -> None:
        """After a full reset: a new run, checkpointed and announced before its first tick."""
        self.render_gate.reset()
        for topics in self.topics.values():
            topics.last_exposure_ns = None
        self.run_state = RunState(new_run_id())
        self._checkpoint()
        self._publish_run(
            RunEvent(
                RunKind.RESET,
                self.run_state,
                self.sim.time_ns,
                reason="full reset requested (/world_sim/reset): the world starts over at t = 0",
            )
        )
        self.publish_tick()


def main(argv: Sequence[str] | None = None) -> int:
    """Console script `hdrc3-world-sim`: exit 0 on SIGINT/SIGTERM, 2 on bad parameters."""
    return run_stepped_node(WorldSimNode, "world_sim", list(sys.argv if argv is None else argv))


if __name__ == "__main__":
    sys.exit(main())
