"""A fake PFC and a fake PPC that speak the event contract (docs/realtime_events.md).

They stand in for the control and perception kernels in unit tests and in the benchmark: each
receives command events through a :class:`~hdrc3_hcsm.transport.Transport`, keeps a simple
kinematic state, and replies with the contract's events after configurable sim-time durations.
They are deliberately simple (no physics); the real kernels live in ``hdrc3_control``.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field, replace

from hdrc3_control.event_codec import decode, encode, encode_values
from hdrc3_control.kernel_functions import OFFER_REFUSALS
from hdrc3_control.path_following import OfferStatus
from hdrc3_control.pfc_state import FlightMode
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.transport import LoopbackNetwork, Transport
from hdrc3_platform_server.commands import wire_arity
from hdrc3_platform_server.completion import CompletionEvent, EventLog
from hdrc3_platform_server.data_interface import HelicopterStateData
from hdrc3_platform_server.drc import load_model
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.journal import CommandJournal
from hdrc3_platform_server.platform_status import CameraSample, PfcSample


def _event_id(name: str) -> int:
    """Id of a reply event: the DRC model declares every event the kernels send it."""
    return load_model().events.id_of(name)


@dataclass
class FakePfcTiming:
    """Sim seconds each activity takes in the fake."""

    takeoff: float = 1.0
    land: float = 1.0
    yaw: float = 0.4
    climb: float = 0.6
    flyto: float = 1.0
    segment: float = 0.5
    brake: float = 0.3
    takeoff_height: float = 10.0


@dataclass
class _Job:
    command_id: int
    kind: str
    done_at: float
    target: tuple[float, float, float] | None = None
    end_velocity: float = 0.0
    queue: deque[tuple[int, float, tuple[float, float, float]]] = field(default_factory=deque)


class FakePfc:
    """A PFC stand-in: accepts, rejects, finishes, streams segments, brakes, cancels.

    ``fcl_track`` is accepted and runs until cancel or emergency brake, as in the real PFC
    while the colour tracker follows the car (the fake has no car to lose).
    """

    def __init__(
        self,
        transport: Transport,
        timing: FakePfcTiming | None = None,
        *,
        on_ground: bool = True,
        auto: bool = True,
    ) -> None:
        self.transport = transport
        self.timing = timing or FakePfcTiming()
        self.now = 0.0
        self.position = (0.0, 0.0, 0.0 if on_ground else self.timing.takeoff_height)
        self.heading = 0.0
        self.on_ground = on_ground
        self.auto = auto
        self.mode = FlightMode.GROUND_IDLE if on_ground else FlightMode.HOVER
        self.job: _Job | None = None
        self.received: list[WireEvent] = []
        self.quiet_last_segment = False
        """True: no Request-Segment-EV when a stopping (last) segment starts (a real PFC may)."""
        self.replace_queued = True
        """False: refuse a segment while a next one is queued (as the PFC does when the aircraft
        is too close to the end of its segment to brake for the replacement)."""
        self.reject_next: str | None = None
        """If set, the next command is rejected with this reason (a race the DRC cannot see)."""

    # --- wire -----------------------------------------------------------------------------
    def _send(self, name: str, command_id: int | None, reason: str = "") -> None:
        data = b"" if command_id is None else encode(command_id, (), reason)
        self.transport.send(WireEvent(_event_id(name), name, data, "PFC", "DRC"))

    def step(self, now: float) -> PfcSample:
        """Advance to sim time ``now``: take commands, finish jobs, report the state."""
        self.now = now
        for event in self.transport.receive():
            self.received.append(event)
            self._command(event)
        self._progress()
        return self.sample(now)

    def sample(self, received: float) -> PfcSample:
        """The state report the real PFC would publish."""
        return PfcSample(
            pfc_time=self.now,
            received=received,
            position_enu=self.position,
            velocity_enu=(0.0, 0.0, 0.0),
            latitude=0.0,
            longitude=0.0,
            altitude=0.0,
            roll=0.0,
            pitch=0.0,
            heading=self.heading,
            rpm=0.0 if self.on_ground else 1400.0,
            on_ground=self.on_ground,
            auto_flag=self.auto,
            mode=self.mode,
            command_id=self.job.command_id if self.job else 0,
        )

    # --- commands -------------------------------------------------------------------------
    def _command(self, event: WireEvent) -> None:
        name = event.name
        arity = wire_arity().get(name)
        if arity is None:
            return
        p = decode(event.data, arity)
        if not p.ok:
            return
        cid, v = p.command_id, p.values
        t = self.timing
        if name == "FCL-Cancel-EV":
            self._abort(f"cancelled by command {cid}")
            return
        if name == "Emergency-Brake-EV":
            self._abort(f"emergency brake (command {cid})")
            self._begin(_Job(cid, "brake", self.now + t.brake), FlightMode.BRAKING)
            return
        if name == "Traj3D-EV" and self.job is not None and self.job.kind == "path":
            self._offer(cid, v)
            return
        if self.reject_next is not None:
            self._send("Cmd-Rejected-EV", cid, self.reject_next)
            self.reject_next = None
            return
        if self.job is not None:
            self._send("Cmd-Rejected-EV", cid, f"busy with command {self.job.command_id}")
            return
        if name == "FCL-Takeoff-EV":
            if not self.on_ground:
                self._send("Cmd-Rejected-EV", cid, "already airborne")
                return
            self._begin(_Job(cid, "takeoff", self.now + t.takeoff), FlightMode.TAKEOFF)
            return
        if self.on_ground:
            self._send("Cmd-Rejected-EV", cid, "on the ground")
            return
        if name == "FCL-Land-EV":
            self._begin(_Job(cid, "land", self.now + t.land), FlightMode.LAND)
        elif name == "FCL-Yaw-EV":
            self.heading = v[0]
            self._begin(_Job(cid, "yaw", self.now + t.yaw), FlightMode.HOVER)
        elif name == "FCL-Climb-EV":
            target = (self.position[0], self.position[1], v[0])
            self._begin(_Job(cid, "climb", self.now + t.climb, target), FlightMode.FLYTO)
        elif name == "Traj3D-Flyto-EV":
            self._begin(
                _Job(cid, "flyto", self.now + t.flyto, (v[0], v[1], v[2])), FlightMode.FLYTO
            )
        elif name == "Traj3D-EV":
            job = _Job(cid, "path", self.now + t.segment, (v[3], v[4], v[5]), v[13])
            self._begin(job, FlightMode.TRAJ3D)
            self._send("Request-Segment-EV", cid)
        elif name == "FCL-Track-EV":
            # car following runs until cancelled (or, in the real PFC, the car is lost)
            self._begin(_Job(cid, "track", math.inf), FlightMode.TRAJ3D)

    def _begin(self, job: _Job, mode: FlightMode) -> None:
        self.job = job
        self.mode = mode
        self._send("Cmd-Accepted-EV", job.command_id)

    def _abort(self, reason: str) -> None:
        if self.job is not None:
            self._send("Cmd-Cancelled-EV", self.job.command_id, reason)
            self.job = None
        self.mode = FlightMode.GROUND_IDLE if self.on_ground else FlightMode.HOVER

    def _offer(self, cid: int, v: tuple[float, ...]) -> None:
        job = self.job
        assert job is not None
        if job.queue and not self.replace_queued:
            refusal = OFFER_REFUSALS[OfferStatus.TOO_LATE_TO_REPLACE]
            self._send("Cmd-Rejected-EV", cid, refusal)
            return
        # a queued, not yet flown segment is replaced: it ends as the PFC ends it (Traj3D C.18)
        for old, _, _ in job.queue:
            self._send("Cmd-Cancelled-EV", old, f"replaced by segment {cid}")
        job.queue.clear()
        job.queue.append((cid, v[13], (v[3], v[4], v[5])))
        self._send("Cmd-Accepted-EV", cid)

    def _progress(self) -> None:
        job = self.job
        if job is None or self.now < job.done_at:
            return
        if job.kind == "path":
            if job.target is not None:
                self.position = job.target
            if job.queue:
                cid, end_velocity, target = job.queue.popleft()
                self.job = replace(
                    job,
                    command_id=cid,
                    done_at=self.now + self.timing.segment,
                    target=target,
                    end_velocity=end_velocity,
                    queue=job.queue,
                )
                if end_velocity > 0.0 or not self.quiet_last_segment:
                    self._send("Request-Segment-EV", cid)
                self._send("Cmd-Finished-EV", job.command_id)  # the segment it follows
                return
            if job.end_velocity > 0.0:
                self._send("Cmd-Failed-EV", job.command_id, "safety braking: next segment late")
            else:
                self._send("Traj-Arrived-EV", job.command_id)
            self._hover()
            return
        if job.kind == "takeoff":
            self.on_ground = False
            self.position = (self.position[0], self.position[1], self.timing.takeoff_height)
        elif job.kind == "land":
            self.on_ground = True
            self.position = (self.position[0], self.position[1], 0.0)
        elif job.target is not None:
            self.position = job.target
        arrived = job.kind in ("flyto",)
        self._send("Traj-Arrived-EV" if arrived else "Cmd-Finished-EV", job.command_id)
        if job.kind == "land":
            self.job = None
            self.mode = FlightMode.GROUND_IDLE
            return
        self._hover()

    def _hover(self) -> None:
        self.job = None
        self.mode = FlightMode.HOVER
        self._send("Hover-Stable-EV", None)


class FakePpc:
    """A PPC stand-in: PTU and zoom move in ``move_time``; parameters apply at once."""

    def __init__(self, transport: Transport, move_time: float = 0.2) -> None:
        self.transport = transport
        name = "PPC-Started-EV"  # like the real kernel: announced before any reply
        self.transport.send(WireEvent(_event_id(name), name, b"", "PPC", "DRC"))
        self.move_time = move_time
        self.now = 0.0
        self.pan = 0.0
        self.tilt = 0.0
        self.zoom = 0.0
        self.pending: list[tuple[float, int]] = []
        self.received: list[WireEvent] = []
        self.fail_next: str | None = None
        """If set, the next command fails with this reason (tests)."""

    def _reply(self, cid: int, reason: str | None) -> None:
        name = "PPCL-Finished-EV" if reason is None else "PPCL-Failed-EV"
        data = encode(cid, (), reason or "")
        self.transport.send(WireEvent(_event_id(name), name, data, "PPC", "DRC"))

    def step(self, now: float) -> list[CameraSample]:
        """Advance to ``now``; returns the camera reports (color and thermal)."""
        self.now = now
        for event in self.transport.receive():
            self.received.append(event)
            arity = wire_arity().get(event.name)
            if arity is None:
                continue
            p = decode(event.data, arity)
            if not p.ok:
                continue
            if self.fail_next is not None:
                self._reply(p.command_id, self.fail_next)
                self.fail_next = None
                continue
            if event.name == "PPCL-Turn-To-EV":
                self.pan, self.tilt = p.values
            elif event.name == "PPCL-Zoom-EV":
                self.zoom = p.values[1]
            if event.name in ("PPCL-Turn-To-EV", "PPCL-Look-At-EV", "PPCL-Zoom-EV"):
                self.pending.append((now + self.move_time, p.command_id))
            else:
                self._reply(p.command_id, None)
        for entry in [e for e in self.pending if e[0] <= now]:
            self.pending.remove(entry)
            self._reply(entry[1], None)
        return [
            CameraSample(cam, self.pan, self.tilt, self.zoom if cam == 0 else 0.0, now, now)
            for cam in (0, 1)
        ]


class FakeRig:
    """A Platform Server core wired to a fake PFC and PPC over a loopback network.

    :meth:`run` advances sim time in 20 ms PFC ticks, as the real lockstep does.
    """

    TICK = 0.02

    def __init__(
        self,
        frame: WorldFrame,
        *,
        on_ground: bool = True,
        timing: FakePfcTiming | None = None,
        with_ppc: bool = True,
        journal: CommandJournal | None = None,
    ) -> None:
        from hdrc3_platform_server.server import PlatformServerCore

        self.net = LoopbackNetwork()
        self.frame = frame
        self.log = EventLog()
        self.core = PlatformServerCore(frame, self.net.endpoint("DRC"), self.log, journal=journal)
        self.pfc = FakePfc(self.net.endpoint("PFC"), timing, on_ground=on_ground)
        self.ppc = FakePpc(self.net.endpoint("PPC")) if with_ppc else None
        self.t = 0.0
        self.pfc_online = True
        """False: the PFC sends nothing (the DRC then only ticks on its own)."""
        self.published: list[HelicopterStateData] = []
        self.run(0.1)

    def run(self, seconds: float) -> None:
        """Advance ``seconds`` of sim time."""
        steps = round(seconds / self.TICK)
        for _ in range(steps):
            self.t = round(self.t + self.TICK, 9)
            if not self.pfc_online:
                self.core.tick(self.t)
                continue
            sample = self.pfc.step(self.t)
            if self.ppc is not None:
                for camera in self.ppc.step(self.t):
                    self.core.on_camera(camera)
            data = self.core.on_pfc(sample)
            if data is not None:
                self.published.append(data)

    def restart_pfc(self) -> None:
        """The PFC process dies and starts again: same aircraft, no command, new incarnation.

        Like the real kernel, the new PFC reports its mode at once (Mode-Changed-EV).
        """
        old = self.pfc
        self.pfc = FakePfc(self.net.endpoint("PFC"), old.timing, on_ground=old.on_ground)
        self.pfc.position, self.pfc.heading = old.position, old.heading
        self.pfc.transport.send(
            WireEvent(
                _event_id("Mode-Changed-EV"),
                "Mode-Changed-EV",
                encode_values((float(self.pfc.mode),)),
                "PFC",
                "DRC",
            )
        )

    def restart_ppc(self) -> None:
        """The PPC process dies and starts again: nothing pending, a new incarnation."""
        self.ppc = FakePpc(self.net.endpoint("PPC"))

    def restart_server(self, id_start: int, journal: CommandJournal | None = None) -> None:
        """The Platform Server dies and starts again with empty state and ids from ``id_start``.

        ``journal``: the file of open commands the launcher keeps for it, if any.
        """
        from hdrc3_platform_server.server import PlatformServerCore

        self.core = PlatformServerCore(
            self.frame, self.net.endpoint("DRC"), self.log, id_start=id_start, journal=journal
        )

    def run_until_final(self, command_id: int, limit: float = 30.0) -> CompletionEvent | None:
        """Advance until ``command_id`` has its terminal event (or ``limit`` seconds pass)."""
        end = self.t + limit
        while self.log.final(command_id) is None and self.t < end:
            self.run(self.TICK)
        return self.log.final(command_id)
