"""The PFC kernel flying the simulated RMAX in-process (lockstep, sim time, no ROS)."""

from __future__ import annotations

import math
import struct
from collections.abc import Callable

import pytest

from hdrc3_control.event_codec import decode, encode
from hdrc3_control.event_protocol import FINAL
from hdrc3_control.kernel import PfcKernel, UiCommand
from hdrc3_control.kernel_harness import KernelFlight
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.pfc_state import POWER_DRC, SENSOR_POWER, Failsafe, FlightMode, PowerReading
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.transport import LoopbackNetwork, LoopbackTransport
from sim.sensors.fault import FaultMode

Vec3 = tuple[float, float, float]

FIGURE_14 = ["A.1", "B.1", "A.2", "A.3", "B.2", "B.7", "B.8", "A.4", "A.5"]


def hovering(f: KernelFlight) -> bool:
    return f.kernel.machine_state("Mode-Switch") == "Hovering-ST"


def speed(f: KernelFlight) -> float:
    return math.hypot(*f.sim.truth(f.agent).velocity_enu)


def airborne_flight() -> KernelFlight:
    """Engine on, autonomous, take-off to 10 m, hovering (about 1.5 s of wall time)."""
    f = KernelFlight()
    f.engine_on(autonomous=True)
    assert f.run_until(lambda: f.kernel.mode is FlightMode.GROUND_IDLE, 5)
    f.run(12)  # rotor spin-up on the skids
    cid = f.send("FCL-Takeoff-EV")
    assert f.run_until(lambda: f.finished(cid) and hovering(f), 60)
    assert f.answers(cid) == [("Cmd-Accepted-EV", ""), ("Cmd-Finished-EV", "")]
    return f


def first_segment(length: float) -> tuple[KernelFlight, Vec3, Vec3, int]:
    """Airborne, flying a straight segment ``length`` m east at 5 m/s that asked for the next.

    Returns the flight, the segment's start and end, and its command id.
    """
    f = airborne_flight()
    state = f.kernel.state
    assert state is not None
    p = state.position
    mid = (p[0] + length, p[1], p[2])
    c1 = f.send_segment(PathSegment.straight(p, mid, 5.0, 5.0))
    assert f.run_until(lambda: f.reply("Request-Segment-EV", c1) is not None, 5)
    return f, p, mid, c1


def test_figure_14_manual_takeoff_auto_switch_braking_hover() -> None:
    f = KernelFlight()
    f.engine_on(autonomous=False)
    f.run(12)
    assert f.kernel.mode is FlightMode.MANUAL
    f.sticks(throttle=0.62)
    assert f.run_until(lambda: f.sim.truth(f.agent).height_above_ground > 6.0, 30)
    f.sticks(throttle=0.55, pitch=0.3)  # the pilot leaves it moving forward
    f.run(2)
    assert speed(f) > 3.0
    mark = len(f.trace.records())
    f.set_mode(True)
    assert f.run_until(lambda: f.reply("Hover-Stable-EV") is not None, 40)
    fired = [t.tid for r in f.trace.records()[mark:] for t in r.transitions if t.tid[0] in "AB"]
    assert fired[: len(FIGURE_14)] == FIGURE_14
    assert speed(f) < 1.0 and not f.sim.truth(f.agent).on_ground
    assert f.kernel.mode is FlightMode.HOVER


