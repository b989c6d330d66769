"""world_sim end to end: `hdrc3 launch` with two RMAXes, sensor rates, lockstep hover, determinism.

The test's own position controller reads ground truth (tests may; the stack never does) and
talks to the aircraft only through the YACS command topic and the RC service.
"""

from __future__ import annotations

import itertools
import math
import os
import signal
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

import pytest
from geometry_msgs.msg import TwistStamped
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, NavSatFix

from hdrc3_interfaces.msg import (
    Attitude,
    Barometer,
    CameraState,
    GroundContact,
    PowerStatus,
    PtuState,
    RotorRpm,
    SimResult,
    TruthState,
    YacsCommand,
    YacsStatus,
)
from hdrc3_interfaces.srv import (
    SimInjectFault,
    SimReset,
    SimSetPower,
    SimSetRc,
    SimSetWind,
    SimSpawnObject,
    SimTeleport,
)
from sim.world_loader import load_world
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros

G = 9.80665
# deep enough that a test process starved of CPU for a moment does not lose samples
RELIABLE = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
CLOCK_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
TICK_NS = 20_000_000
BACKLOG_S = 60.0
"""Sim seconds of samples a subscription of the rate test holds while the test catches up."""

# topic (under /<agent>/) -> (type, rate in Hz of sim time)
RATES: dict[str, tuple[Any, float]] = {
    "sensors/imu": (Imu, 200.0),
    "sensors/attitude": (Attitude, 50.0),
    "sensors/ground_contact": (GroundContact, 50.0),
    "sensors/barometer": (Barometer, 25.0),
    "sensors/rpm": (RotorRpm, 25.0),
    "sensors/ptu": (PtuState, 25.0),
    "sensors/color_camera": (CameraState, 25.0),
    "sensors/thermal_camera": (CameraState, 25.0),
    "sensors/gps/fix": (NavSatFix, 10.0),
    "sensors/gps/velocity": (TwistStamped, 10.0),
    "sensors/power": (PowerStatus, 5.0),
    "yacs/status": (YacsStatus, 50.0),
    "ground_truth/state": (TruthState, 50.0),
    "ground_truth/odometry": (Odometry, 50.0),
}


def _backlog_qos(rate: float) -> QoSProfile:
    """Reliable, deep enough for BACKLOG_S of a topic's samples.

    One Python executor takes ~1,100 samples/s of two agents' 28 topics one callback at a time;
    on a loaded machine it falls seconds behind, and its queue must hold that backlog (world_sim's
    writer history holds 10 s for the resends of deliveries the starved process dropped).
    """
    return QoSProfile(depth=round(rate * BACKLOG_S), reliability=ReliabilityPolicy.RELIABLE)


def _ns(stamp: Any) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def _sim_now(executor: SingleThreadedExecutor, node: Node) -> int:
    """A sim time (ns) at or after that of every world_sim request answered so far.

    world_sim serves a request between ticks, after the /clock of the current tick; /clock is
    latched keep-last 1, so a subscription created now first receives the latest value, which
    is at least the tick at which the request was served. (A /clock value already received
    may be older than the request: DDS does not order /clock against the service reply.)
    """
    now: list[int] = []
    sub = node.create_subscription(Clock, "/clock", lambda m: now.append(_ns(m.clock)), CLOCK_QOS)
    try:
        assert spin_until(executor, lambda: bool(now), 20.0), "no /clock"
    finally:
        node.destroy_subscription(sub)
    return now[0]


def _call(executor: SingleThreadedExecutor, node: Node, srv: Any, name: str, **fields: Any) -> Any:
    client = node.create_client(srv, name)
    try:
        assert client.wait_for_service(timeout_sec=20.0), name
        future = client.call_async(srv.Request(**fields))
        assert spin_until(executor, future.done, 20.0), f"{name} did not answer"
        return future.result().result
    finally:
        node.destroy_client(client)


