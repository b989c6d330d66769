"""kill -9 of platform_server / control_kernel mid-command, and a burst of service calls.

The real chain under ``hdrc3 launch`` (which restarts a crashed node): world_sim, control_kernel
and platform_server of one agent over real DDS on the test's own domain. A fly-to is killed in
flight; the command must end with exactly one terminal FAILED event naming the restart, and the
next command must be accepted and finish without a cancel. Waits are bounded in wall time; what
is waited for is read from the stack's outputs (answers, platform events, the Data Interface).
The wall times from the kill to the terminal event are printed (pytest -s shows them).
"""

from __future__ import annotations

import math
import os
import signal
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

pytestmark = pytest.mark.ros

AGENT = "uav0"
WORLD = "revinge"
CALL_TIMEOUT_S = 10.0
SPEED = "2"
"""Sim speed: a dead control_kernel leaves the aircraft on its last command (automatic
lockstep lets the sim go on), so the sim must not run far ahead while it restarts."""


HOVER_S = 0.5
"""PFC seconds of steady autonomous hover before the next command (see Rig.hovering)."""


def _seconds(stamp: Any) -> float:
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


class Rig:
    """The test's side: FCL client, Data Interface, the launcher's process table."""

    def __init__(self, process: Any) -> None:
        from hdrc3_base.ros_runtime import STATUS_QOS, STATUS_TOPIC
        from hdrc3_interfaces.msg import HelicopterState, LaunchStatus, PfcState, TruthState
        from hdrc3_platform_server.client import PlatformClient
        from hdrc3_platform_server.geo_frame import frame_from_world
        from hdrc3_platform_server.node import STATE_QOS

        self.process = process
        self.frame = frame_from_world(WORLD)
        self.client = PlatformClient(process, AGENT)
        self.node: Any = self.client.node
        self.states: list[Any] = []
        self.pfc: list[Any] = []
        self.status: Any = None
        self.arrived: dict[str, list[float]] = {"platform_server": [], "control_kernel": []}
        """Wall time of every Data Interface / PFC state sample: when each node was heard."""

        def keep(samples: list[Any], arrivals: list[float]) -> Callable[[Any], None]:
            def on_sample(msg: Any) -> None:
                samples.append(msg)
                arrivals.append(time.monotonic())

            return on_sample

        self.node.create_subscription(
            HelicopterState,
            f"/{AGENT}/helicopter_state",
            keep(self.states, self.arrived["platform_server"]),
            STATE_QOS,
        )
        self.node.create_subscription(
            PfcState,
            f"/{AGENT}/pfc/state",
            keep(self.pfc, self.arrived["control_kernel"]),
            STATE_QOS,
        )
        self.node.create_subscription(LaunchStatus, STATUS_TOPIC, self._on_status, STATUS_QOS)
        self.truth: Any = None
        """The simulator's latest ground truth (read only to check the PFC's height)."""
        self.node.create_subscription(
            TruthState, f"/{AGENT}/ground_truth/state", self._on_truth, 10
        )

    def _on_truth(self, msg: Any) -> None:
        self.truth = msg

    def _on_status(self, msg: Any) -> None:
        self.status = msg

    def wait(self, done: Callable[[], bool], timeout: float, what: str) -> None:
        assert self.process.spin_until(done, timeout), f"not within {timeout} s: {what}"

    def supervised(self, node: str) -> Any:
        """The launcher's entry of ``node`` (waits for a status that lists it running)."""

        def entry() -> Any:
            for p in self.status.processes if self.status is not None else ():
                if p.name == f"{AGENT}/{node}":
                    return p
            return None

        self.wait(lambda: entry() is not None and entry().pid > 0, 30.0, f"{node} running")
        return entry()

    def fcl(self, srv: Any, name: str, **fields: Any) -> Any:
        response = self.client.call(srv, f"fcl/{name}", srv.Request(**fields), CALL_TIMEOUT_S)
        assert response is not None, f"fcl_{name}: no answer within {CALL_TIMEOUT_S} s"
        return response.result

    def final(self, command_id: int, timeout: float) -> Any:
        event = self.client.wait_final(command_id, timeout, lambda _e: None)
        assert event is not None, f"command {command_id}: no terminal event in {timeout} s"
        return event

    def terminal_events(self, command_id: int) -> list[Any]:
        from hdrc3_platform_server.completion import TERMINAL

        return [e for e in self.client.events if e.command_id == command_id and e.kind in TERMINAL]

    def hovering(self) -> bool:
        """The PFC has reported autonomous hover for HOVER_S of its time.

        Its mode reads HOVER from the moment a cancelled fly-to hands over to the hover
        function (Mode Switch Wait-Hover-ST), a few ticks before the PFC takes commands again
        (Hovering-ST); a command sent on that first sample is refused by the PFC.
        """
        latest = _seconds(self.pfc[-1].pfc_time) if self.pfc else 0.0
        for s in reversed(self.pfc):
            speed = math.hypot(*s.velocity_enu)
            if not (s.auto_flag and not s.on_ground and s.mode == s.MODE_HOVER and speed < 1.0):
                return False
            if latest - _seconds(s.pfc_time) >= HOVER_S:
                return True
        return False

    def enu(self) -> tuple[float, float, float]:
        s = self.states[-1]
        return self.frame.to_enu(s.longitude, s.latitude, s.altitude)

    def airborne(self) -> None:
        """Hand over to autonomy and take off (finished, hovering)."""
        from hdrc3.safety_pilot import Switch, set_rc
        from hdrc3_interfaces.msg import FclReturn, SimResult
        from hdrc3_interfaces.srv import FclTakeoff
        from hdrc3_platform_server.codes import EventKind

        code, reason = set_rc(
            self.process, self.node, AGENT, Switch.AUTONOMOUS, Switch.ON, CALL_TIMEOUT_S
        )
        assert code == SimResult.OK, reason
        self.wait(
            lambda: bool(self.pfc) and self.pfc[-1].mode == self.pfc[-1].MODE_GROUND_IDLE,
            60.0,
            "autonomous, idle on the ground",
        )
        takeoff = self.fcl(FclTakeoff, "takeoff")
        assert takeoff.code == FclReturn.FCL_OK, takeoff.reason
        assert self.final(takeoff.command_id, 120.0).kind is EventKind.FINISHED

    def flyto(self, east: float, north: float, velocity: float) -> Any:
        """Start a fly-to relative to the current position at 15 m up."""
        from hdrc3_interfaces.srv import FclTraj3dFlyto

        e, n, _ = self.enu()
        lon, lat, alt = self.frame.to_wgs84(e + east, n + north, 15.0)
        return self.fcl(
            FclTraj3dFlyto,
            "traj3d_flyto",
            longitude=lon,
            latitude=lat,
            altitude=alt,
            velocity=velocity,
        )