def test_takeoff_hover_path_land() -> None:
    f = airborne_flight()
    x, y, z = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (x + 30.0, y + 20.0, z + 5.0, 6.0))
    assert f.run_until(lambda: f.finished(cid), 40)
    assert f.answers(cid) == [("Cmd-Accepted-EV", ""), ("Traj-Arrived-EV", "")]
    assert math.dist(f.sim.truth(f.agent).position_enu, (x + 30, y + 20, z + 5)) < 3.5
    assert f.run_until(lambda: hovering(f), 20)
    lid = f.send("FCL-Land-EV", (math.pi / 2,))
    touchdown: list[float] = []

    def landed() -> bool:
        truth = f.sim.truth(f.agent)
        if truth.on_ground and not touchdown:
            touchdown.append(truth.velocity_enu[2])
        return f.finished(lid)

    assert f.run_until(landed, 90)
    landed_on = "landed on GPS and barometer: no vision fix of pad L1; heading 90 deg as commanded"
    (accepted, finished) = f.answers(lid)
    plans_on = "landing on GPS and barometer: no vision fix of pad L1"  # said at once
    assert accepted[0] == "Cmd-Accepted-EV" and accepted[1].startswith(plans_on), accepted
    assert finished[0] == "Cmd-Finished-EV" and finished[1].startswith(landed_on), finished
    assert "estimated wind" in finished[1]  # calm air: under LandingConfig.calm_wind
    assert f.run_until(lambda: f.kernel.mode is FlightMode.GROUND_IDLE, 5)
    assert f.sim.truth(f.agent).on_ground and -0.5 < touchdown[0] <= 0.0
    assert abs(math.remainder(f.sim.truth(f.agent).heading - math.pi / 2, math.tau)) < 0.15
    assert not f.sim.truth(f.agent).engine_running  # the landing mode shut the engine down