@dataclass
class HoverFlight:
    """Spin up, climb 3 m above the pad, hold 60 sim-seconds, descend and land (truth-driven)."""

    target: tuple[float, float, float]
    hold_s: float = 60.0
    phase: str = "spin_up"
    hold_start: float | None = None
    landed_ticks: int = 0
    max_error: float = 0.0
    integral: list[float] = field(default_factory=lambda: [0.0, 0.0])

    def step(self, t: float, m: TruthState) -> tuple[float, float, float, float]:
        """(roll, pitch, yaw_rate, climb rate) for the tick at sim time ``t``."""
        pos, vel = m.position_enu, m.velocity_enu
        e = (self.target[0] - pos[0], self.target[1] - pos[1])
        error = math.sqrt(e[0] ** 2 + e[1] ** 2 + (self.target[2] - pos[2]) ** 2)
        if self.phase == "spin_up":
            if m.rotor_rpm > 800.0:
                self.phase = "climb"
            return 0.0, 0.0, 0.0, 0.0
        if self.phase == "climb" and error < 0.5:
            self.phase, self.hold_start = "hold", t
        if self.phase == "hold":
            assert self.hold_start is not None
            self.max_error = max(self.max_error, error)
            if t - self.hold_start >= self.hold_s:
                self.phase = "land"
        if self.phase == "land" and m.on_ground:
            self.landed_ticks += 1
            if self.landed_ticks >= 50:
                self.phase = "done"
        landing = self.phase in ("land", "done")
        climb = -0.6 if landing else max(-1.0, min(1.0, 0.8 * (self.target[2] - pos[2])))
        if m.on_ground:
            return 0.0, 0.0, 0.0, climb
        acc = []
        for i in range(2):
            v_des = max(-2.0, min(2.0, 0.5 * e[i]))
            self.integral[i] += 0.02 * e[i]
            acc.append(1.0 * (v_des - vel[i]) + 0.08 * self.integral[i])
        c, s = math.cos(m.heading), math.sin(m.heading)
        forward = acc[1] * c + acc[0] * s
        right = -acc[1] * s + acc[0] * c
        limit = math.radians(15.0)
        pitch = max(-limit, min(limit, -math.atan2(forward, G)))
        roll = max(-limit, min(limit, math.atan2(right, G)))
        yaw_rate = (-m.heading + math.pi) % (2.0 * math.pi) - math.pi
        return roll, pitch, yaw_rate, climb


def _truth_tuple(m: TruthState) -> tuple[Any, ...]:
    return (
        _ns(m.header.stamp),
        *m.position_enu,
        *m.velocity_enu,
        m.roll,
        m.pitch,
        m.heading,
        *m.body_rates,
        *m.specific_force_body,
        m.rotor_rpm,
        m.engine_running,
        m.on_ground,
        m.height_above_ground,
        m.mass,
    )


def _fly(executor: SingleThreadedExecutor, node: Node, pad: tuple[float, float]) -> HoverFlight:
    """One lockstepped flight of uav0 from t = 0; returns the flight with its truth record.

    The command publisher is matched before the reset (an unmatched volatile writer would lose
    the first answers); the truth subscription is created only after the reset, so that no
    sample of before the reset can pass for one of the new run (stamps restart at 0). Its first
    sample may come from world_sim's stall re-announcement; a re-announced tick that was already
    answered is answered again with the same command (world_sim ignores the duplicate).
    """
    pub = node.create_publisher(YacsCommand, "/uav0/yacs/command", RELIABLE)
    assert spin_until(executor, lambda: pub.get_subscription_count() > 0, 20.0)
    result = _call(executor, node, SimReset, "/world_sim/reset", agent="", lockstep_agents=["uav0"])
    assert result.code == SimResult.OK, result.reason
    truths: dict[int, TruthState] = {}
    sub = node.create_subscription(
        TruthState,
        "/uav0/ground_truth/state",
        lambda m: truths.__setitem__(_ns(m.header.stamp), m),
        RELIABLE,
    )
    rc = SimSetRc.Request
    result = _call(
        executor, node, SimSetRc, "/uav0/rc/set", mode=rc.MODE_AUTONOMOUS, engine=rc.ENGINE_ON
    )
    assert result.code == SimResult.OK, result.reason
    flight: HoverFlight | None = None
    record: list[tuple[Any, ...]] = []
    expected = 0
    command = YacsCommand()

    def answer() -> bool:
        nonlocal flight, expected
        if truths.pop(expected - TICK_NS, None) is not None:
            pub.publish(command)  # a re-announced tick: our answer may have been lost
        while expected in truths:
            m = truths.pop(expected)
            if flight is None:
                flight = HoverFlight(
                    (m.position_enu[0], m.position_enu[1], m.position_enu[2] + 3.0)
                )
            record.append(_truth_tuple(m))
            roll, pitch, yaw_rate, climb = flight.step(expected * 1e-9, m)
            command.header.stamp = m.header.stamp
            command.roll, command.pitch = roll, pitch
            command.yaw_rate, command.vertical = yaw_rate, climb
            pub.publish(command)
            expected += TICK_NS
        return flight is not None and flight.phase == "done"

    try:
        assert spin_until(executor, answer, 120.0), (flight, expected * 1e-9)
    finally:
        node.destroy_subscription(sub)
        node.destroy_publisher(pub)
    assert flight is not None
    flight.record = record  # type: ignore[attr-defined]
    assert math.dist(record[0][1:3], pad) < 0.1  # started on H1
    return flight