def _processes_on(domain: int) -> list[str]:
    """Other processes whose environment has this ROS domain (launcher, warm spare, nodes)."""
    needle = f"ROS_DOMAIN_ID={domain}".encode()
    found = []
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        proc = Path("/proc", entry.name)
        try:
            environ = (proc / "environ").read_bytes().split(b"\0")
            state = (proc / "stat").read_text().rsplit(")", 1)[1].split()[0]
            command = (proc / "cmdline").read_text().replace("\0", " ")
        except OSError:
            continue  # gone, or not ours
        if needle in environ and state != "Z":
            found.append(command)
    return found


@pytest.fixture
def rig(hdrc3_cli: Callable[..., Any], ros_domain: int) -> Iterator[Rig]:
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
        SPEED,
    )
    launch.wait_for_line("READY", timeout=90)
    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        r = Rig(process)
        try:
            r.wait(lambda: len(r.states) > 0, 60.0, "the Data Interface")
            yield r
        finally:
            r.node.destroy_node()
            code = launch.interrupt()
            print("\n".join(launch.lines[-30:]))
    # the launcher stops its nodes, the restarted ones and its unused warm spare included
    assert code == 0, launch.lines[-30:]
    deadline = time.monotonic() + 10.0
    while _processes_on(ros_domain) and time.monotonic() < deadline:
        time.sleep(0.1)  # a process's exit has no notification for a non-parent
    assert _processes_on(ros_domain) == []