def test_segments_in_sequence_request_and_switch() -> None:
    f, p, mid, c1 = first_segment(25.0)
    end = (mid[0] + 15.0, mid[1] + 15.0, p[2])
    second = PathSegment(mid, end, (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 5.0, 0.0)
    request_delay = f.sim.time
    c2 = f.send_segment(second)
    assert f.run_until(lambda: f.finished(c2), 40)
    assert f.answers(c1) == [
        ("Cmd-Accepted-EV", ""),
        ("Request-Segment-EV", ""),
        ("Cmd-Finished-EV", ""),
    ]
    assert f.answers(c2) == [("Cmd-Accepted-EV", ""), ("Traj-Arrived-EV", "")]
    assert request_delay > 0.0


FIRST_OF_TWO = ["Cmd-Accepted-EV", "Request-Segment-EV", "Cmd-Finished-EV"]


def _drop_gps(f: KernelFlight) -> None:
    f.sim.agents[f.agent].sensors.sensors()["gps"].fault.set(FaultMode.DROP, (0.0,))


def _rc_manual(f: KernelFlight) -> None:
    f.set_mode(False)


def _brake(f: KernelFlight) -> None:
    f.send("Emergency-Brake-EV")


def _cancel(f: KernelFlight) -> None:
    f.send("FCL-Cancel-EV")


@pytest.mark.parametrize(
    ("interrupt", "reply", "reason"),
    [
        (_drop_gps, "Cmd-Failed-EV", "failsafe: GPS lost for 3.0 s"),
        (_rc_manual, "Cmd-Cancelled-EV", "RC switch to manual"),
        (_brake, "Cmd-Cancelled-EV", "emergency brake"),
        (_cancel, "Cmd-Cancelled-EV", "cancelled"),
    ],
)
def test_an_interrupted_path_ends_the_segment_in_flight(
    interrupt: Callable[[KernelFlight], None], reply: str, reason: str
) -> None:
    # The replies the Mode Switch sends "data Command-DO" named the path's first segment, which
    # had long finished: the protocol dropped them and the segment in flight never ended.
    f, p, mid, c1 = first_segment(20.0)
    c2 = f.send_segment(PathSegment.straight(mid, (mid[0] + 80.0, mid[1], p[2]), 5.0, 0.0))
    assert f.run_until(lambda: f.finished(c1), 20)
    assert f.answers(c1)[-1] == ("Cmd-Finished-EV", "")  # the PFCM flies c2 now
    interrupt(f)
    assert f.run_until(lambda: f.finished(c2), 5)
    f.run(1.0)  # nothing more for either segment: exactly one final reply each
    assert [n for n, _ in f.answers(c2)] == ["Cmd-Accepted-EV", reply]
    assert f.answers(c2)[-1][1].startswith(reason), f.answers(c2)
    assert [n for n, _ in f.answers(c1)] == FIRST_OF_TWO


def test_safety_braking_when_the_next_segment_is_withheld() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    seg = PathSegment.straight(p, (p[0], p[1] + 40.0, p[2]), 6.0, 6.0)
    cid = f.send_segment(seg)
    assert f.run_until(lambda: f.finished(cid), 40)
    (name, reason) = f.answers(cid)[-1]
    assert name == "Cmd-Failed-EV" and reason.startswith("safety braking")
    assert f.run_until(lambda: hovering(f), 30)
    north = f.sim.truth(f.agent).position_enu[1]
    assert north < seg.end[1]  # stopped before the end of the segment
    assert speed(f) < 1.0


def test_emergency_brake_mid_path() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send_segment(PathSegment.straight(p, (p[0] - 80.0, p[1], p[2]), 8.0, 0.0))
    assert f.run_until(lambda: speed(f) > 6.0, 30)
    bid = f.send("Emergency-Brake-EV")
    assert f.run_until(lambda: f.finished(bid), 30)
    assert f.answers(cid)[-1] == ("Cmd-Cancelled-EV", "emergency brake")
    assert f.answers(bid) == [("Cmd-Accepted-EV", ""), ("Cmd-Finished-EV", "")]
    assert speed(f) < 1.0 and hovering(f)


@pytest.mark.parametrize(
    ("event", "values", "reason"),
    [
        ("FCL-Takeoff-EV", (), "Hovering-ST"),
        ("FCL-Track-EV", (), "no colour track"),
        ("Traj3D-EV", (0.0,) * 12 + (5.0, 0.0), "Hovering-ST"),  # degenerate: refused by init
    ],
)
def test_requests_in_the_wrong_state_are_refused_with_a_reason(
    event: str, values: tuple[float, ...], reason: str
) -> None:
    f = airborne_flight()
    if event == "Traj3D-EV":
        far = PathSegment.straight((500.0, 500.0, 30.0), (520.0, 500.0, 30.0), 5.0)
        cid = f.send_segment(far)
        reason = "segment starts"
    else:
        cid = f.send(event, values)
    assert f.run_until(lambda: f.finished(cid), 5)
    name, text = f.answers(cid)[-1]
    assert name == "Cmd-Rejected-EV" and reason in text
    assert f.run_until(lambda: hovering(f), 10)


@pytest.mark.parametrize(
    ("engine", "event", "reason"),
    [
        (False, "FCL-Takeoff-EV", "engine is not running"),
        (True, "FCL-Land-EV", "Ground-Idle-ST"),
        (True, "Traj3D-Flyto-EV", "Ground-Idle-ST"),
    ],
)
def test_on_the_ground_only_takeoff_with_the_engine_running(
    engine: bool, event: str, reason: str
) -> None:
    f = KernelFlight()
    f.engine_on(autonomous=True)
    if not engine:
        f.aircraft.rc.set_engine(False)
    assert f.run_until(lambda: f.kernel.mode is FlightMode.GROUND_IDLE, 5)
    cid = f.send(event, (1.0,) * {"FCL-Takeoff-EV": 0, "FCL-Land-EV": 1}.get(event, 4))
    assert f.run_until(lambda: f.finished(cid), 2)
    assert f.answers(cid)[-1][0] == "Cmd-Rejected-EV" and reason in f.answers(cid)[-1][1]


def test_takeoff_without_enough_lift_fails_and_stays_on_the_ground() -> None:
    f = KernelFlight(payload=60.0)
    f.engine_on(autonomous=True)
    f.run(12)
    cid = f.send("FCL-Takeoff-EV")
    assert f.run_until(lambda: f.finished(cid), 30)
    name, reason = f.answers(cid)[-1]
    assert name == "Cmd-Failed-EV" and "need" in reason
    assert f.run_until(lambda: f.kernel.mode is FlightMode.GROUND_IDLE, 10)
    assert f.sim.truth(f.agent).on_ground


def test_gps_loss_brakes_then_lands_when_the_solution_is_lost() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 60.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    f.sim.agents[f.agent].sensors.sensors()["gps"].fault.set(FaultMode.DROP, (0.0,))
    assert f.run_until(lambda: f.finished(cid), 5)
    name, reason = f.answers(cid)[-1]
    assert name == "Cmd-Failed-EV" and "GPS lost" in reason
    faults = [e.data.decode() for e in f.replies if e.name == "PFC-Fault-EV"]
    assert any("degraded" in text for text in faults)
    assert f.run_until(lambda: f.kernel.mode is FlightMode.BRAKING, 1)
    assert f.run_until(lambda: speed(f) < 1.5, 10)
    assert f.kernel.mode in (FlightMode.BRAKING, FlightMode.HOVER)
    assert f.run_until(lambda: f.kernel.mode is FlightMode.LAND, 15)
    assert any("lost" in e.data.decode() for e in f.replies if e.name == "PFC-Fault-EV")


def test_a_short_gps_dropout_is_ridden_through_on_dead_reckoning() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 60.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    gps = f.sim.agents[f.agent].sensors.sensors()["gps"]
    gps.fault.set(FaultMode.DROP, (0.0,))
    f.run(2.0)  # shorter than KernelConfig.gps_loss_tolerance
    gps.fault.clear()
    assert f.run_until(lambda: f.finished(cid), 40)
    assert f.answers(cid)[-1] == ("Traj-Arrived-EV", "")


def test_frozen_imu_ends_in_a_landing() -> None:
    f = airborne_flight()
    f.sim.agents[f.agent].sensors.sensors()["imu"].fault.set(FaultMode.FREEZE, (0.0,))
    assert f.run_until(lambda: f.kernel.mode is FlightMode.LAND, 5)
    assert any("lost" in e.data.decode() for e in f.replies if e.name == "PFC-Fault-EV")


@pytest.mark.parametrize("lost_ticks", [0, 12, 24])
def test_a_simulator_resumed_from_its_checkpoint_is_a_pause_not_a_sensor_loss(
    lost_ticks: int,
) -> None:
    # world_sim killed ``lost_ticks`` after its last checkpoint: the restarted one resumes the
    # checkpoint one period (25 ticks) after it, the clock jumps by 25 - lost_ticks ticks
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 60.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    checkpoint = f.checkpoint()
    f.run(lost_ticks * 0.02)
    f.resume(checkpoint)
    assert f.run_until(lambda: f.finished(cid), 40)
    assert f.answers(cid)[-1] == ("Traj-Arrived-EV", "")
    assert f.kernel.failsafe is Failsafe.NONE
    assert f.kernel.pauses == (1 if 25 - lost_ticks > 5 else 0)
    assert not [e for e in f.replies if e.name == "PFC-Fault-EV"]


@pytest.mark.parametrize("warm", [True, False])
def test_a_kernel_restarted_in_the_air_hovers_and_a_warm_start_keeps_its_height(
    warm: bool,
) -> None:
    f = airborne_flight()
    f.run(5)
    record = f.kernel.warm_start_record()
    assert record is not None and record.time == pytest.approx(f.sim.time, abs=0.03)
    f.kernel = PfcKernel(
        None,
        terrain=f.world.terrain.height,
        transport=f.network.endpoint("PFC"),
        start_time=f.sim.time,
        warm_start=record if warm else None,
    )
    assert f.run_until(lambda: hovering(f), 30)
    f.run(5)
    assert speed(f) < 1.0 and not f.sim.truth(f.agent).on_ground
    assert f.kernel.warm_start_note.startswith("warm start" if warm else "cold start")
    if warm:  # the barometer's reference of the first run: within a metre of the truth
        error = f.kernel.state.position[2] - f.sim.truth(f.agent).position_enu[2]  # type: ignore[union-attr]
        assert abs(error) < 1.0


def test_a_drifting_barometer_is_announced_excluded_and_the_flyto_goes_on() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 150.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    baro = f.sim.agents[f.agent].sensors.sensors()["barometer"].fault
    start = f.sim.time
    for _ in range(round(40 / 0.02)):  # 0.2 m/s of drift for 30 s (6 m), as bench/faults.py
        baro.set(FaultMode.BIAS, (0.2 * min(30.0, f.sim.time - start),))
        f.tick()
    assert f.run_until(lambda: f.finished(cid), 30)
    assert f.answers(cid)[-1] == ("Traj-Arrived-EV", "")
    texts = [e.data.decode() for e in f.replies if e.name == "PFC-Fault-EV"]
    assert len(texts) == 1 and texts[0].startswith("navigation degraded: barometer drifting")
    error = f.kernel.state.position[2] - f.sim.truth(f.agent).position_enu[2]  # type: ignore[union-attr]
    assert abs(error) < 2.5  # carried by GPS velocity; 6 m had it followed the barometer
    assert f.kernel.failsafe is Failsafe.NONE


def test_rc_switch_to_manual_cancels_the_command() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 40.0, p[1], p[2], 5.0))
    assert f.run_until(lambda: speed(f) > 2.0, 20)
    f.set_mode(False)
    assert f.run_until(lambda: f.finished(cid), 2)
    assert f.answers(cid)[-1] == (
        "Cmd-Cancelled-EV",
        "RC switch to manual: the safety pilot has the aircraft",
    )
    assert f.kernel.mode is FlightMode.MANUAL


