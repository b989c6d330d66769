"""The platform_server node over real DDS, with the fake kernels node, via rclpy and the CLI."""

from __future__ import annotations

import itertools
import json
import math
import os
import random
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from hdrc3.cli.main import main as hdrc3_main
from tests.integration.ros_wait import answer

pytestmark = pytest.mark.ros

BIN = Path(sys.executable).parent
AGENT = "uav0"
SETTLE_S = 1.0
"""Sim seconds after a completion event at which the end-to-end test reads the aircraft's state."""


def _seconds(stamp: Any) -> float:
    return stamp.sec + 1e-9 * stamp.nanosec


def _spawn(args: list[str]) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        args,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
        env=dict(os.environ),
    )


@pytest.fixture
def stack(ros_domain: int) -> Iterator[None]:
    """The real platform_server and the fake PFC/PPC (1 s activities, 2x real time)."""
    ns = ["--ros-args", "-r", f"__ns:=/{AGENT}"]
    procs = [
        _spawn([str(BIN / "hdrc3-platform-server"), *ns]),
        _spawn(
            [
                sys.executable,
                "-m",
                "hdrc3_platform_server.fake_node",
                *ns,
                "-p",
                "speed:=2.0",
                "-p",
                "duration:=1.0",
            ]
        ),
    ]
    try:
        yield
    finally:
        for p in procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
        for p in procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(timeout=10)


