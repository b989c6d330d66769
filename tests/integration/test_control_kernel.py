"""world_sim + control_kernel as processes, in lockstep over real DDS; the test acts as the DRC.

The test sends the DRC's events through the HCSM ROS transport, flips the safety pilot's RC
switches through world_sim's ``rc/set`` service and reads the PFC's replies, its ``pfc/state``
and its HCSM trace. Every wait is bounded in wall time; the conditions are in sim time.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from hdrc3_control.event_codec import command_id_of, decode, encode
from hdrc3_control.kernel_harness import event_id, segment_payload
from hdrc3_control.path_segment import PathSegment
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.trace import TraceRecord
from tests.integration.ros_wait import answer

pytestmark = pytest.mark.ros

AGENT = "uav0"
FIGURE_14 = ["A.1", "B.1", "A.2", "A.3", "B.2", "B.7", "B.8", "A.4", "A.5"]
FINAL = (
    "Cmd-Finished-EV",
    "Cmd-Failed-EV",
    "Cmd-Rejected-EV",
    "Cmd-Cancelled-EV",
    "Traj-Arrived-EV",
)


class Drc:
    """The test's DRC: HCSM transport, RC client, PfcState/trace/truth subscriptions."""

    def __init__(self, context: Any) -> None:
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node
        from std_msgs.msg import String

        from hdrc3_hcsm.ros_transport import EVENT_QOS, RosTransport
        from hdrc3_interfaces.msg import PfcState, TruthState
        from hdrc3_interfaces.srv import SimSetRc

        self.node: Any = Node("drc_test", namespace=f"/{AGENT}", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.transport = RosTransport(self.node, "DRC")
        self.rc = self.node.create_client(SimSetRc, "rc/set")
        self.rc_type = SimSetRc
        self.states: list[Any] = []
        self.truth: Any = None
        self.track: list[tuple[float, float, float]] = []
        self.trace: list[TraceRecord] = []
        self.replies: list[WireEvent] = []
        self.node.create_subscription(PfcState, "pfc/state", self.states.append, 50)
        self.node.create_subscription(TruthState, "ground_truth/state", self._on_truth, 10)
        self.node.create_subscription(String, "hcsm/trace", self._on_trace, EVENT_QOS)
        self._ids = iter(range(1, 10_000))

    def _on_trace(self, msg: Any) -> None:
        self.trace.append(TraceRecord.from_json(msg.data))

    def _on_truth(self, msg: Any) -> None:
        self.truth = msg
        self.track.append(tuple(msg.position_enu))

    def spin_until(self, done: Callable[[], bool], timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while not done():
            if time.monotonic() > deadline:
                return False
            self.executor.spin_once(timeout_sec=0.05)
            self.replies += self.transport.receive()
        return True

    @property
    def sim_time(self) -> float:
        return self.states[-1].header.stamp.sec + self.states[-1].header.stamp.nanosec * 1e-9

    def wait_sim(self, seconds: float, timeout: float = 60.0) -> None:
        start = self.sim_time
        assert self.spin_until(lambda: self.sim_time >= start + seconds, timeout)

    def set_rc(self, **fields: Any) -> None:
        assert self.rc.wait_for_service(timeout_sec=10.0)
        # stick and switch settings are idempotent: sent again until answered
        response = answer(self.executor, self.rc, self.rc_type.Request(**fields), 10.0)
        assert response is not None, "rc/set did not answer"
        assert response.result.code == 0, response.result.reason

    def send(self, name: str, values: tuple[float, ...] = (), data: bytes | None = None) -> int:
        cid = next(self._ids)
        payload = encode(cid, values) if data is None else data
        self.transport.send(WireEvent(event_id(name), name, payload, "DRC", "PFC"))
        return command_id_of(payload)

    def send_segment(self, seg: PathSegment) -> int:
        cid = next(self._ids)
        return self.send("Traj3D-EV", data=segment_payload(cid, seg))

    def answers(self, cid: int) -> list[tuple[str, str]]:
        return [
            (e.name, decode(e.data, 0, with_reason=True).reason)
            for e in self.replies
            if e.name in (*FINAL, "Cmd-Accepted-EV", "Request-Segment-EV")
            and command_id_of(e.data) == cid
        ]

    def finished(self, cid: int) -> bool:
        return any(name in FINAL for name, _ in self.answers(cid))

    def hovering(self) -> bool:
        return bool(self.states) and self.states[-1].mode_switch_state == "Hovering-ST"

    def speed(self) -> float:
        """The latest true speed, whatever its time (for waits on the truth topic itself)."""
        return 0.0 if self.truth is None else math.hypot(*self.truth.velocity_enu)

    def truth_at(self, sim_time: float, timeout: float = 30.0) -> Any:
        """The ground truth once a sample of ``sim_time`` or later has arrived.

        Ground truth is a topic of its own (world_sim's), unordered against ``pfc/state``, the
        trace and the replies: a test that waited on one of those waits here before reading it.
        """
        assert self.spin_until(
            lambda: self.truth is not None and stamp_ns(self.truth) >= round(sim_time * 1e9),
            timeout,
        ), f"no ground truth at or after {sim_time:.2f} s of sim time"
        return self.truth

    def speed_at(self, sim_time: float) -> float:
        """True speed from a ground-truth sample of ``sim_time`` or later."""
        return math.hypot(*self.truth_at(sim_time).velocity_enu)

    def traced(self, since: int, match: Callable[[TraceRecord], bool]) -> TraceRecord:
        """The first PFC trace record from index ``since`` on that ``match``es (waits for it)."""

        def found() -> TraceRecord | None:
            return next((r for r in self.trace[since:] if match(r)), None)

        assert self.spin_until(lambda: found() is not None, 30.0), "no such trace record"
        record = found()
        assert record is not None
        return record

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()


@pytest.fixture
def drc(hdrc3_cli: Callable[..., Any], ros_context: Any) -> Iterator[Drc]:
    launch = hdrc3_cli(
        "launch", "--agents", AGENT, "--nodes", "world_sim,control_kernel", "--speed", "max"
    )
    launch.wait_for_line("READY", timeout=60)
    rig = Drc(ros_context)
    try:
        assert rig.spin_until(lambda: len(rig.states) > 5, 30), "no pfc/state"
        yield rig
    finally:
        rig.close()
        launch.interrupt(timeout=20)
        print("\n".join(launch.lines[-40:]))  # shown by pytest when the test failed


def stamp_ns(state: Any) -> int:
    return int(state.header.stamp.sec) * 1_000_000_000 + int(state.header.stamp.nanosec)


def test_figure_14_then_safety_braking_and_emergency_brake(drc: Drc) -> None:
    wall0, sim0, start = time.monotonic(), drc.sim_time, drc.states[-1]
    drc.set_rc(engine=1, mode=1)  # engine on, manual
    drc.wait_sim(12.0)  # rotor spin-up
    assert drc.states[-1].mode == drc.states[-1].MODE_MANUAL
    drc.set_rc(set_sticks=True, throttle=0.62)
    assert drc.spin_until(lambda: drc.truth.height_above_ground > 6.0, 60)
    drc.set_rc(set_sticks=True, throttle=0.55, pitch=0.3)
    drc.wait_sim(2.0)
    assert drc.speed_at(drc.sim_time) > 3.0
    mark = len(drc.trace)
    drc.set_rc(mode=2)  # autonomous
    assert drc.spin_until(lambda: any(e.name == "Hover-Stable-EV" for e in drc.replies), 60)

    hovered = drc.traced(mark, lambda r: any(t.tid == "A.5" for t in r.transitions))
    fired = [t.tid for r in drc.trace[mark:] for t in r.transitions if t.tid[0] in "AB"]
    assert fired[: len(FIGURE_14)] == FIGURE_14
    assert drc.speed_at(hovered.time) < 1.0

    # a path whose next segment never comes: safety braking, then hover
    p = tuple(drc.states[-1].position_enu)
    seg = PathSegment.straight(p, (p[0], p[1] + 40.0, p[2]), 6.0, 6.0)
    braking_from, states_from = len(drc.track), len(drc.states)
    trace_from = len(drc.trace)
    cid = drc.send_segment(seg)
    assert drc.spin_until(lambda: len(drc.answers(cid)) >= 2, 30)
    # Measured on the PFC's clock, from its trace: the test process is not part of the lockstep,
    # so sim time it reads races ahead of it on a loaded machine.
    received = drc.traced(trace_from, lambda r: r.event == "Traj3D-EV")
    requested = drc.traced(
        trace_from,
        lambda r: any("SEND Request-Segment-EV" in a for t in r.transitions for a in t.actions),
    )
    latency = requested.time - received.time
    print(f"Request-Segment-EV after {latency * 1000:.0f} ms of PFC sim time")
    assert 0.0 <= latency < 0.2  # chapter section 7: well below 200 ms
    assert drc.spin_until(lambda: drc.finished(cid), 60)
    names = [name for name, _ in drc.answers(cid)]
    assert names == ["Cmd-Accepted-EV", "Request-Segment-EV", "Cmd-Failed-EV"]
    assert drc.answers(cid)[-1][1].startswith("safety braking")
    assert drc.spin_until(drc.hovering, 60)
    # Stopped before the end of the segment in the PFC's navigation frame; the true position
    # differs by the GPS error (a bias of ~2 m that wanders over minutes, sim/sensors/gps.py).
    furthest = max(s.position_enu[1] for s in drc.states[states_from:])
    truth = max(north for _, north, _ in drc.track[braking_from:])
    print(
        f"safety braking: stopped {seg.end[1] - furthest:.2f} m before the end (estimate), "
        f"truth {seg.end[1] - truth:+.2f} m"
    )
    assert furthest < seg.end[1] and drc.speed_at(drc.sim_time) < 1.0

    # emergency brake in the middle of a fast path
    p = tuple(drc.states[-1].position_enu)
    cid = drc.send_segment(PathSegment.straight(p, (p[0] - 80.0, p[1], p[2]), 8.0, 0.0))
    assert drc.spin_until(lambda: drc.speed() > 6.0, 60)
    bid = drc.send("Emergency-Brake-EV")
    assert drc.spin_until(lambda: drc.finished(bid), 60)
    assert drc.answers(cid)[-1] == ("Cmd-Cancelled-EV", "emergency brake")
    assert drc.spin_until(drc.hovering, 10) and drc.speed_at(drc.sim_time) < 1.0

    # a GPS outage from world_sim: reported to the DRC, the PFC keeps hovering on dead reckoning
    from hdrc3_interfaces.srv import SimInjectFault

    fault = drc.node.create_client(SimInjectFault, "/world_sim/inject_fault")
    assert fault.wait_for_service(timeout_sec=10.0)
    request = SimInjectFault.Request(
        agent=AGENT, sensor="gps", mode=SimInjectFault.Request.MODE_DROP
    )
    future = fault.call_async(request)
    assert drc.spin_until(future.done, 10.0) and future.result().result.code == 0

    def fault_reports() -> list[str]:
        return [e.data.decode() for e in drc.replies if e.name == "PFC-Fault-EV"]

    assert drc.spin_until(lambda: any("degraded" in text for text in fault_reports()), 20)
    degraded = drc.states[-1].HEALTH_DEGRADED
    assert drc.spin_until(lambda: drc.states[-1].estimator_health == degraded, 10)
    assert drc.hovering() and drc.speed_at(drc.sim_time) < 1.0

    # lockstep: the PFC answered every 20 ms tick of this flight (its tick counter vs sim time)
    first, last = drc.states[drc.states.index(start)], drc.states[-1]
    ticks = last.ticks - first.ticks
    assert ticks == round((stamp_ns(last) - stamp_ns(first)) / 20_000_000)
    sim_s, wall_s = drc.sim_time - sim0, time.monotonic() - wall0
    print(f"lockstep: {sim_s:.1f} s sim in {wall_s:.1f} s wall ({sim_s / wall_s:.1f}x real time)")
    print(f"steps longer than 20 ms (wall): {drc.states[-1].overruns} of {drc.states[-1].ticks}")


def test_takeoff_flyto_land(drc: Drc) -> None:
    wall0, sim0 = time.monotonic(), drc.sim_time
    drc.set_rc(engine=1, mode=2)
    assert drc.spin_until(lambda: drc.states[-1].mode == drc.states[-1].MODE_GROUND_IDLE, 30)
    drc.wait_sim(12.0)
    tid = drc.send("FCL-Takeoff-EV")
    assert drc.spin_until(lambda: drc.finished(tid) and drc.hovering(), 90)
    assert drc.answers(tid) == [("Cmd-Accepted-EV", ""), ("Cmd-Finished-EV", "")]
    land_early = drc.send("FCL-Takeoff-EV")  # wrong state: already flying
    assert drc.spin_until(lambda: drc.finished(land_early), 10)
    assert drc.answers(land_early)[-1][0] == "Cmd-Rejected-EV"
    assert "Hovering-ST" in drc.answers(land_early)[-1][1]
    x, y, z = drc.states[-1].position_enu
    fid = drc.send("Traj3D-Flyto-EV", (x + 25.0, y + 10.0, z, 5.0))
    assert drc.spin_until(lambda: drc.finished(fid), 60)
    assert drc.answers(fid) == [("Cmd-Accepted-EV", ""), ("Traj-Arrived-EV", "")]
    assert drc.spin_until(drc.hovering, 60)
    lid = drc.send("FCL-Land-EV", (0.0,))
    assert drc.spin_until(lambda: drc.finished(lid), 120)
    on_gps = "landed on GPS and barometer: no vision fix of pad L1"  # no camera in this launch
    (accepted, finished) = drc.answers(lid)
    plans_on = "landing on GPS and barometer: no vision fix of pad L1"  # said as it starts
    assert accepted[0] == "Cmd-Accepted-EV" and accepted[1].startswith(plans_on), accepted
    assert finished[0] == "Cmd-Finished-EV" and finished[1].startswith(on_gps), finished
    assert "heading 0 deg as commanded" in finished[1]  # calm air (LandingConfig.calm_wind)
    assert drc.spin_until(lambda: drc.states[-1].mode == drc.states[-1].MODE_GROUND_IDLE, 10)
    assert drc.truth_at(drc.sim_time).on_ground and drc.states[-1].on_ground
    sim_s, wall_s = drc.sim_time - sim0, time.monotonic() - wall0

    # a full world reset restarts sim time at 0: the PFC restarts and keeps the lockstep going
    from hdrc3_interfaces.srv import SimReset

    reset = drc.node.create_client(SimReset, "/world_sim/reset")
    assert reset.wait_for_service(timeout_sec=10.0)
    before, seen = drc.sim_time, len(drc.states)
    future = reset.call_async(SimReset.Request(agent=""))
    assert drc.spin_until(future.done, 10.0) and future.result().result.code == 0

    def restarted() -> Any:
        # pfc/state is keep-last: a test process slower than the lockstep may miss the samples
        # of any given second, so look for the first sample past 1 s of the new sim time.
        return next((s for s in drc.states[seen:] if 1e9 < stamp_ns(s) < before * 1e9), None)

    assert drc.spin_until(lambda: restarted() is not None, 30)
    assert restarted().mode in (restarted().MODE_BOOT, restarted().MODE_MANUAL)
    print(f"lockstep: {sim_s:.1f} s sim in {wall_s:.1f} s wall ({sim_s / wall_s:.1f}x real time)")
    print(f"steps longer than 20 ms (wall): {drc.states[-1].overruns} of {drc.states[-1].ticks}")


@pytest.mark.parametrize(
    ("param", "message"),
    [("world:=nope", "unknown world"), ("takeoff_height:=1000.0", "takeoff_height")],
)
def test_bad_parameters_exit_2_with_one_line(
    ros_domain: int, param: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from hdrc3_control.control_kernel_node import main

    assert main(["hdrc3-control-kernel", "--ros-args", "-p", param]) == 2
    assert message in capsys.readouterr().err


def test_a_reannounced_tick_is_answered_again(
    hdrc3_cli: Callable[..., Any], ros_domain: int
) -> None:
    """world_sim re-announces a tick whose answer it never got: the PFC answers it again.

    At a launch's first tick the PFC's command writer may not have matched world_sim's reader
    yet, and a reliable writer sends to matched readers only: the answer was lost and the whole
    simulation waited for it for good (a flagship run stalled at 0 s). The test is world_sim.
    """
    from rclpy.node import Node
    from rosgraph_msgs.msg import Clock

    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_base.stamps import set_stamp_ns
    from hdrc3_control.control_kernel_node import CLOCK_QOS, COMMAND_QOS, SENSOR_QOS
    from hdrc3_interfaces.msg import YacsCommand, YacsStatus

    launch = hdrc3_cli("launch", "--agents", AGENT, "--nodes", "control_kernel")
    launch.wait_for_line("READY", timeout=90)
    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        node = process.add_node(Node("fake_world_sim", context=process.context))
        answers: list[int] = []
        node.create_subscription(
            YacsCommand,
            f"/{AGENT}/yacs/command",
            lambda m: answers.append(m.header.stamp.sec * 10**9 + m.header.stamp.nanosec),
            COMMAND_QOS,
        )
        status = node.create_publisher(YacsStatus, f"/{AGENT}/yacs/status", SENSOR_QOS)
        clock = node.create_publisher(Clock, "/clock", CLOCK_QOS)
        assert process.spin_until(
            lambda: status.get_subscription_count() > 0 and clock.get_subscription_count() > 0,
            60.0,
        )

        def announce(ns: int) -> None:
            s = YacsStatus()
            set_stamp_ns(s.header.stamp, ns)
            status.publish(s)
            c = Clock()
            set_stamp_ns(c.clock, ns)
            clock.publish(c)

        tick = 20_000_000
        # as world_sim does: announce the tick again every half second until it is answered
        for _ in range(120):
            announce(tick)
            if process.spin_until(lambda: tick in answers, 0.5):
                break
        assert answers and set(answers) == {tick}, answers
        announce(tick)  # re-announced: world_sim says it has no answer for it
        # answered again (a PFC answers each tick once otherwise: the count would stay 1)
        assert process.spin_until(lambda: answers.count(tick) >= 2, 30.0), answers
        announce(2 * tick)
        assert process.spin_until(lambda: 2 * tick in answers, 30.0), answers
        assert answers[-1] == 2 * tick and set(answers) == {tick, 2 * tick}, answers
        node.destroy_node()
    assert launch.interrupt() == 0