@pytest.mark.parametrize(("arm", "braked"), [(True, True), (False, False)])
def test_ui_brake_needs_the_arm_key(arm: bool, braked: bool) -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 60.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    if arm:
        f.kernel.post_ui(UiCommand.ARM)
        f.tick()
    f.kernel.post_ui(UiCommand.BRAKE)
    f.run(1.0)
    cancelled = f.answers(cid)[-1] == ("Cmd-Cancelled-EV", "emergency brake")
    assert cancelled is braked


FIGURE_23 = ["A.6", "B.11", "B.10", "C.1", "B.3", "B.7", "B.8", "C.2"]
FIGURE_23_END = ["C.3", "B.11", "B.10", "C.4", "A.7", "B.2", "B.7", "B.8", "A.4", "A.5"]


def test_figure_23_single_segment_event_order() -> None:
    f = airborne_flight()
    mark = len(f.trace.records())
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send_segment(PathSegment.straight(p, (p[0] + 20.0, p[1], p[2]), 4.0, 0.0))
    assert f.run_until(lambda: f.finished(cid) and hovering(f), 40)
    fired = [t.tid for r in f.trace.records()[mark:] for t in r.transitions if t.tid[0] in "ABC"]
    assert fired[: len(FIGURE_23)] == FIGURE_23
    assert fired[-len(FIGURE_23_END) :] == FIGURE_23_END


