"""The whole chain: FCL service -> DRC (platform_server) -> PFC automata (control_kernel) -> sim.

One flight through the FCL services over real DDS, as a TST executor would fly it, with the Platform
Server's client (``PlatformClient``) and the demo mission's path streaming: take-off, a fly-to (a
second command meanwhile answers FCL_BUSY), a path streamed on the PFC's segment requests, a path
whose next segment never comes (safety braking), a GPS outage (dead reckoning) and a landing with
engine shutdown; a queued segment replaced before it is flown (issue 13). Then ``hdrc3 demo
--short`` as a subprocess. Outcomes are read from the stack's outputs (FCL answers, platform events,
the Data Interface); ground truth only for what the stack cannot see (its own position error on dead
reckoning, the engine). Every wait is bounded in wall time; the conditions are in sim time.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from hdrc3_base.stamps import stamp_s

pytestmark = pytest.mark.ros

AGENT = "uav0"
WORLD = "revinge"
CALL_TIMEOUT_S = 10.0
ALTITUDE = 12.0
"""Flight altitude, m up of the world origin (the pads are at -0.85 m): short climbs/descents."""
OUTAGE_HOLD_S = 3.0
"""Sim time hovered on dead reckoning; the PFC declares navigation lost (and lands) after 10 s
without GPS (StateEstimator max_dead_reckoning)."""


class Chain:
    """The test's side of the chain: FCL client, Data Interface and ground-truth readers."""

    def __init__(self, process: Any) -> None:
        from hdrc3_interfaces.msg import HelicopterState, PfcState, TruthState
        from hdrc3_platform_server.client import PlatformClient
        from hdrc3_platform_server.geo_frame import frame_from_world
        from hdrc3_platform_server.node import STATE_QOS

        self.process = process
        self.frame = frame_from_world(WORLD)
        self.client = PlatformClient(process, AGENT)
        self._sim_clients: dict[str, Any] = {}
        self.node: Any = self.client.node  # rclpy is untyped
        self.states: list[Any] = []
        self.truth: list[Any] = []
        self.pfc: list[Any] = []
        self.node.create_subscription(
            HelicopterState, f"/{AGENT}/helicopter_state", self.states.append, STATE_QOS
        )
        self.node.create_subscription(PfcState, f"/{AGENT}/pfc/state", self.pfc.append, STATE_QOS)
        self.node.create_subscription(
            TruthState, f"/{AGENT}/ground_truth/state", self.truth.append, 50
        )

    def wait(self, done: Callable[[], bool], timeout: float, what: str) -> None:
        assert self.process.spin_until(done, timeout), f"not within {timeout} s: {what}"

    def ready_for_takeoff(self) -> None:
        """Wait until the PFC reports autonomous ground idle (its Mode Switch left Start)."""
        self.wait(
            lambda: (
                bool(self.pfc)
                and self.pfc[-1].auto_flag
                and self.pfc[-1].mode == self.pfc[-1].MODE_GROUND_IDLE
            ),
            60.0,
            "the PFC in autonomous ground idle",
        )

    def fcl(self, srv: Any, name: str, **fields: Any) -> Any:
        """Call ``fcl/<name>``; the immediate FclReturn."""
        response = self.client.call(srv, f"fcl/{name}", srv.Request(**fields), CALL_TIMEOUT_S)
        assert response is not None, f"fcl_{name}: no answer within {CALL_TIMEOUT_S} s"
        return response.result

    def final(self, command_id: int, timeout: float) -> Any:
        event = self.client.wait_final(command_id, timeout, lambda _e: None)
        assert event is not None, f"command {command_id}: no terminal event in {timeout} s"
        return event

    def events_of(self, command_id: int) -> list[Any]:
        return [e for e in self.client.events if e.command_id == command_id]

    def _first_at(self, samples: list[Any], stamp: Callable[[Any], float], t: float) -> Any:
        def found() -> Any:
            if not samples or stamp(samples[-1]) < t:  # cheap: checked on every callback
                return None
            return next(m for m in samples if stamp(m) >= t)

        self.wait(lambda: found() is not None, 30.0, f"a sample at or after {t:.2f} s")
        return found()

    def state_at(self, t: float) -> Any:
        """The first Data Interface sample of sim time ``t`` or later (waits for it)."""
        return self._first_at(self.states, lambda m: stamp_s(m.pfc_time), t)

    def truth_at(self, t: float) -> Any:
        """The first ground-truth sample of sim time ``t`` or later (waits for it)."""
        return self._first_at(self.truth, lambda m: stamp_s(m.header.stamp), t)

    def states_between(self, t0: float, t1: float) -> list[Any]:
        self.state_at(t1)
        return [s for s in self.states if t0 <= stamp_s(s.pfc_time) <= t1]

    def enu(self, state: Any) -> tuple[float, float, float]:
        """Data Interface position in the world's local frame."""
        east, north, up = self.frame.to_enu(state.longitude, state.latitude, state.altitude)
        return (east, north, up)

    def sim_client(self, srv: Any, name: str) -> Any:
        """A client of a simulator service, matched (made once per name)."""
        if name not in self._sim_clients:
            self._sim_clients[name] = self.node.create_client(srv, name)
        client = self._sim_clients[name]
        self.wait(client.service_is_ready, CALL_TIMEOUT_S, f"service {name}")
        return client

    def call_sim(self, srv: Any, name: str, **fields: Any) -> Any:
        client = self.sim_client(srv, name)
        future: Any = client.call_async(srv.Request(**fields))
        self.wait(future.done, CALL_TIMEOUT_S, f"answer of {name}")
        return future.result().result


