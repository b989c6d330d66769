"""The PFC kernel: HCSM interpreter + control functions + event protocol, one call per 50 Hz tick.

Pure core of the ``control_kernel`` node (no rclpy). One :meth:`PfcKernel.tick` is one pass of
Algorithm 1 in sim time:

1. *Communicate*: sensor samples of the period go to the state estimator in time order; events
   received from the DRC/PPC and the control functions' events of the previous tick are queued.
2. *ExecuteStateMachine*: the slots the automata read (Position-DO, Sync-DO, Fault-DO) are
   written, then one macro step of the PFC automata (``automata/pfc.hcsm``) runs.
3. *RunControlFunctions*: the kernel's own flags (KF init, power, yaw, segment offers, UI timer),
   braking and the Control Mode function set act on this step's flags; the selected function
   computes the command.

A pause of the simulation (a world_sim that died and resumed from its checkpoint: the clock jumps
by up to a checkpoint period while nothing moved and no sample came) is no sensor failure: when
sim time advances by more than ``KernelConfig.pause_gap`` between two ticks, the kernel runs on
its own clock, sim time minus the time it was not ticked, so sensor ages, dead-reckoning times
and timers do not count the pause. Reports keep the sim time.

The outgoing events pass :class:`~hdrc3_control.event_protocol.EventProtocol` and leave at the
end of the tick; the result holds the YACS command (always one, also in manual mode or on the
ground) and the :class:`~hdrc3_control.pfc_state.PfcSnapshot`.
"""

from __future__ import annotations

import enum
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, replace

from hdrc3_base.errors import ConfigError
from hdrc3_control.aiding import AidingSource
from hdrc3_control.automata import automaton_path
from hdrc3_control.braking import BrakeStatus
from hdrc3_control.car_following import TargetFix
from hdrc3_control.commands import AttitudeCommand, EstimatedState, EstimatorHealth, Vec3
from hdrc3_control.event_codec import encode, encode_values
from hdrc3_control.event_protocol import EventProtocol, SendLog
from hdrc3_control.hover import HoverStatus
from hdrc3_control.kernel_config import KernelConfig
from hdrc3_control.kernel_functions import (
    BrakingConsumer,
    FlytoFunction,
    FunctionContext,
    HoverFunction,
    LandingFunction,
    TakeoffFunction,
    TrackFunction,
    Traj3DFunction,
    pack_pose,
)
from hdrc3_control.landing import LandingPhase, LandingSite
from hdrc3_control.measurements import (
    AttitudeMeasurement,
    BaroMeasurement,
    GpsMeasurement,
    GroundContactMeasurement,
    ImuMeasurement,
    VisionPoseMeasurement,
)
from hdrc3_control.navigation_texts import baro_text, failsafe_texts, fault_text
from hdrc3_control.path_following import PathStatus
from hdrc3_control.pfc_state import (
    FAILSAFE_STATES,
    POWER_DRC,
    SENSOR_POWER,
    Failsafe,
    FlightMode,
    PfcSnapshot,
    PlatformStatus,
    PowerReading,
)
from hdrc3_control.ppc_modes import PadVision
from hdrc3_control.state_estimator import StateEstimator
from hdrc3_control.warm_start import WarmStart
from hdrc3_control.wind_estimate import WindEstimator
from hdrc3_hcsm.control_function import ControlFunctionRunner, ControlFunctionSet, FunctionState
from hdrc3_hcsm.event import PostStatus, WireEvent
from hdrc3_hcsm.interpreter import Interpreter, StepResult
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.main_loop import MainLoop
from hdrc3_hcsm.memory import ActionFlags, MemoryBank
from hdrc3_hcsm.tables import CompiledModel, compile_model
from hdrc3_hcsm.trace import TraceSink
from hdrc3_hcsm.transport import SendStatus, Transport