def _kill_mid_flyto(r: Rig, node: str, reason: str) -> None:
    from hdrc3_interfaces.msg import FclReturn
    from hdrc3_interfaces.srv import FclYaw
    from hdrc3_platform_server.codes import EventKind

    r.airborne()
    # 120 s of sim time (60 s of wall time at --speed 2): still flying when the new node is up,
    # also at load 12, where a restarted platform_server took 27 s to come up (before the warm
    # spare). A fly-to that ends while the server is down: the test below.
    flyto = r.flyto(120.0, 0.0, 1.0)
    assert flyto.code == FclReturn.FCL_OK, flyto.reason
    r.wait(lambda: r.pfc[-1].command_id == flyto.command_id, 30.0, "the PFC flies it")
    before = r.supervised(node)
    killed = time.monotonic()
    os.kill(before.pid, signal.SIGKILL)
    r.wait(
        lambda: (
            r.supervised(node).restarts == before.restarts + 1
            and r.supervised(node).pid != before.pid
        ),
        30.0,
        f"{node} restarted",
    )
    restarted = time.monotonic()
    failed = r.final(flyto.command_id, 60.0)
    ended = time.monotonic()
    r.wait(lambda: r.arrived[node][-1] > restarted, 60.0, f"output of the new {node}")
    heard = next(t for t in r.arrived[node] if t > restarted)
    print(
        f"kill -9 {node}: process restarted {restarted - killed:.2f} s after the kill, its first "
        f"output {heard - killed:.2f} s after; terminal event {ended - killed:.2f} s after the "
        f"kill = {ended - heard:+.2f} s from the new node's first output"
    )
    assert failed.kind is EventKind.FAILED and reason in failed.reason, failed

    # no cancel: the next command is taken once the PFC reports autonomous hover again
    r.wait(r.hovering, 120.0, "autonomous hover after the restart")
    if node == "control_kernel":
        # the new PFC's height comes from the old one's barometer reference (warm start), not
        # from GPS: without it the Data Interface was 5.3 m off the truth
        r.wait(lambda: r.truth is not None, 10.0, "ground truth")
        error = r.pfc[-1].position_enu[2] - r.truth.position_enu[2]
        assert abs(error) < 1.5, f"PFC height {error:+.2f} m off the truth after its restart"
    yaw = r.fcl(FclYaw, "yaw", heading=1.0)
    assert yaw.code == FclReturn.FCL_OK, yaw.reason
    done = r.final(yaw.command_id, 120.0)
    assert done.kind is EventKind.FINISHED, done
    assert len(r.terminal_events(flyto.command_id)) == 1, r.terminal_events(flyto.command_id)


@pytest.mark.slow
def test_platform_server_killed_mid_command(rig: Rig) -> None:
    _kill_mid_flyto(rig, "platform_server", "platform server restarted")


@pytest.mark.slow
def test_control_kernel_killed_mid_command(rig: Rig) -> None:
    # the launcher saw the exit: the command ends then, before the new PFC is up
    _kill_mid_flyto(rig, "control_kernel", "control kernel (PFC) exited (code -9)")