def horizontal_speed(state: Any) -> float:
    return math.hypot(state.velocity_north, state.velocity_east)


@pytest.fixture
def chain(hdrc3_cli: Callable[..., Any], ros_domain: int) -> Iterator[Chain]:
    """world_sim, control_kernel and platform_server of one agent in lockstep, at full speed."""
    from hdrc3_base.ros_runtime import RosProcess

    launch = hdrc3_cli(
        "launch",
        "--agents",
        AGENT,
        "--world",
        WORLD,
        "--nodes",
        "world_sim,control_kernel,platform_server",
        "--speed",
        "max",
    )
    launch.wait_for_line("READY", timeout=90)
    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        rig = Chain(process)
        try:
            rig.wait(lambda: len(rig.states) > 0, 60.0, "the Data Interface")
            yield rig
        finally:
            rig.node.destroy_node()
            launch.interrupt()
            print("\n".join(launch.lines[-40:]))  # shown by pytest when the test failed


@pytest.mark.slow
def test_fcl_flight_through_the_whole_chain(chain: Chain) -> None:
    from hdrc3.demo_mission import SurveyMission
    from hdrc3.safety_pilot import Switch, set_rc
    from hdrc3.survey import SurveyArea, lawn_mower
    from hdrc3_control.path_segment import PathSegment
    from hdrc3_interfaces.msg import FclReturn, SimResult
    from hdrc3_interfaces.srv import (
        FclLand,
        FclTakeoff,
        FclTraj3d,
        FclTraj3dFlyto,
        SimInjectFault,
        SimPause,
    )
    from hdrc3_navigation.messages import segment_to_msg
    from hdrc3_platform_server.codes import EventKind

    c = chain
    # the safety pilot starts the engine and hands over; the Data Interface shows autonomy
    code, reason = set_rc(c.process, c.node, AGENT, Switch.AUTONOMOUS, Switch.ON, CALL_TIMEOUT_S)
    assert code == SimResult.OK, reason
    c.wait(lambda: c.states[-1].auto_flag, 60.0, "auto_flag in the Data Interface")
    c.ready_for_takeoff()

    # take-off: accepted at once, finished airborne
    takeoff = c.fcl(FclTakeoff, "takeoff")
    assert takeoff.code == FclReturn.FCL_OK, takeoff.reason
    done = c.final(takeoff.command_id, 120.0)
    assert (done.command, done.kind) == ("fcl_takeoff", EventKind.FINISHED), done
    airborne = c.state_at(done.time)
    pad = c.enu(airborne)
    assert not airborne.on_ground_flag and airborne.auto_flag
    assert pad[2] - c.frame.ground_up(pad[0], pad[1]) > 5.0, pad

    # fly-to; a second command meanwhile is answered FCL_BUSY naming the running one
    target = (pad[0] + 30.0, pad[1] + 60.0, ALTITUDE)
    lon, lat, alt = c.frame.to_wgs84(*target)
    where = {"longitude": lon, "latitude": lat, "altitude": alt, "velocity": 8.0}
    flyto = c.fcl(FclTraj3dFlyto, "traj3d_flyto", **where)
    assert flyto.code == FclReturn.FCL_OK, flyto.reason
    busy = c.fcl(FclTraj3dFlyto, "traj3d_flyto", **where)
    assert busy.code == FclReturn.FCL_BUSY and busy.command_id == 0
    assert f"fcl_traj3d_flyto (command {flyto.command_id})" in busy.reason, busy.reason
    done = c.final(flyto.command_id, 120.0)
    assert done.kind is EventKind.FINISHED, done
    arrived = c.enu(c.state_at(done.time))
    assert math.dist(arrived, target) <= 3.0, arrived
    assert not c.events_of(busy.command_id), "a refused command got events"

    # a path streamed on the PFC's segment requests (the demo mission's streaming)
    area = SurveyArea(target[0], target[1], 50.0, 20.0, legs=2, altitude=ALTITUDE, heading=0.0)
    path = lawn_mower(area, leg_speed=6.0, turn_speed=3.0)
    mission = SurveyMission(c.client, c.frame, path)
    last = mission.stream(path)
    assert last.outcome == "FINISHED" and len(mission.segment_ids) == len(path) == 3
    for cid in mission.segment_ids[:-1]:
        events = c.events_of(cid)
        assert EventKind.SEGMENT_REQUEST in [e.kind for e in events], events
        assert (events[-1].kind, events[-1].reason) == (EventKind.FINISHED, "segment flown")
    end = c.state_at(c.final(mission.segment_ids[-1], 1.0).time)
    assert math.dist(c.enu(end), path[-1].end) <= 3.0, c.enu(end)

    # a path whose next segment is withheld: safety braking fails it, the aircraft hovers
    p = c.enu(end)
    goal = (p[0], p[1] + 40.0, ALTITUDE)
    seg = PathSegment.straight(p, goal, 6.0, 6.0)
    sent = c.fcl(FclTraj3d, "traj3d", segment=segment_to_msg(seg), velocity=6.0, end_velocity=6.0)
    assert sent.code == FclReturn.FCL_OK, sent.reason
    failed = c.final(sent.command_id, 120.0)
    kinds = [e.kind for e in c.events_of(sent.command_id) if e.kind is not EventKind.INFO]
    assert kinds == [EventKind.SEGMENT_REQUEST, EventKind.FAILED], kinds
    assert failed.kind is EventKind.FAILED and "safety braking" in failed.reason, failed
    c.wait(
        lambda: (
            stamp_s(c.states[-1].pfc_time) > failed.time
            and horizontal_speed(c.states[-1]) < 0.3
            and abs(c.states[-1].velocity_up) < 0.3
        ),
        60.0,
        "hovering after the safety braking",
    )
    hover = c.states[-1]
    braked = c.states_between(stamp_s(end.pfc_time), stamp_s(hover.pfc_time))
    furthest = max(c.enu(s)[1] for s in braked)
    print(f"safety braking: stopped {goal[1] - furthest:.1f} m before the segment's end")
    assert furthest < goal[1], f"flew past the end of the segment: {furthest:.1f} m north"
    assert not hover.on_ground_flag and abs(c.enu(hover)[2] - ALTITUDE) < 2.0

    # GPS outage: reported by the PFC through the DRC; hovering goes on on dead reckoning
    drop, restore = SimInjectFault.Request.MODE_DROP, SimInjectFault.Request.MODE_NONE
    fault = c.call_sim(
        SimInjectFault, "/world_sim/inject_fault", agent=AGENT, sensor="gps", mode=drop
    )
    assert fault.code == SimResult.OK, fault.reason

    def fault_report(text: str) -> Any:
        return next(
            (
                e
                for e in c.client.events
                if e.kind is EventKind.INFO and e.reason.startswith(f"PFC fault: {text}")
            ),
            None,
        )

    c.sim_client(SimPause, "/world_sim/pause")  # matched before the window below opens
    c.wait(lambda: fault_report("navigation degraded") is not None, 30.0, "GPS loss reported")
    lost = fault_report("navigation degraded").time
    held = c.states_between(lost, lost + OUTAGE_HOLD_S)
    assert len(held) > 25 and all(
        not s.on_ground_flag and horizontal_speed(s) < 1.0 for s in held
    ), [(stamp_s(s.pfc_time), horizontal_speed(s)) for s in held]
    # how far it really drifted is what the stack cannot see
    drift = math.dist(c.truth_at(lost).position_enu, c.truth_at(lost + OUTAGE_HOLD_S).position_enu)
    print(f"GPS outage: {drift:.2f} m true drift in {OUTAGE_HOLD_S:g} s on dead reckoning")
    assert drift < 3.0, f"drifted {drift:.2f} m in {OUTAGE_HOLD_S:g} s on dead reckoning"
    # GPS comes back within the PFC's 10 s dead-reckoning window however loaded the machine is:
    # sim time stands still while the restore is sent
    paused = c.call_sim(SimPause, "/world_sim/pause", paused=True)
    assert paused.code == SimResult.OK, paused.reason
    cleared = c.call_sim(
        SimInjectFault, "/world_sim/inject_fault", agent=AGENT, sensor="gps", mode=restore
    )
    assert cleared.code == SimResult.OK, cleared.reason
    resumed = c.call_sim(SimPause, "/world_sim/pause", paused=False)
    assert resumed.code == SimResult.OK, resumed.reason
    c.wait(lambda: fault_report("navigation recovered") is not None, 30.0, "GPS back")

    # landing ends on the ground with the engine shut down
    land = c.fcl(FclLand, "land", heading=0.0)
    assert land.code == FclReturn.FCL_OK, land.reason
    landed = c.final(land.command_id, 180.0)
    assert (landed.command, landed.kind) == ("fcl_land", EventKind.FINISHED), landed
    assert c.state_at(landed.time).on_ground_flag
    assert not c.truth_at(landed.time).engine_running
    refused = c.fcl(FclLand, "land", heading=0.0)
    assert refused.code == FclReturn.FCL_NOT_ACCEPTED and "hovering" in refused.reason