MODE_CHANGED_ID = 2107
"""Mode-Changed-EV (docs/realtime_events.md): sent by the kernel itself on every mode change.

The one id the PFC models cannot give: no automaton sends the event, and declaring it there
would be an unused declaration (W002). The DRC model declares it, and test_drc checks this id.
"""

_FUNCTION_MODES = {
    "hover": FlightMode.HOVER,
    "takeoff": FlightMode.TAKEOFF,
    "traj3d": FlightMode.TRAJ3D,
    "flyto": FlightMode.FLYTO,
    "landing": FlightMode.LAND,
    # car following flies on the path following mode's outer loop (§6.2.2); PfcState has no
    # MODE_TRACK, so the Data Interface shows it as path following
    "track": FlightMode.TRAJ3D,
}
GROUND_IDLE = AttitudeCommand(vertical=-1.0)
"""On the skids: minimum collective (the YACS keeps the collective at 0 when not climbing)."""
LEVEL_HOLD = AttitudeCommand()
"""Airborne with no function running (for a tick between two functions): level, climb rate 0."""


@functools.cache
def load_model() -> CompiledModel:
    """The shipped PFC model, loaded and compiled once (raises on a broken file: packaging)."""
    return compile_model(load_file(automaton_path()))


class UiCommand(enum.Enum):
    """Keys of the ground UI (topic ``<agent>/pfc/ui``)."""

    ARM = "arm"
    BRAKE = "brake"
    LAND = "land"


_UI_EVENTS = {
    UiCommand.ARM: "Ui-Arm-EV",
    UiCommand.BRAKE: "Ui-Brake-EV",
    UiCommand.LAND: "Ui-Land-EV",
}


@dataclass(frozen=True, slots=True)
class PowerRequest:
    """Devices the Power Switch / Root asked the power management unit to switch on."""

    devices: int


@dataclass(frozen=True, slots=True)
class TickResult:
    """Outcome of one control tick."""

    command: AttitudeCommand
    snapshot: PfcSnapshot
    step: StepResult
    sent: tuple[WireEvent, ...]
    power_requests: tuple[PowerRequest, ...]


Sample = (
    ImuMeasurement
    | AttitudeMeasurement
    | GpsMeasurement
    | BaroMeasurement
    | GroundContactMeasurement
    | VisionPoseMeasurement
)