@pytest.mark.slow
def test_a_command_ending_while_platform_server_is_down_ends_once(rig: Rig) -> None:
    """The PFC ends a fly-to while the server is stopped, then the server is killed: the fly-to's
    final reply went to the dead process; the new server ends the command from its journal."""
    from hdrc3_interfaces.msg import FclReturn
    from hdrc3_interfaces.srv import FclYaw
    from hdrc3_platform_server.codes import EventKind
    from hdrc3_platform_server.fcl_api import ENDED_WHILE_DOWN, RESTARTED_LOST

    r = rig
    r.airborne()
    flyto = r.flyto(8.0, 0.0, 2.0)
    assert flyto.code == FclReturn.FCL_OK, flyto.reason
    r.wait(lambda: r.pfc[-1].command_id == flyto.command_id, 30.0, "the PFC flies it")
    before = r.supervised("platform_server")
    os.kill(before.pid, signal.SIGSTOP)  # the server hears nothing from here on ...
    r.wait(lambda: r.pfc[-1].command_id != flyto.command_id, 120.0, "the PFC ends the fly-to")
    os.kill(before.pid, signal.SIGKILL)  # ... and dies without having heard the final reply
    r.wait(lambda: r.supervised("platform_server").pid != before.pid, 30.0, "restarted")
    ended = r.final(flyto.command_id, 60.0)
    # the PFC's reply reaches the new server only if DDS had unmatched the stopped one (its
    # lease ran out) before the fly-to ended; else the journal's command ends as lost
    assert (ended.kind, ended.reason) in {
        (EventKind.FINISHED, ENDED_WHILE_DOWN),
        (EventKind.FAILED, RESTARTED_LOST),
    }, ended
    r.wait(r.hovering, 120.0, "autonomous hover after the restart")
    yaw = r.fcl(FclYaw, "yaw", heading=2.0)
    assert yaw.code == FclReturn.FCL_OK, yaw.reason
    assert r.final(yaw.command_id, 120.0).kind is EventKind.FINISHED
    assert len(r.terminal_events(flyto.command_id)) == 1, r.terminal_events(flyto.command_id)


def test_a_burst_of_concurrent_calls_is_answered(hdrc3_cli: Callable[..., Any], ros_domain: int):
    """150 calls sent at once to FCL, PPCL and world_sim services: every one is answered."""
    from hdrc3_base.ros_runtime import SERVICE_QOS, RosProcess
    from hdrc3_interfaces.msg import FclReturn, PpclReturn, SimResult
    from hdrc3_interfaces.srv import FclClimb, PpclPtuLimits, SimTeleport

    launch = hdrc3_cli("launch", "--agents", AGENT, "--nodes", "world_sim,platform_server")
    launch.wait_for_line("READY", timeout=90)
    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        from rclpy.node import Node

        node = Node("burst_test", context=process.context)
        process.add_node(node)
        calls = [
            (node.create_client(srv, name, qos_profile=SERVICE_QOS), request)
            for srv, name, request in (
                (FclClimb, f"/{AGENT}/fcl/climb", FclClimb.Request(altitude=float("nan"))),
                (PpclPtuLimits, f"/{AGENT}/ppcl/ptu_limits", PpclPtuLimits.Request()),
                (SimTeleport, "/world_sim/teleport", SimTeleport.Request(agent=AGENT, frame=99)),
            )
        ]
        assert process.spin_until(lambda: all(c.service_is_ready() for c, _ in calls), 60.0)
        # an answer back first: the burst measures queueing, not the discovery of the answer path
        assert all(process.first_answer(c, request, 60.0) is not None for c, request in calls)
        futures = [client.call_async(request) for client, request in calls for _ in range(50)]
        process.spin_until(lambda: all(f.done() for f in futures), 120.0)
        answered = [f.result() for f in futures if f.done()]
        assert len(answered) == len(futures) == 150, f"{len(answered)} of {len(futures)}"
        codes = {(type(a).__name__, a.result.code) for a in answered}
        assert codes == {
            ("FclClimb_Response", FclReturn.FCL_NOT_ACCEPTED),  # NaN altitude
            ("PpclPtuLimits_Response", PpclReturn.PPCL_OK),
            ("SimTeleport_Response", SimResult.INVALID_ARGUMENT),  # unknown frame
        }, codes
        node.destroy_node()
    assert launch.interrupt() == 0