def test_launch_two_rmaxes_rates_hover_and_bit_identical_lockstep(hdrc3_cli, ros_context) -> None:
    world = load_world("revinge")
    pads = {"uav0": world.pad("H1"), "uav1": world.pad("H2")}
    # only world_sim (+ the monitor): the test's controller must be the only YACS client
    launch = hdrc3_cli(
        "launch", "--agents", "uav0,uav1", "--world", "revinge", "--nodes", "world_sim"
    )
    launch.wait_for_line("READY", timeout=60)
    node = Node("world_sim_test", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)

    # (1) /clock advances; every sensor topic of both agents at its rate, over sim time
    clock: list[int] = []
    node.create_subscription(Clock, "/clock", lambda m: clock.append(_ns(m.clock)), CLOCK_QOS)
    stamps: dict[str, list[int]] = defaultdict(list)
    subs = []
    for agent in pads:
        for topic, (msg_type, rate) in RATES.items():
            key = f"{agent}/{topic}"
            subs.append(
                node.create_subscription(
                    msg_type,
                    f"/{agent}/{topic}",
                    lambda m, k=key: stamps[k].append(_ns(m.header.stamp)),
                    _backlog_qos(rate),
                )
            )
    truth_last: dict[str, TruthState] = {}
    for agent in pads:
        subs.append(
            node.create_subscription(
                TruthState,
                f"/{agent}/ground_truth/state",
                lambda m, a=agent: truth_last.__setitem__(a, m),
                RELIABLE,
            )
        )
    # The writer side of a match may lag the reader side, and world_sim publishes only to matched
    # readers: count from the first sample every topic has delivered (from then on nothing is
    # missed), not from a guessed margin.
    keys = [f"{agent}/{topic}" for agent in pads for topic in RATES]

    def flowing() -> bool:
        return bool(clock) and all(stamps.get(k) for k in keys) and len(truth_last) == len(pads)

    assert spin_until(executor, flowing, 30.0), [k for k in keys if not stamps.get(k)]
    start = max(stamps[k][0] for k in keys)
    end = start + 2_000_000_000
    assert spin_until(executor, lambda: clock[-1] >= end + 100_000_000, 30.0), clock[-1:]
    assert clock == sorted(clock) and clock[-1] > clock[0]

    def drained() -> bool:
        """/clock (keep-last 1) runs ahead of a backlog on the busier topics: drain the window."""
        truth_stamps = [_ns(truth_last[a].header.stamp) for a in pads]
        return all(stamps[k][-1] >= end for k in keys) and min(truth_stamps) >= end

    assert spin_until(executor, drained, 120.0), {k: v[-1:] for k, v in stamps.items()}
    for key, ns in stamps.items():
        rate = RATES[key.split("/", 1)[1]][1]
        count = sum(start <= s < end for s in ns)
        assert abs(count - 2.0 * rate) <= 1, (key, count, rate)
    assert len(stamps) == len(RATES) * len(pads)
    for agent, pad in pads.items():
        position = truth_last[agent].position_enu
        assert math.dist(position[:2], (pad.east, pad.north)) < 0.1, (agent, position)
        assert truth_last[agent].on_ground
    for sub in subs:
        node.destroy_subscription(sub)

    # bad requests answer a code and a reason; the node keeps running
    footprint = world.buildings[0].footprint
    inside = [sum(p[i] for p in footprint) / len(footprint) for i in (0, 1)]
    bad = _call(executor, node, SimSpawnObject, "/world_sim/spawn_object", id="x", kind="box",
                east=inside[0], north=inside[1])  # fmt: skip
    assert (bad.code, world.buildings[0].name in bad.reason) == (SimResult.BLOCKED, True)
    bad = _call(
        executor, node, SimInjectFault, "/world_sim/inject_fault", agent="uav7", sensor="gps"
    )
    assert (bad.code, "uav7" in bad.reason) == (SimResult.UNKNOWN_AGENT, True)
    bad = _call(executor, node, SimInjectFault, "/world_sim/inject_fault", agent="uav0",
                sensor="gps", mode=3, magnitude=[math.nan])  # fmt: skip
    assert bad.code == SimResult.INVALID_ARGUMENT

    # (2) lockstep flight: lift off, hold 60 sim-seconds within 1 m, land
    h1 = (pads["uav0"].east, pads["uav0"].north)
    first = _fly(executor, node, h1)
    assert first.hold_start is not None and first.max_error <= 1.0, first.max_error
    record = first.record  # type: ignore[attr-defined]
    assert max(r[3] for r in record) > record[0][3] + 2.5  # climbed
    assert record[-1][-3]  # on the ground at the end

    # (3) the same run again from a reset is bit-identical
    second = _fly(executor, node, h1)
    again = second.record  # type: ignore[attr-defined]
    diverged = next(
        (i for i, (x, y) in enumerate(zip(record, again, strict=False)) if x != y), None
    )
    assert diverged is None and len(again) == len(record), (
        diverged,
        diverged is not None
        and [(x, y) for x, y in zip(record[diverged], again[diverged], strict=True) if x != y],
        len(record),
        len(again),
    )

    node.destroy_node()
    assert launch.interrupt(timeout=15) == 0
    assert "stopped" in launch.lines