class PfcKernel:
    """The control kernel of one aircraft; call :meth:`tick` every 20 ms of sim time."""

    def __init__(
        self,
        config: KernelConfig | None = None,
        *,
        terrain: Callable[[float, float], float],
        transport: Transport | None = None,
        trace: TraceSink | None = None,
        start_time: float = 0.0,
        warm_start: WarmStart | None = None,
        landing_sites: tuple[LandingSite, ...] = (),
    ) -> None:
        """Load the automata and bind conditions, functions and flags (ModelError if invalid).

        ``landing_sites``: the world's pads with the vision landing pattern (§5.4).

        ``warm_start``: the record a previous run of this kernel left (``warm_start.py``); used
        at the first tick if it is at most ``warm_start_max_age`` old then.
        """
        self.config = c = config or KernelConfig()
        self._warm_start = warm_start
        self.warm_start_note = "cold start"
        """What became of the warm-start record (for the node's log)."""
        self.terrain = terrain
        self.transport = transport
        self.ctx = FunctionContext(terrain=terrain, dt=c.tick, landing_sites=landing_sites)
        self.hover = HoverFunction(self.ctx)
        self.takeoff = TakeoffFunction(self.ctx, c.takeoff)
        self.traj3d = Traj3DFunction(self.ctx, c.path, c.segment_start_tolerance)
        self.flyto = FlytoFunction(self.ctx, c.path, c.climb_speed)
        self.landing = LandingFunction(self.ctx, c.landing)
        self.track = TrackFunction(self.ctx, c.track)
        self.braking = BrakingConsumer(self.ctx, c.path)
        self.functions = ControlFunctionSet(
            {
                "Hover-Mode-AC": ControlFunctionRunner("hover", self.hover),
                "Takeoff-Mode-AC": ControlFunctionRunner("takeoff", self.takeoff),
                "Traj3D-Mode-AC": ControlFunctionRunner("traj3d", self.traj3d),
                "Flyto-Mode-AC": ControlFunctionRunner("flyto", self.flyto),
                "Land-Mode-AC": ControlFunctionRunner("landing", self.landing),
                "Track-Mode-AC": ControlFunctionRunner("track", self.track),
            }
        )
        self.model = load_model() if c.model is None else compile_model(load_file(c.model))
        """The compiled PFC model: its events' ids are the wire contract's."""
        events = self.model.source.events
        self.log = SendLog(frozenset(e.name for e in events if e.source == "DRC"), trace)
        rejected = self.model.events.id_of("Cmd-Rejected-EV")
        self.protocol = EventProtocol(
            lambda: self.ctx.failure,
            rejected,
            lambda trigger: self._fs_reasons.get(trigger),
            lambda command_id: self.ctx.notes.pop(command_id, ""),
            lambda command_id: self.ctx.accept_notes.pop(command_id, ""),
        )
        self.interpreter = Interpreter(self.model, self._conditions(), trace=self.log)
        self.loop = MainLoop(self.interpreter, (self, self.braking, self.functions))
        self.estimator = StateEstimator(c.estimator)
        self.state: EstimatedState | None = None
        self.wind = WindEstimator(c.wind)
        """The on-board wind estimate (attitude and velocity), for the landing's heading."""
        self.now = start_time
        """The kernel's clock: sim time minus :attr:`paused`."""
        self.paused = 0.0
        """Sim time the kernel was not ticked in simulation pauses (``pause_gap``), s."""
        self.pauses = 0
        self._sim_now = start_time
        self.ticks = 0
        self.mode = FlightMode.BOOT
        self._samples: list[tuple[float, int, Sample]] = []
        self._seq = 0
        self._kf_enabled = False
        self._last_imu = -math.inf
        self._last_attitude = -math.inf
        self._last_gps = -math.inf
        self._last_gps_position: Vec3 = (0.0, 0.0, 0.0)
        self._on_ground = True
        self._status: PlatformStatus | None = None
        self._power: PowerReading | None = None
        self._power_since = start_time
        self._power_requests: list[PowerRequest] = []
        self._ground_ref: Vec3 | None = None
        self._last_sync = -math.inf
        self._ui_since = -math.inf
        self._fault = ""
        self._states: dict[str, str] = {}
        self._fs_texts: dict[str, str] = {}
        self._fs_reasons: dict[str, str] = {}
        """Reason of a command failed by a failsafe event (Fs-Hold-EV, Fs-Land-EV)."""
        self.failsafe = Failsafe.NONE
        self.failsafe_reason = ""

    # ------------------------------------------------------------------ inputs
    def feed(self, sample: Sample) -> None:
        """Queue a sensor sample; the next tick applies the samples in time order."""
        self._seq += 1
        self._samples.append((sample.time, self._seq, sample))

    def feed_rpm(self, rpm: float) -> None:
        """Latest main rotor rpm."""
        self.estimator.update_rpm(rpm)

    def feed_status(self, status: PlatformStatus) -> None:
        """Latest YACS/RC status."""
        self._status = status

    def feed_power(self, reading: PowerReading) -> None:
        """Latest power management unit report."""
        self._power = reading

    def pad_vision(self, state: int) -> bool:
        """The PPC's :class:`PadVision` report (``ppc/pad_vision``); False if not one of them.

        The landing plans on it: it searches for the pad's pattern only when the PPC can see it.
        """
        try:
            self.ctx.pad_vision = PadVision(state)
        except ValueError:
            return False
        return True

    def target_fix(self, time: float, east: float, north: float, up: float) -> bool:
        """A ground fix of the colour tracker's car (image time, world ENU); False if not finite.

        Kept for the car following function (``fcl_track``) on the kernel's clock.
        """
        if not all(math.isfinite(v) for v in (time, east, north, up)):
            return False
        self.ctx.target_fixes.append(TargetFix(time - self.paused, (east, north, up)))
        return True

    def post_ui(self, command: UiCommand) -> PostStatus:
        """A key of the ground UI; LAND lands with the current heading."""
        data = encode(0)
        if command is UiCommand.LAND:
            heading = self.state.heading if self.state is not None else 0.0
            data = encode(0, (heading,))
        if command is UiCommand.BRAKE:
            with self.interpreter.memory.lock:
                self.interpreter.memory.write("Ui-Command-DO", encode(0))
        return self._post(_UI_EVENTS[command], data)

    def _post(self, name: str, data: bytes) -> PostStatus:
        status = self.interpreter.post_external(name, data)
        if status is PostStatus.ACCEPTED:
            self.log.posted(name, data)
        return status

    def _apply_samples(self) -> None:
        samples = sorted(self._samples, key=lambda s: (s[0], s[1]))
        self._samples.clear()
        est = self.estimator
        for _, _, s in samples:
            if self.paused:
                s = replace(s, time=s.time - self.paused)
            if isinstance(s, ImuMeasurement):
                self._last_imu = s.time
                if self._kf_enabled:
                    est.update_imu(s)
            elif isinstance(s, AttitudeMeasurement):
                self._last_attitude = s.time
                est.update_attitude(s)
            elif isinstance(s, GpsMeasurement):
                self._last_gps = s.time
                self._last_gps_position = s.position
                if self._kf_enabled:
                    est.update_gps(s)
            elif isinstance(s, BaroMeasurement):
                if self._kf_enabled:
                    est.update_baro(s)
            elif isinstance(s, VisionPoseMeasurement):
                if self._kf_enabled:
                    est.update_vision(s)
            else:
                self._on_ground = s.on_ground
                if self._kf_enabled:
                    e, n, _ = self._position_now(s.time)
                    est.update_ground_contact(
                        GroundContactMeasurement(s.time, s.on_ground, self.terrain(e, n))
                    )

    def _position_now(self, time: float) -> Vec3:
        if self.estimator.initialised:
            try:
                return self.estimator.estimate(time).position
            except ConfigError:  # no attitude yet after a reset: use the GPS fix
                return self._last_gps_position
        return self._last_gps_position

    # ------------------------------------------------------------------ conditions
    def _conditions(self) -> dict[str, Callable[[], bool]]:
        c = self.config
        health = self._health
        conditions: dict[str, Callable[[], bool]] = dict(self.functions.conditions())
        conditions.update(
            {
                "Drc-Powered-CO": lambda: (
                    self._power is not None and bool(self._power.status & POWER_DRC)
                ),
                "Power-Known-CO": lambda: self._power is not None,
                "Power-Timeout-CO": lambda: self.now - self._power_since > c.power_timeout,
                "Sensors-Powered-CO": lambda: (
                    self._power is not None and self._power.status & SENSOR_POWER == SENSOR_POWER
                ),
                "Sensors-Ok-CO": self._sensors_ok,
                "Kf-Ready-CO": lambda: (
                    self.estimator.initialised and health() is EstimatorHealth.OK
                ),
                "Rc-Auto-CO": lambda: self._status is not None and self._status.autonomous,
                "Engine-On-CO": lambda: self._status is not None and self._status.engine_running,
                "On-Ground-CO": lambda: self._on_ground,
                "Nav-Degraded-CO": lambda: (
                    self.estimator.initialised
                    and health() is not EstimatorHealth.OK
                    and (
                        health() is EstimatorHealth.LOST
                        or self.estimator.aiding_age(self.now) > c.gps_loss_tolerance
                    )
                ),
                "Baro-Fault-CO": lambda: self.estimator.baro_fault is not None,
                "Nav-Lost-CO": lambda: (
                    self.estimator.initialised and health() is EstimatorHealth.LOST
                ),
                "Landing-CO": lambda: self._function_selected("landing"),
                "Braking-Done-CO": self.braking.done,
                "Hover-Stable-CO": lambda: (
                    self._function_is("hover") and self.hover.status is HoverStatus.STABLE
                ),
                "Takeoff-Done-CO": lambda: self._function_is("takeoff") and self.takeoff.done,
                "Yaw-Done-CO": self.hover.yaw_done,
                "Single-Segment-CO": lambda: self.traj3d.single_segment(self.interpreter.memory),
                "Path-Stopped-CO": lambda: self.traj3d.status is PathStatus.STOPPED,
                "Touchdown-CO": lambda: (
                    self.landing.phase in (LandingPhase.TOUCHDOWN, LandingPhase.LANDED)
                ),
                "Landed-CO": lambda: self.landing.phase is LandingPhase.LANDED,
                "Ground-Ref-CO": lambda: self._ground_ref is not None,
                "Sync-Due-CO": lambda: self.now - self._last_sync >= c.sync_period,
                "Ui-Timeout-CO": lambda: self.now - self._ui_since > c.ui_window,
            }
        )
        return conditions

    def _health(self) -> EstimatorHealth:
        return self.estimator.health(self.now)

    def _sensors_ok(self) -> bool:
        now, est = self.now, self.config.estimator
        return (
            now - self._last_imu <= est.imu_timeout
            and now - self._last_attitude <= est.attitude_timeout
            and now - self._last_gps <= self.config.gps_timeout
        )

    def _function_selected(self, name: str) -> bool:
        cur = self.functions.current
        return cur is not None and cur.name == name and cur.state is not FunctionState.OFF

    def _function_is(self, name: str) -> bool:
        cur = self.functions.current
        return cur is not None and cur.name == name and cur.state is FunctionState.RUNNING

    # ------------------------------------------------------------------ kernel flags
    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        """FlagConsumer for the kernel's own flags (runs before braking and the functions)."""
        if flags.is_set("Kf-Init-AC"):
            self.estimator.reset()
            self._kf_enabled = True
            self._ground_ref = None
        if flags.is_set("Power-Drc-On-AC"):
            self._power_requests.append(PowerRequest(POWER_DRC))
            self._power_since = now
        if flags.is_set("Power-Sensors-On-AC"):
            self._power_requests.append(PowerRequest(SENSOR_POWER))
            self._power_since = now
        if flags.is_set("Yaw-AC"):
            self.ctx.yaw_request = True
        if flags.is_set("Segment-Offer-AC"):
            self.ctx.offer_pending = True
        if flags.is_set("Ui-Timer-Start-AC"):
            self._ui_since = now

    # ------------------------------------------------------------------ the tick
    def tick(self, now: float) -> TickResult:
        """One pass of Algorithm 1 at sim time ``now``."""
        sim_now = now
        if self.ticks and sim_now - self._sim_now > self.config.pause_gap:
            self.paused += sim_now - self._sim_now - self.config.tick
            self.pauses += 1
        self._sim_now = sim_now
        now = sim_now - self.paused
        self.now = now
        self.ticks += 1
        if self.ticks == 1:
            # the node may join a clock that is already running: time-outs start now
            self._power_since = now
            self._use_warm_start(sim_now)
        interp = self.interpreter
        # Communicate: sensors, then events from the other computers
        self._apply_samples()
        if self.transport is not None:
            for event in self.transport.receive():
                if interp.post_wire(event) is PostStatus.ACCEPTED:
                    self.log.posted(event.name, event.data)
        self.state = self._estimate(now)
        self.ctx.state, self.ctx.command, self.ctx.camera_aim = self.state, None, None
        if self.state is None:
            self.wind.reset()
            self.ctx.wind = None
        else:
            self.ctx.wind = self.wind.update(self.state)
        self.ctx.vision_age = self.estimator.aiding.age(AidingSource.VISION, now)
        self.ctx.vision_seen_age = self.estimator.aiding.seen_age(AidingSource.VISION, now)
        self._write_slots(interp.memory, now)
        step = interp.execute(now)
        self._states = self._machine_states()
        self._update_failsafe()
        self.loop.run_control_functions(now)
        cur = self.functions.current
        if cur is not None and cur.state is FunctionState.RUNNING:
            self.braking.stop()
        for name, data in self.ctx.events:
            self._post(name, data)
        self.ctx.events.clear()
        sent = self._send(interp.take_outbox())
        requests, self._power_requests = tuple(self._power_requests), []
        command = self._command()
        return TickResult(command, self._snapshot(sim_now), step, sent, requests)

    def _use_warm_start(self, sim_now: float) -> None:
        record = self._warm_start
        if record is None:
            return
        why_not = record.usable_at(sim_now, self.config.warm_start_max_age)
        if why_not is not None:
            self.warm_start_note = f"cold start: warm-start {why_not}"
            return
        self.estimator.seed_baro_bias(record.baro_bias, record.baro_bias_sigma)
        self.warm_start_note = (
            f"warm start: barometer bias {record.baro_bias:.2f} m of t = {record.time:.2f} s"
        )

    def aiding_report(self) -> dict[str, object]:
        """Which sources the navigation filter used lately, and their verdict counts (JSON)."""
        est = self.estimator
        return est.aiding.report(self.now, est.config.aiding_timeout)

    def warm_start_record(self) -> WarmStart | None:
        """The record to keep for a restart now (None while the solution is not good)."""
        est = self.estimator
        if not (self._kf_enabled and est.initialised) or est.health(self.now) is not (
            EstimatorHealth.OK
        ):
            return None
        bias, sigma = est.baro_reference()
        return WarmStart(self._sim_now, bias, sigma)

    def _estimate(self, now: float) -> EstimatedState | None:
        if not (self._kf_enabled and self.estimator.initialised):
            return None
        try:
            state = self.estimator.estimate(now)
        except ConfigError:  # initialised without attitude yet: no solution
            return None
        if self._ground_ref is None and state.health is EstimatorHealth.OK:
            self._ground_ref = state.position
        return state

    def _write_slots(self, memory: MemoryBank, now: float) -> None:
        with memory.lock:
            if self.state is not None:
                memory.write("Position-DO", pack_pose(self.state.position, self.state.heading))
            ref = self._ground_ref or (0.0, 0.0, 0.0)
            memory.write("Sync-DO", encode_values((self._sim_now, *ref)))
            memory.write("Fault-DO", fault_text(self.estimator, now).encode("utf-8")[:256])
            baro = baro_text(self.estimator)
            if baro is not None:
                memory.write("Baro-DO", baro.encode("utf-8")[:256])
            self._fs_texts = failsafe_texts(self.estimator, now, self._on_ground)
            for slot, text in self._fs_texts.items():
                memory.write(slot, text.encode("utf-8")[:256])
            memory.write("No-Command-DO", encode(0))
        self._fs_reasons = {
            "Fs-Hold-EV": self._fs_texts["Fs-Hold-DO"],
            "Fs-Land-EV": self._fs_texts["Fs-Land-DO"],
        }

    def _update_failsafe(self) -> None:
        """The Failsafe automaton's state after this step, with the text that announced it."""
        failsafe = FAILSAFE_STATES.get(self._states.get("Failsafe", ""), Failsafe.NONE)
        if failsafe is not self.failsafe:
            self.failsafe = failsafe
            slot = {Failsafe.HOLD: "Fs-Hold-DO", Failsafe.LAND: "Fs-Land-DO"}.get(failsafe)
            self.failsafe_reason = self._fs_texts.get(slot, "") if slot else ""

    def _send(self, outbox: list[WireEvent]) -> tuple[WireEvent, ...]:
        sends, unanswered = self.log.take()
        events = self.protocol.outgoing(outbox, sends, unanswered)
        for event in events:
            if event.name == "Sync-EV":
                self._last_sync = self.now
        mode = self._mode()
        if mode is not self.mode or self.ticks == 1:
            # the first tick reports the mode too: a (re)started PFC announces itself, and the
            # DRC hears its new incarnation (docs/realtime_events.md, "Restarts")
            self.mode = mode
            events.append(
                WireEvent(
                    MODE_CHANGED_ID, "Mode-Changed-EV", encode_values((float(mode),)), "PFC", "DRC"
                )
            )
        if self.transport is not None:
            events = [e for e in events if self.transport.send(e) is SendStatus.SENT]
        return tuple(events)

    # ------------------------------------------------------------------ outputs
    def _machine_states(self) -> dict[str, str]:
        out: dict[str, str] = {}
        for entry in self.interpreter.configuration():
            path, _, state = entry.rpartition(":")
            out[path.rsplit("/", 1)[-1]] = state
        return out

    def machine_state(self, machine: str) -> str:
        """Current state of automaton ``machine`` after the last tick ("" if not active)."""
        return self._states.get(machine, "")

    def auto(self) -> bool:
        """Autonomous mode: the Auto Switch runs the Mode Switch."""
        return self._states.get("Auto-Switch") == "Auto-ST"

    def _mode(self) -> FlightMode:
        auto_state = self._states.get("Auto-Switch")
        if auto_state == "Manual-ST":
            return FlightMode.MANUAL
        if auto_state != "Auto-ST":
            return FlightMode.BOOT
        cur = self.functions.current
        if cur is not None and cur.state is FunctionState.RUNNING:
            return _FUNCTION_MODES.get(cur.name, FlightMode.SWITCHING)
        if self.braking.active:
            return FlightMode.BRAKING
        if self._states.get("Mode-Switch") == "Ground-Idle-ST":
            return FlightMode.GROUND_IDLE
        return FlightMode.SWITCHING

    def _command(self) -> AttitudeCommand:
        if self.auto() and self.state is not None:
            cur = self.functions.current
            if cur is not None and cur.state is FunctionState.RUNNING and self.ctx.command:
                return self.ctx.command
            if self.braking.active and self.braking.command is not None:
                return self.braking.command
        return GROUND_IDLE if self._on_ground else LEVEL_HOLD

    def _snapshot(self, now: float) -> PfcSnapshot:
        """The report of this tick, stamped with the sim time ``now``."""
        s = self.state
        cur = self.functions.current
        running = cur is not None and cur.state is not FunctionState.OFF
        status = self._status
        return PfcSnapshot(
            time=now,
            mode=self.mode,
            position=s.position if s else self._last_gps_position,
            velocity=s.velocity if s else (0.0, 0.0, 0.0),
            roll=s.roll if s else 0.0,
            pitch=s.pitch if s else 0.0,
            heading=s.heading if s else 0.0,
            rates=s.rates if s else (0.0, 0.0, 0.0),
            rotor_rpm=s.rotor_rpm if s else (status.rotor_rpm if status else 0.0),
            on_ground=self._on_ground,
            auto=self.auto(),
            engine_running=status is not None and status.engine_running,
            estimator_initialised=self.estimator.initialised,
            health=self.estimator.health(self.now) if self._kf_enabled else EstimatorHealth.LOST,
            position_sigma=s.position_sigma if s else math.inf,
            control_function=cur.name if running and cur is not None else "",
            mode_switch_state=self._states.get("Mode-Switch", "") if self.auto() else "",
            command_id=self.protocol.current,
            ticks=self.ticks,
            failsafe=self.failsafe,
            failsafe_reason=self.failsafe_reason,
        )

    def braking_status(self) -> BrakeStatus:
        """Status of the braking consumer (for tests and diagnostics)."""
        return self.braking.status