@pytest.mark.slow
def test_short_demo_flies_records_and_reports(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> None:
    import matplotlib.image
    from rclpy.serialization import deserialize_message

    from hdrc3.mcap_recording import RecordingReader
    from hdrc3.message_types import message_class

    out = tmp_path / "demo"
    demo = hdrc3_cli(
        "demo", "--basic", "--short", "--out", str(out), "--domain-id", str(ros_domain)
    )
    code = demo.finish(timeout=280.0)
    text = "\n".join(demo.lines)
    assert code == 0, text
    assert "mission completed" in text

    recording = RecordingReader.open(out / "run.mcap")
    topics = recording.topics()
    state_topic = f"/{AGENT}/helicopter_state"
    assert recording.truncated is False
    state_cls = message_class(topics[state_topic])
    states = [deserialize_message(m.data, state_cls) for m in recording.messages([state_topic])]
    assert len(states) > 1000 and states[-1].on_ground_flag
    assert any(not s.on_ground_flag for s in states)

    image = matplotlib.image.imread(out / "flight.png")  # decodes the whole PNG
    height, width, _ = image.shape
    assert height > 300 and width > 600 and image.std() > 0.01  # a drawing, not a blank page

    outcomes = re.findall(r"^\s+[\d.]+ s\s+(fcl_\w+)\s+(\w+)", text, re.MULTILINE)
    assert outcomes == [
        ("fcl_takeoff", "FINISHED"),
        ("fcl_traj3d_flyto", "FINISHED"),
        ("fcl_traj3d", "FINISHED"),
        ("fcl_traj3d", "FINISHED"),
        ("fcl_traj3d", "FINISHED"),
        ("fcl_land", "FINISHED"),
    ], text
    assert "+ 2 segment requests" in text


# --- faults (issue 21): truthful outcomes and the failsafe policy of the platform server README


def airborne(c: Chain) -> tuple[float, float, float]:
    """Safety pilot hands over, take-off finished; the hover point (ENU)."""
    from hdrc3.safety_pilot import Switch, set_rc
    from hdrc3_interfaces.msg import FclReturn, SimResult
    from hdrc3_interfaces.srv import FclTakeoff
    from hdrc3_platform_server.codes import EventKind

    code, reason = set_rc(c.process, c.node, AGENT, Switch.AUTONOMOUS, Switch.ON, CALL_TIMEOUT_S)
    assert code == SimResult.OK, reason
    c.wait(lambda: c.states[-1].auto_flag, 60.0, "auto_flag in the Data Interface")
    c.ready_for_takeoff()
    takeoff = c.fcl(FclTakeoff, "takeoff")
    assert takeoff.code == FclReturn.FCL_OK, takeoff.reason
    done = c.final(takeoff.command_id, 120.0)
    assert done.kind is EventKind.FINISHED, done
    return c.enu(c.state_at(done.time))


def flyto(c: Chain, target: tuple[float, float, float]) -> int:
    """Start a fly-to at 6 m/s; its command id once the aircraft is under way."""
    from hdrc3_interfaces.msg import FclReturn
    from hdrc3_interfaces.srv import FclTraj3dFlyto

    lon, lat, alt = c.frame.to_wgs84(*target)
    where = {"longitude": lon, "latitude": lat, "altitude": alt, "velocity": 6.0}
    answer = c.fcl(FclTraj3dFlyto, "traj3d_flyto", **where)
    assert answer.code == FclReturn.FCL_OK, answer.reason
    c.wait(lambda: horizontal_speed(c.states[-1]) > 3.0, 60.0, "under way")
    return int(answer.command_id)


def set_fault(c: Chain, sensor: str, mode: int) -> None:
    from hdrc3_interfaces.msg import SimResult
    from hdrc3_interfaces.srv import SimInjectFault

    result = c.call_sim(
        SimInjectFault, "/world_sim/inject_fault", agent=AGENT, sensor=sensor, mode=mode
    )
    assert result.code == SimResult.OK, result.reason


def failsafe_events(c: Chain) -> list[Any]:
    return [e for e in c.client.events if e.command == "pfc_failsafe"]


def terminal_events(c: Chain, command_id: int) -> list[Any]:
    from hdrc3_platform_server.completion import TERMINAL

    return [e for e in c.events_of(command_id) if e.kind in TERMINAL]


@pytest.mark.slow
def test_imu_freeze_fails_the_flyto_and_lands_as_announced(chain: Chain) -> None:
    from hdrc3_interfaces.msg import HelicopterState
    from hdrc3_interfaces.srv import SimInjectFault
    from hdrc3_platform_server.codes import EventKind

    c = chain
    pad = airborne(c)
    cid = flyto(c, (pad[0] + 80.0, pad[1], ALTITUDE))
    set_fault(c, "imu", SimInjectFault.Request.MODE_FREEZE)
    failed = c.final(cid, 30.0)
    assert failed.kind is EventKind.FAILED, failed
    assert failed.reason.startswith("failsafe: emergency landing"), failed.reason
    assert "IMU frozen" in failed.reason, failed.reason
    c.wait(lambda: len(failsafe_events(c)) >= 1, 30.0, "the emergency landing announced")
    assert failsafe_events(c)[0].reason == failed.reason
    assert failsafe_events(c)[0].command_id == 0
    c.wait(
        lambda: c.states[-1].failsafe == HelicopterState.FAILSAFE_LAND, 30.0, "failsafe in the DI"
    )
    assert c.states[-1].failsafe_reason == failed.reason
    c.wait(  # the descent without IMU is slow (0.25 m/s from 10 m, about 50 s of sim time)
        lambda: len(failsafe_events(c)) >= 2 and c.states[-1].on_ground_flag,
        240.0,
        "landed, failsafe ended",
    )
    assert failsafe_events(c)[1].reason == "failsafe ended: on the ground"
    ended = failsafe_events(c)[1].time
    down = c.state_at(ended + 0.5)
    assert down.on_ground_flag and down.failsafe == HelicopterState.FAILSAFE_NONE
    assert [e.kind for e in terminal_events(c, cid)] == [EventKind.FAILED]
    # how hard it touched down is measured by bench/faults.py (imu_freeze) from ground truth


@pytest.mark.slow
def test_gps_loss_holds_and_hovers_when_back(chain: Chain) -> None:
    from hdrc3_interfaces.msg import HelicopterState
    from hdrc3_interfaces.srv import SimInjectFault
    from hdrc3_platform_server.codes import EventKind

    c = chain
    drop, restore = SimInjectFault.Request.MODE_DROP, SimInjectFault.Request.MODE_NONE
    pad = airborne(c)

    # A dropout shorter than the 3 s tolerance is ridden through: that is tested on the kernel
    # harness in sim time (test_kernel.py), since here the outage's length in sim time would be
    # the wall-clock latency of two service calls at --speed max (once over 3 s at load 12).
    # GPS lost for longer: the fly-to fails with the failsafe's reason, brake + hover (HOLD)
    cid = flyto(c, (pad[0] + 60.0, pad[1], ALTITUDE))
    set_fault(c, "gps", drop)
    failed = c.final(cid, 60.0)
    assert failed.kind is EventKind.FAILED, failed
    assert failed.reason.startswith("failsafe: GPS lost"), failed.reason
    c.wait(lambda: len(failsafe_events(c)) == 1, 30.0, "the hold announced")
    hold = failsafe_events(c)[0]
    assert hold.reason == failed.reason and hold.command_id == 0
    held = c.state_at(hold.time + 1.0)
    assert held.failsafe == HelicopterState.FAILSAFE_HOLD and not held.on_ground_flag
    assert held.failsafe_reason == hold.reason

    # GPS back before the dead-reckoning limit (10 s): the failsafe ends, the aircraft hovers
    set_fault(c, "gps", restore)
    c.wait(lambda: len(failsafe_events(c)) == 2, 30.0, "the end of the hold announced")
    back = failsafe_events(c)[1]
    assert back.reason == "failsafe ended: GPS back, hovering on GPS", back.reason
    c.wait(
        lambda: (
            stamp_s(c.states[-1].pfc_time) > back.time
            and horizontal_speed(c.states[-1]) < 0.5
            and abs(c.states[-1].velocity_up) < 0.5
        ),
        60.0,
        "hovering after the hold",
    )
    still = stamp_s(c.states[-1].pfc_time)
    after = c.states_between(still, still + 12.0)  # past the dead-reckoning limit
    assert after and all(
        not s.on_ground_flag and s.failsafe == HelicopterState.FAILSAFE_NONE for s in after
    )
    assert horizontal_speed(after[-1]) < 1.0 and abs(c.enu(after[-1])[2] - ALTITUDE) < 2.0
    assert len(failsafe_events(c)) == 2  # no emergency landing after all
    assert [e.kind for e in terminal_events(c, cid)] == [EventKind.FAILED]


# --- path execution (issue 13): a queued segment replaced before the PFC flies it


@pytest.mark.slow
def test_a_queued_segment_is_replaced_before_it_is_flown(chain: Chain) -> None:
    from hdrc3_control.path_segment import PathSegment
    from hdrc3_interfaces.msg import FclReturn
    from hdrc3_interfaces.srv import FclTraj3d
    from hdrc3_navigation.messages import segment_to_msg
    from hdrc3_platform_server.codes import EventKind

    c = chain
    pad = airborne(c)
    start = (pad[0], pad[1], ALTITUDE)
    mid = (pad[0] + 60.0, pad[1], ALTITUDE)
    first = PathSegment.straight(start, mid, 6.0, 6.0)
    second = PathSegment.straight(mid, (mid[0] + 40.0, mid[1], ALTITUDE), 6.0, 0.0)
    third = PathSegment(  # a gentle left turn instead of going on east
        mid, (mid[0] + 30.0, mid[1] + 30.0, ALTITUDE), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 6.0, 0.0
    )

    def send(seg: PathSegment) -> int:
        answer = c.fcl(
            FclTraj3d,
            "traj3d",
            segment=segment_to_msg(seg),
            velocity=seg.target_velocity,
            end_velocity=seg.end_velocity,
        )
        assert answer.code == FclReturn.FCL_OK, answer.reason
        return int(answer.command_id)

    def requested(cid: int) -> bool:
        return any(e.kind is EventKind.SEGMENT_REQUEST for e in c.events_of(cid))

    c1 = send(first)
    c.wait(lambda: requested(c1), 30.0, "the request for the second segment")
    sent_at = stamp_s(c.states[-1].pfc_time)
    c2 = send(second)
    c3 = send(third)  # 60 m at 6 m/s: the PFCM is still on the first segment
    replaced = c.final(c2, 30.0)
    assert (replaced.kind, replaced.reason) == (EventKind.CANCELLED, f"replaced by segment {c3}")
    done = c.final(c3, 120.0)
    assert done.kind is EventKind.FINISHED, done
    c.state_at(done.time + 2.0)  # later events would have come by now: one terminal event each
    assert [e.kind for e in terminal_events(c, c1)] == [EventKind.FINISHED]
    assert [e.kind for e in terminal_events(c, c2)] == [EventKind.CANCELLED]
    assert [e.kind for e in terminal_events(c, c3)] == [EventKind.FINISHED]
    assert not requested(c2)  # the PFCM never flew it
    end = c.enu(c.state_at(done.time))
    print(
        f"replacement flown: {math.dist(end, third.end):.1f} m from its end, "
        f"{done.time - sent_at:.1f} s of sim time after it was sent"
    )
    assert math.dist(end, third.end) <= 3.0, end
    assert math.dist(end, second.end) > 30.0
    assert done.time - sent_at < 40.0  # 60 m + 47 m at 6 m/s: about 20 s