def bare_kernel() -> tuple[PfcKernel, LoopbackTransport]:
    """A kernel fed by hand (no aircraft): boot-time automata only."""
    net = LoopbackNetwork()
    drc = net.endpoint("DRC")
    kernel = PfcKernel(terrain=lambda e, n: 0.0, transport=net.endpoint("PFC"))
    return kernel, drc


@pytest.mark.parametrize(
    ("status", "requested"),
    [(0, [POWER_DRC]), (POWER_DRC, [SENSOR_POWER]), (POWER_DRC | SENSOR_POWER, [])],
)
def test_power_switch_and_root_request_missing_power(status: int, requested: list[int]) -> None:
    kernel, _ = bare_kernel()
    asked: list[int] = []
    for k in range(20):
        kernel.feed_power(PowerReading(k * 0.02, status))
        asked += [r.devices for r in kernel.tick(k * 0.02).power_requests]
    assert asked == requested


def test_commands_before_initialisation_are_refused_naming_the_state() -> None:
    kernel, drc = bare_kernel()
    drc.send(WireEvent(2001, "FCL-Takeoff-EV", encode(42), "DRC", "PFC"))
    sent = [e for k in range(3) for e in kernel.tick(k * 0.02).sent]
    [reply] = [e for e in sent if e.name == "Cmd-Rejected-EV"]
    decoded = decode(reply.data, 0, with_reason=True)
    assert decoded.command_id == 42 and "Root:Boot-ST" in decoded.reason


def test_sync_sends_time_and_ground_reference() -> None:
    f = KernelFlight()
    f.run(0.5)
    [sync, *_] = [e for e in f.replies if e.name == "Sync-EV"]
    t, east, north, _ = struct.unpack("<4d", sync.data)
    pad = f.sim.truth(f.agent).position_enu
    assert 0.0 < t < 0.5 and math.dist((east, north), pad[:2]) < 5.0