def test_requests_change_the_running_world(hdrc3_cli, ros_context) -> None:
    from hdrc3_interfaces.msg import PtuCommand, RotatingLaserScan, WindState, WorldObjects
    from hdrc3_interfaces.srv import SimSetPower, SimSetWind, SimTeleport

    world = load_world("revinge")
    launch = hdrc3_cli("launch", "--agents", "uav0", "--speed", "5", "--nodes", "world_sim")
    launch.wait_for_line("READY", timeout=60)
    node = Node("world_sim_requests", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    clock: list[int] = [0]
    gps: list[int] = []
    laser: list[int] = []
    truth: list[TruthState] = []
    objects: list[WorldObjects] = []
    wind: list[WindState] = []
    node.create_subscription(Clock, "/clock", lambda m: clock.append(_ns(m.clock)), CLOCK_QOS)
    node.create_subscription(
        NavSatFix, "/uav0/sensors/gps/fix", lambda m: gps.append(_ns(m.header.stamp)), RELIABLE
    )
    node.create_subscription(
        RotatingLaserScan,
        "/uav0/sensors/laser",
        lambda m: laser.append(_ns(m.header.stamp)),
        RELIABLE,
    )
    node.create_subscription(TruthState, "/uav0/ground_truth/state", truth.append, RELIABLE)
    node.create_subscription(WorldObjects, "/world_sim/objects", objects.append, CLOCK_QOS)
    node.create_subscription(WindState, "/world_sim/wind", wind.append, RELIABLE)

    def advance(seconds: float) -> None:
        """Let ``seconds`` of sim time pass after every request answered so far."""
        goal = _sim_now(executor, node) + int(seconds * 1e9)
        assert spin_until(executor, lambda: clock[-1] >= goal, 20.0), clock[-1]

    assert spin_until(executor, lambda: bool(gps and objects and truth and wind), 20.0)
    assert len(objects[-1].objects) == len(world.objects)
    assert not laser  # switched off at start

    def ok(result: Any) -> None:
        assert result.code == SimResult.OK, result.reason

    # GPS dropped for 2 sim-seconds, then cleared: the fixes show the gap
    def gps_fault(mode: int) -> None:
        ok(_call(executor, node, SimInjectFault, "/world_sim/inject_fault", agent="uav0",
                 sensor="gps", mode=mode))  # fmt: skip

    gps_fault(1)
    advance(2.0)
    gps_fault(0)
    cleared_at = clock[-1]
    resumed = lambda: sum(s > cleared_at for s in gps) >= 5  # noqa: E731
    assert spin_until(executor, resumed, 20.0)
    gaps = [b - a for a, b in itertools.pairwise(gps)]
    assert max(gaps) >= 1_800_000_000, max(gaps)
    assert gaps[-4:] == pytest.approx([100_000_000] * 4, abs=10_000)  # 10 Hz again
    # laser on: scans at 1 / 13 ms
    ok(
        _call(
            executor, node, SimSetPower, "/world_sim/set_power", agent="uav0", devices=256, on=True
        )
    )
    assert spin_until(executor, lambda: len(laser) > 40, 30.0), (len(laser), clock[-1])
    # 1 / 13 ms: 40 scans within about 0.52 s of sim time
    assert laser[40] - laser[0] == pytest.approx(40 * 13_000_000, rel=0.05)
    # teleport by latitude/longitude onto the origin, 4 m up
    o = world.origin
    ok(
        _call(executor, node, SimTeleport, "/world_sim/teleport", agent="uav0",
              frame=SimTeleport.Request.FRAME_WGS84, x=o.latitude, y=o.longitude, height=4.0)
    )  # fmt: skip
    moved_at = _sim_now(executor, node)  # clock[-1] may still be of before the teleport
    later = lambda: _ns(truth[-1].header.stamp) > moved_at + 500_000_000  # noqa: E731
    assert spin_until(executor, later, 20.0)
    assert math.dist(truth[-1].position_enu[:2], (0.0, 0.0)) < 0.5
    # an object appears in the latched object list
    ok(
        _call(
            executor,
            node,
            SimSpawnObject,
            "/world_sim/spawn_object",
            id="crate",
            kind="box",
            east=1.0,
            north=2.0,
        )
    )
    assert spin_until(executor, lambda: any(x.id == "crate" for x in objects[-1].objects), 10.0)
    # wind at run time
    request = SimSetWind.Request()
    request.mean.x, request.gust_intensity = 6.0, 1.0
    ok(
        _call(
            executor, node, SimSetWind, "/world_sim/set_wind", mean=request.mean, gust_intensity=1.0
        )
    )
    assert spin_until(executor, lambda: wind[-1].mean.x == 6.0 and wind[-1].gust.x != 0.0, 10.0)
    # the perception kernel's PTU set-point moves the pan-tilt unit
    pans: list[float] = []
    node.create_subscription(PtuState, "/uav0/sensors/ptu", lambda m: pans.append(m.pan), RELIABLE)
    ptu = node.create_publisher(PtuCommand, "/uav0/ptu/command", RELIABLE)
    assert spin_until(executor, lambda: ptu.get_subscription_count() > 0, 10.0)
    ptu.publish(PtuCommand(pan=0.5, tilt=0.2))
    assert spin_until(executor, lambda: bool(pans) and abs(pans[-1] - 0.5) < 0.01, 20.0)
    bad = _call(executor, node, SimSetRc, "/uav0/rc/set", set_sticks=True, throttle=math.inf)
    assert bad.code == SimResult.INVALID_ARGUMENT
    node.destroy_node()
    assert launch.interrupt(timeout=15) == 0


HUGE = "x" * 100_000
EXTREME_REQUESTS: list[tuple[Any, str, dict[str, Any]]] = [
    (SimTeleport, "/world_sim/teleport", {"agent": "uav0", "x": math.nan}),
    (SimTeleport, "/world_sim/teleport", {"agent": "uav0", "heading": 1e308, "height": 2.0}),
    (SimTeleport, "/world_sim/teleport", {"agent": HUGE}),
    (SimTeleport, "/world_sim/teleport", {"agent": "uav0", "frame": 255}),
    (
        SimInjectFault,
        "/world_sim/inject_fault",
        {"agent": "uav0", "sensor": "gps", "mode": 3, "magnitude": [1e308]},
    ),
    (
        SimInjectFault,
        "/world_sim/inject_fault",
        {"agent": "uav0", "sensor": "gps", "mode": 3, "magnitude": [1.0] * 100_000},
    ),
    (SimInjectFault, "/world_sim/inject_fault", {"agent": "uav0", "sensor": HUGE, "mode": 1}),
    (SimInjectFault, "/world_sim/inject_fault", {"agent": "uav0", "sensor": "imu", "mode": 255}),
    (SimSpawnObject, "/world_sim/spawn_object", {"id": HUGE, "kind": "box"}),
    (SimSpawnObject, "/world_sim/spawn_object", {"id": "b", "kind": "box", "east": math.inf}),
    (SimSpawnObject, "/world_sim/spawn_object", {"id": "b", "kind": "box", "heading": -1e308}),
    (SimSpawnObject, "/world_sim/spawn_object", {"id": "b", "kind": HUGE}),
    (SimSetWind, "/world_sim/set_wind", {"gust_intensity": math.nan}),
    (SimSetWind, "/world_sim/set_wind", {"gust_intensity": 1e308}),
    (SimSetPower, "/world_sim/set_power", {"agent": "uav0", "devices": 2**32 - 1, "on": True}),
    (SimSetPower, "/world_sim/set_power", {"agent": HUGE, "devices": 1}),
    (SimSetRc, "/uav0/rc/set", {"mode": 255}),
    (SimSetRc, "/uav0/rc/set", {"set_sticks": True, "roll": math.nan}),
    (SimSetRc, "/uav0/rc/set", {"set_sticks": True, "throttle": 1e308}),
    (SimReset, "/world_sim/reset", {"agent": HUGE}),
    (SimReset, "/world_sim/reset", {"agent": "", "lockstep_agents": ["uav0"] * 1000}),
]
"""A small version of the sim services' property test (tests/unit/sim/test_sim_services.py)."""


def test_extreme_requests_get_an_answer_and_the_node_lives_on(hdrc3_cli, ros_context) -> None:
    from hdrc3_interfaces.msg import LaserCommand, PtuCommand

    launch = hdrc3_cli("launch", "--agents", "uav0", "--speed", "5", "--nodes", "world_sim")
    launch.wait_for_line("READY", timeout=60)
    node = Node("world_sim_extremes", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    for srv, name, fields in EXTREME_REQUESTS:
        result = _call(executor, node, srv, name, **fields)
        assert result.code != SimResult.OK and 0 < len(result.reason) <= 300, (name, result)
    # payload commands with absurd values (topics: refused and logged, nothing to answer)
    ptu = node.create_publisher(PtuCommand, "/uav0/ptu/command", RELIABLE)
    laser = node.create_publisher(LaserCommand, "/uav0/laser/command", RELIABLE)
    assert spin_until(
        executor, lambda: ptu.get_subscription_count() and laser.get_subscription_count(), 20.0
    )
    ptu.publish(PtuCommand(pan=1e308, tilt=math.nan))
    laser.publish(LaserCommand(angular_resolution=1.0, distance_resolution=0.01,
                               hold_angle=True, rotation_angle=-1e308))  # fmt: skip
    # alive: it answers a valid request and its clock goes on
    before = _sim_now(executor, node)
    result = _call(executor, node, SimSetWind, "/world_sim/set_wind", gust_intensity=0.5)
    assert result.code == SimResult.OK, result.reason
    assert _sim_now(executor, node) > before
    assert launch.proc.poll() is None


def test_world_sim_killed_mid_flight_resumes_its_checkpoint(hdrc3_cli, ros_context) -> None:
    """kill -9 of world_sim under the launcher: the restarted one goes on with the same flight."""
    from hdrc3_base.ros_runtime import STATUS_QOS, STATUS_TOPIC
    from hdrc3_interfaces.msg import LaunchStatus, SimRun

    launch = hdrc3_cli("launch", "--agents", "uav0", "--speed", "4", "--nodes", "world_sim")
    launch.wait_for_line("READY", timeout=60)
    node = Node("world_sim_restart", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    clock: list[int] = []
    truth: list[TruthState] = []
    runs: list[SimRun] = []
    status: list[LaunchStatus] = []
    node.create_subscription(Clock, "/clock", lambda m: clock.append(_ns(m.clock)), CLOCK_QOS)
    node.create_subscription(TruthState, "/uav0/ground_truth/state", truth.append, RELIABLE)
    node.create_subscription(SimRun, "/world_sim/run", runs.append, CLOCK_QOS)
    node.create_subscription(LaunchStatus, STATUS_TOPIC, status.append, STATUS_QOS)
    assert spin_until(executor, lambda: bool(runs and status), 20.0)
    assert runs[0].kind == SimRun.STARTED
    # the safety pilot starts the engine and climbs on the collective stick (no controller)
    result = _call(executor, node, SimSetRc, "/uav0/rc/set", engine=SimSetRc.Request.ENGINE_ON,
                   set_sticks=True, throttle=0.65)  # fmt: skip
    assert result.code == SimResult.OK, result.reason
    airborne = lambda: bool(truth) and truth[-1].height_above_ground > 8.0  # noqa: E731
    assert spin_until(executor, airborne, 60.0), truth[-1:]
    pid = next(p.pid for p in status[-1].processes if p.name == "world_sim")
    os.kill(pid, signal.SIGKILL)
    before = len(truth)

    def resumed() -> bool:  # the old process's queued states may still arrive first (load)
        if len(runs) < 2:
            return False
        return sum(_ns(m.header.stamp) >= _ns(runs[-1].stamp) for m in truth[before:]) > 10

    assert spin_until(executor, resumed, 90.0), (runs[1:], len(truth) - before)
    run = runs[-1]
    assert run.kind == SimRun.RESUMED, run.reason
    assert run.run_id == runs[0].run_id and run.process_id != runs[0].process_id
    stamp, saved = _ns(run.stamp), _ns(run.checkpoint_stamp)
    # the clock never went back; the world was at most one checkpoint period (0.5 s) behind
    assert all(b >= a for a, b in itertools.pairwise(clock)), clock
    last_old = max(_ns(m.header.stamp) for m in truth[:before])
    assert last_old < stamp <= saved + 500_000_000
    after = [m for m in truth[before:] if _ns(m.header.stamp) >= stamp]
    first = after[0]  # the new process's first ticks can precede discovery of our reader
    assert not first.on_ground and first.engine_running and first.height_above_ground > 5.0
    old = {_ns(m.header.stamp): m for m in truth[:before]}
    if saved in old and _ns(first.header.stamp) == stamp:  # the checkpoint's state, resumed
        assert math.dist(old[saved].position_enu, first.position_enu) < 0.01
    # near where it was: at most the motion (< 8 m/s) between the last old sample this reader got
    # and the checkpoint (either may come first: a loaded reader can miss the old process's last
    # samples), plus the motion since the resume; not back on its pad
    moved_s = (_ns(first.header.stamp) - stamp + abs(last_old - saved)) / 1e9
    assert math.dist(old[last_old].position_enu, first.position_enu) < 1.0 + 8.0 * moved_s
    assert not after[-1].on_ground and after[-1].rotor_rpm > 700.0
    launch.wait_for_line("world_sim: restarted (restart 1)")
    # stopped by the launcher (SIGINT, then SIGTERM/SIGKILL): no world_sim outlives the test
    assert launch.interrupt(timeout=30.0) == 0