class Client:
    """rclpy service calls and event/state subscriptions with bounded waits."""

    def __init__(self, context: Any) -> None:
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node

        from hdrc3_interfaces.msg import HelicopterState, PlatformEvent
        from hdrc3_platform_server.node import EVENT_QOS, STATE_QOS

        self.node: Any = Node("test_client", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.events: list[Any] = []
        self.states: list[Any] = []
        self.node.create_subscription(
            PlatformEvent, f"/{AGENT}/platform_events", self.events.append, EVENT_QOS
        )
        self.node.create_subscription(
            HelicopterState, f"/{AGENT}/helicopter_state", self.states.append, STATE_QOS
        )

    def spin_until(self, done: Callable[[], bool], timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while not done() and time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.05)
        return done()

    def call(self, srv: Any, name: str, **fields: Any) -> Any:
        """Call a service of the agent (``name`` relative to it) or an absolute ``/name``."""
        client = self.node.create_client(srv, name if name.startswith("/") else f"/{AGENT}/{name}")
        assert self.spin_until(client.service_is_ready, 30.0), name
        request = srv.Request()
        for key, value in fields.items():
            setattr(request, key, value)
        response = answer(self.executor, client, request, 60.0)
        assert response is not None, f"no answer from {name}"
        return response

    def final(
        self, command_id: int | None = None, timeout: float = 30.0, *, command: str = ""
    ) -> Any:
        """The completion event (finished, failed, cancelled) of a command, by id or by name."""

        def find() -> Any:
            return next(
                (
                    e
                    for e in self.events
                    if e.kind in (0, 1, 2)
                    and (command_id is None or e.command_id == command_id)
                    and (not command or e.command == command)
                ),
                None,
            )

        self.spin_until(lambda: find() is not None, timeout)
        return find()

    def states_since(self, t: float) -> list[Any]:
        """The Data Interface samples received so far that are stamped at or after sim time t."""
        i = len(self.states)
        while i > 0 and _seconds(self.states[i - 1].pfc_time) >= t:
            i -= 1
        return self.states[i:]

    def state_at(self, t: float, timeout: float = 60.0) -> Any:
        """The first Data Interface sample stamped at or after sim time ``t`` (bounded wait).

        DDS does not order the state topic against the event topic: a sample read right after
        an event arrived may still be one of before the event, so wait for the sim time instead.
        """
        assert self.spin_until(lambda: bool(self.states_since(t)), timeout), (
            t,
            [_seconds(s.pfc_time) for s in self.states[-1:]],
        )
        return self.states_since(t)[0]


@pytest.fixture
def client(stack: None, ros_context: Any) -> Iterator[Client]:
    c = Client(ros_context)
    assert c.spin_until(lambda: len(c.states) > 0, 30.0), "no helicopter_state"
    try:
        yield c
    finally:
        c.executor.shutdown()


def test_fcl_over_dds_ok_busy_finished_and_data_interface(client: Client) -> None:
    from hdrc3_interfaces.srv import FclTakeoff, FclTraj3dFlyto, FclYaw

    takeoff = client.call(FclTakeoff, "fcl/takeoff").result
    assert takeoff.code == 0 and takeoff.command_id > 0
    busy = client.call(FclYaw, "fcl/yaw", heading=0.3).result
    assert busy.code == 1 and "fcl_takeoff" in busy.reason
    event = client.final(takeoff.command_id)
    assert event is not None and event.kind == 0 and event.command == "fcl_takeoff"
    bad = client.call(
        FclTraj3dFlyto,
        "fcl/traj3d_flyto",
        longitude=13.47,
        latitude=math.nan,
        altitude=125.0,
        velocity=8.0,
    ).result
    assert bad.code == 2 and "finite" in bad.reason
    # Data Interface: 25 Hz of sim time, airborne after the take-off (samples stamped from the
    # completion event's sim time on: one received after the event may be older than it)
    finished = _seconds(event.header.stamp)
    client.spin_until(lambda: len(client.states_since(finished)) >= 30, 20.0)
    states = client.states_since(finished)
    stamps = [_seconds(s.pfc_time) for s in states]
    gaps = [b - a for a, b in itertools.pairwise(stamps)]
    assert len(stamps) >= 30 and all(abs(g - 0.04) < 1e-6 for g in gaps), gaps
    assert not states[-1].on_ground_flag


def test_services_survive_random_requests(client: Client) -> None:
    from hdrc3_interfaces.srv import FclClimb, FclLand, FclTraj3dFlyto, PpclTurnTo, PpclZoom

    rng = random.Random(7)
    specials = [math.nan, math.inf, -math.inf, 1e308, -1e308, 0.0, 13.47, 55.7]

    def value() -> float:
        return rng.choice(specials) if rng.random() < 0.5 else rng.uniform(-1e4, 1e4)

    calls = [
        (FclLand, "fcl/land", ("heading",)),
        (FclClimb, "fcl/climb", ("altitude",)),
        (FclTraj3dFlyto, "fcl/traj3d_flyto", ("longitude", "latitude", "altitude", "velocity")),
        (PpclTurnTo, "ppcl/turn_to", ("pan", "tilt")),
        (PpclZoom, "ppcl/zoom", ("value",)),
    ]
    for _ in range(60):
        srv, name, fields = rng.choice(calls)
        result = client.call(srv, name, **{f: value() for f in fields}).result
        assert result.code in (0, 1, 2, 3) and (result.code == 0 or result.reason)
    from hdrc3_interfaces.srv import FclCancel

    assert client.call(FclCancel, "fcl/cancel").result.code == 0


def test_a_command_sent_again_with_its_key_runs_once(client: Client) -> None:
    from hdrc3_interfaces.srv import FclTakeoff, FclYaw

    first = client.call(FclTakeoff, "fcl/takeoff", request_key="take-off-1").result
    again = client.call(FclTakeoff, "fcl/takeoff", request_key="take-off-1").result
    other = client.call(FclTakeoff, "fcl/takeoff", request_key="take-off-2").result
    too_long = client.call(FclYaw, "fcl/yaw", heading=0.0, request_key="k" * 65).result
    assert first.code == 0 and first.command_id > 0
    assert (again.code, again.command_id) == (0, first.command_id)  # the first answer, not BUSY
    assert other.code == 1  # a new key is a new command
    assert too_long.code == 2 and "request_key: 65 characters" in too_long.reason
    final = client.final(first.command_id)
    assert final is not None and final.kind == 0


def test_the_tst_port_sends_again_when_an_answer_is_lost(client: Client) -> None:
    """The first answer to the TST's platform port is dropped; the resend gets it, run once."""
    from rclpy.task import Future

    from hdrc3_interfaces.srv import FclTakeoff
    from hdrc3_platform_server.codes import FclCommand
    from hdrc3_platform_server.geo_frame import frame_from_world
    from hdrc3_tst.platform_port import CommandState
    from hdrc3_tst.ros_platform import RosPlatform

    probe = client.node.create_client(FclTakeoff, f"/{AGENT}/fcl/takeoff")
    assert client.spin_until(probe.service_is_ready, 30.0)
    lost: list[Any] = []
    create_client = client.node.create_client

    def losing_client(*args: Any, **kwargs: Any) -> Any:
        made = create_client(*args, **kwargs)
        call_async = made.call_async

        def first_answer_lost(request: Any) -> Any:
            sent = call_async(request)
            if lost:
                return sent
            lost.append(sent)  # served, but its answer never reaches the port
            return Future()

        made.call_async = first_answer_lost
        return made

    client.node.create_client = losing_client
    port = RosPlatform(client.node, AGENT, frame_from_world("revinge"), lambda: None)
    handle = port.send(FclCommand.TAKEOFF)
    assert client.spin_until(lambda: handle.state is not CommandState.SENT, 20.0), handle
    assert lost and lost[0].done()
    assert handle.command_id == lost[0].result().result.command_id > 0, handle
    assert client.spin_until(lambda: handle.state.ended, 30.0), handle
    assert handle.state is CommandState.FINISHED, handle


def test_cli_fcl_ppcl_state(stack: None, capsys: pytest.CaptureFixture[str]) -> None:
    # the Data Interface flows once the DRC has the PFC's state: then commands are meaningful
    assert hdrc3_main(["state", AGENT, "--once", "--timeout", "60"]) == 0
    capsys.readouterr()
    assert hdrc3_main(["fcl", AGENT, "takeoff", "--timeout", "60"]) == 0
    assert "FCL_FINISHED" in capsys.readouterr().out
    assert hdrc3_main(["fcl", AGENT, "takeoff"]) == 1
    assert "FCL_NOT_ACCEPTED" in capsys.readouterr().out
    assert hdrc3_main(["fcl", AGENT, "yaw", "30", "--no-wait"]) == 0
    assert "FCL_OK" in capsys.readouterr().out
    assert hdrc3_main(["fcl", AGENT, "cancel"]) == 0
    assert hdrc3_main(["fcl", "nobody", "takeoff"]) == 2
    capsys.readouterr()
    for words in (
        ["request", "ptu"],
        ["request", "camera"],
        ["turn_to", "0", "90"],
        ["zoom", "0.4"],
        ["release", "ptu"],
        ["release", "camera"],
    ):
        assert hdrc3_main(["ppcl", AGENT, *words]) == 0, capsys.readouterr().out
    assert hdrc3_main(["ppcl", AGENT, "turn_to", "0", "90"]) == 1  # ptu released
    assert "request control of the ptu" in capsys.readouterr().out
    assert hdrc3_main(["state", AGENT, "--once"]) == 0
    record = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert set(record) >= {"latitude", "longitude", "altitude", "on_ground_flag", "pfc_time"}
    assert hdrc3_main(["state", AGENT, "--once", "--camera"]) == 0
    camera = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert set(camera) == {"id", "pan", "tilt", "zoom", "ipc_time"}


@pytest.mark.slow
def test_end_to_end_with_the_real_kernels(
    hdrc3_cli: Callable[..., Any], ros_context: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    """Issue 6 "done when": take-off, 300 m fly-to (+ FCL_BUSY), land, through the real stack."""
    import pymap3d

    from hdrc3_interfaces.srv import SimPause, SimSetRc

    launch = hdrc3_cli("launch", "--agents", AGENT, "--world", "revinge")
    launch.wait_for_line("READY", timeout=90)
    client = Client(ros_context)
    try:
        assert client.spin_until(lambda: len(client.states) > 0, 60.0)
        rc = SimSetRc.Request
        answer = client.call(
            SimSetRc, "rc/set", mode=rc.MODE_AUTONOMOUS, engine=rc.ENGINE_ON
        ).result
        assert answer.code == 0, answer.reason
        assert client.spin_until(lambda: client.states[-1].rpm >= 800.0, 120.0)
        assert hdrc3_main(["fcl", AGENT, "takeoff", "--timeout", "300"]) == 0
        assert "FCL_FINISHED" in capsys.readouterr().out
        takeoff = client.final(command="fcl_takeoff", timeout=60.0)
        assert takeoff is not None and takeoff.kind == 0, takeoff
        s = client.state_at(_seconds(takeoff.header.stamp))
        e, n, _ = pymap3d.geodetic2enu(s.latitude, s.longitude, s.altitude, 55.70, 13.47, 95.0)
        lat, lon, alt = pymap3d.enu2geodetic(e + 300.0, n, 30.0, 55.70, 13.47, 95.0)
        from hdrc3_interfaces.srv import FclTraj3dFlyto

        flyto = client.call(
            FclTraj3dFlyto,
            "fcl/traj3d_flyto",
            longitude=lon,
            latitude=lat,
            altitude=alt,
            velocity=8.0,
        ).result
        assert flyto.code == 0, flyto.reason
        # sim time stands still while the CLI starts, so the fly-to is still running when the
        # second one arrives, however long that takes on a loaded machine
        paused = client.call(SimPause, "/world_sim/pause", paused=True).result
        assert paused.code == 0, paused.reason
        try:
            argv = ["fcl", AGENT, "traj3d_flyto", str(lon), str(lat), str(alt), "8"]
            assert hdrc3_main(argv) == 1
            assert "FCL_BUSY" in capsys.readouterr().out
        finally:
            resumed = client.call(SimPause, "/world_sim/pause", paused=False).result
        assert resumed.code == 0, resumed.reason
        final = client.final(flyto.command_id, timeout=300.0)
        assert final is not None and final.kind == 0, final
        s = client.state_at(_seconds(final.header.stamp) + SETTLE_S)
        offset = pymap3d.geodetic2enu(s.latitude, s.longitude, s.altitude, lat, lon, alt)
        assert math.dist(offset, (0.0, 0.0, 0.0)) <= 3.0, offset
        assert hdrc3_main(["fcl", AGENT, "land", "0", "--timeout", "300"]) == 0
        landed = client.final(command="fcl_land", timeout=60.0)
        assert landed is not None and landed.kind == 0, landed
        assert client.state_at(_seconds(landed.header.stamp) + SETTLE_S).on_ground_flag
    finally:
        client.executor.shutdown()
        launch.interrupt()