def test_yaw_then_climb() -> None:
    f = airborne_flight()
    yid = f.send("FCL-Yaw-EV", (math.pi / 2,))
    assert f.run_until(lambda: f.finished(yid), 20)
    assert f.answers(yid) == [("Cmd-Accepted-EV", ""), ("Cmd-Finished-EV", "")]
    heading = f.kernel.state.heading  # type: ignore[union-attr]
    assert abs(math.remainder(heading - math.pi / 2, math.tau)) <= math.radians(5.0)
    # the attitude sensor's heading error comes on top (sim/sensors/attitude.py)
    assert abs(math.remainder(f.sim.truth(f.agent).heading - math.pi / 2, math.tau)) < 0.2
    z = f.kernel.state.position[2]  # type: ignore[union-attr]
    cid = f.send("FCL-Climb-EV", (z + 8.0,))
    assert f.run_until(lambda: f.finished(cid), 30)
    assert f.answers(cid) == [("Cmd-Accepted-EV", ""), ("Cmd-Finished-EV", "")]
    assert f.run_until(lambda: hovering(f), 30)
    assert abs(f.kernel.state.position[2] - (z + 8.0)) < 1.0  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("offset", "reason"),
    [((5.0, 0.0, 0.0), "does not start where"), ((0.0, 0.0, 0.0), "")],
)
def test_next_segment_must_continue_the_path(
    offset: tuple[float, float, float], reason: str
) -> None:
    f, _, mid, _ = first_segment(30.0)
    start = (mid[0] + offset[0], mid[1] + offset[1], mid[2] + offset[2])
    c2 = f.send_segment(PathSegment.straight(start, (start[0] + 10.0, start[1], start[2]), 4.0))
    assert f.run_until(lambda: bool(f.answers(c2)), 2)
    name, text = f.answers(c2)[0]
    if reason:
        assert name == "Cmd-Rejected-EV" and reason in text
    else:
        assert name == "Cmd-Accepted-EV"


@pytest.mark.parametrize(
    ("offset", "replaced"),
    [((0.0, 0.0, 0.0), True), ((5.0, 0.0, 0.0), False)],
    ids=["continuous: replaced", "discontinuous: refused"],
)
def test_a_queued_segment_is_replaced_before_it_is_flown(
    offset: tuple[float, float, float], replaced: bool
) -> None:
    f, p, mid, c1 = first_segment(30.0)
    second = PathSegment.straight(mid, (mid[0] + 40.0, mid[1], p[2]), 5.0, 0.0)
    c2 = f.send_segment(second)
    assert f.run_until(lambda: f.reply("Cmd-Accepted-EV", c2) is not None, 2)
    start = (mid[0] + offset[0], mid[1] + offset[1], mid[2] + offset[2])
    third = PathSegment(
        start, (start[0] + 15.0, start[1] + 15.0, p[2]), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 5.0
    )
    c3 = f.send_segment(third)
    flown, dropped = (c3, c2) if replaced else (c2, c3)
    assert f.run_until(lambda: f.finished(dropped), 2)
    assert not f.finished(c1)  # decided before the PFCM left the first segment
    assert f.run_until(lambda: f.finished(flown), 40)
    f.run(1.0)  # nothing more for any segment: exactly one final reply each
    assert [n for n, _ in f.answers(c1)] == FIRST_OF_TWO
    assert f.answers(flown) == [("Cmd-Accepted-EV", ""), ("Traj-Arrived-EV", "")]
    if replaced:
        assert f.answers(c2) == [
            ("Cmd-Accepted-EV", ""),
            ("Cmd-Cancelled-EV", f"replaced by segment {c3}"),
        ]
    else:
        [(name, reason)] = f.answers(c3)
        assert name == "Cmd-Rejected-EV" and "does not start where" in reason
    end = (third if replaced else second).end
    # arrival radius 3 m, plus the estimate's error and the payload hook's pull (measured 3.51 m)
    assert math.dist(f.sim.truth(f.agent).position_enu, end) < 4.0


@pytest.mark.parametrize(
    ("event", "values", "answer", "reason"),
    [
        ("FCL-Yaw-EV", (), "Cmd-Failed-EV", "bad heading"),
        ("Traj3D-Flyto-EV", (1.0, 2.0), "Cmd-Rejected-EV", "bad command"),
        ("FCL-Climb-EV", (math.nan,), "Cmd-Rejected-EV", "bad command"),
        ("Traj3D-EV", (1.0,) * 5, "Cmd-Rejected-EV", "bad segment"),
        ("Traj3D-Flyto-EV", (0.0, 0.0, 30.0, -2.0), "Cmd-Rejected-EV", "velocity must be > 0"),
    ],
)
def test_malformed_payloads_get_a_defined_answer(
    event: str, values: tuple[float, ...], answer: str, reason: str
) -> None:
    f = airborne_flight()
    cid = f.send(event, values)
    assert f.run_until(lambda: f.finished(cid), 5)
    name, text = f.answers(cid)[-1]
    assert name == answer and reason in text
    assert f.run_until(lambda: hovering(f), 20)


def test_a_failing_control_function_is_stopped_and_hover_restarted() -> None:
    f = airborne_flight()
    controller = f.kernel.hover.controller
    assert controller is not None
    calls = {"n": 0}
    original = controller.update

    def broken(state: object, dt: float) -> object:
        calls["n"] += 1
        if calls["n"] == 1:
            raise RuntimeError("injected fault")
        return original(state, dt)  # type: ignore[arg-type]

    controller.update = broken  # type: ignore[method-assign]
    f.tick()
    assert f.kernel.functions.current is not None
    assert f.kernel.functions.current.last_error == "RuntimeError('injected fault')"
    assert f.run_until(lambda: f.reply("PFC-Fault-EV") is not None, 2)
    assert f.run_until(lambda: f.kernel.machine_state("Mode-Switch") == "Braking-ST", 2)
    assert f.run_until(lambda: hovering(f), 30) and speed(f) < 1.0


def test_frozen_imu_during_a_flyto_fails_it_once_and_lands_as_announced() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 60.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    f.sim.agents[f.agent].sensors.sensors()["imu"].fault.set(FaultMode.FREEZE, (0.0,))
    assert f.run_until(lambda: f.kernel.failsafe is Failsafe.LAND, 2)
    assert f.kernel.failsafe_reason.startswith("failsafe: emergency landing")
    assert f.run_until(lambda: f.sim.truth(f.agent).on_ground, 80)
    # the ground contact is soft: the descent held its rate on the filter's GPS/baro vertical
    # velocity although the YACS's own climb-rate hold had lost its accelerometer
    assert f.sim.truth(f.agent).velocity_enu[2] > -1.0
    assert f.run_until(lambda: f.kernel.mode is FlightMode.GROUND_IDLE, 10)
    finals = [(n, r) for n, r in f.answers(cid) if n in FINAL]
    assert len(finals) == 1 and finals[0][0] == "Cmd-Failed-EV", f.answers(cid)
    assert "emergency landing" in finals[0][1] and "IMU frozen" in finals[0][1]
    texts = [e.data.decode() for e in f.replies if e.name == "PFC-Fault-EV"]
    assert [t for t in texts if t.startswith("failsafe")] == [
        finals[0][1],
        "failsafe ended: on the ground",
    ]
    assert f.kernel.failsafe is Failsafe.NONE
    assert not f.sim.truth(f.agent).engine_running


def test_gps_back_within_the_dead_reckoning_limit_ends_the_hold_in_hover() -> None:
    f = airborne_flight()
    p = f.kernel.state.position  # type: ignore[union-attr]
    cid = f.send("Traj3D-Flyto-EV", (p[0] + 60.0, p[1], p[2], 6.0))
    assert f.run_until(lambda: speed(f) > 4.0, 20)
    gps = f.sim.agents[f.agent].sensors.sensors()["gps"]
    gps.fault.set(FaultMode.DROP, (0.0,))
    assert f.run_until(lambda: f.kernel.failsafe is Failsafe.HOLD, 5)
    ((name, reason),) = [(n, r) for n, r in f.answers(cid) if n in FINAL]
    assert name == "Cmd-Failed-EV" and reason.startswith("failsafe: GPS lost"), reason
    assert f.kernel.failsafe_reason == reason
    f.run(1.0)
    refused = f.send("Traj3D-Flyto-EV", (p[0], p[1], p[2], 6.0))
    f.run(0.1)
    assert [n for n, _ in f.answers(refused)] == ["Cmd-Rejected-EV"]
    gps.fault.clear()
    assert f.run_until(lambda: f.kernel.failsafe is Failsafe.NONE, 2)
    assert f.run_until(lambda: hovering(f), 30)
    f.run(12)  # past the dead-reckoning limit of the outage: no landing
    assert hovering(f) and not f.sim.truth(f.agent).on_ground
    assert "failsafe ended: GPS back, hovering on GPS" in [
        e.data.decode() for e in f.replies if e.name == "PFC-Fault-EV"
    ]
