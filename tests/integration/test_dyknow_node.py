"""The dyknow node over real rclpy/DDS: Data Interface in, semantic matching, verdicts out.

The test publishes /clock (the node runs on sim time) and HelicopterState for three AVs, asks the
node to monitor the chapter's section 8.5 formula over XYDist streams it finds by matching, and
waits (bounded) for the violation verdict.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import pytest

pytestmark = pytest.mark.ros

MAX_SPINS = 600
SPIN_TIMEOUT = 0.02
LAT0, LON0 = 58.4, 15.6
DEG_LAT_M = 111_000.0

# The node runs in namespace /av1: its own Data Interface topic is the relative helicopter_state.
SPEC = """
object av1 : RMAX;
object uav2, uav3 : UAV;
stream a/pos contains Position(av1) from topic "helicopter_state" field position;
stream b/pos contains Position(uav2) from topic "/uav2/helicopter_state" field position;
stream c/pos contains Position(uav3) from topic "/uav3/helicopter_state" field position;
stream b/alt contains altitude(uav2) from topic "/uav2/helicopter_state" field altitude;
stream p/ba contains XYDist(uav2, av1) = xy_dist(b/pos, a/pos) with period 100 ms, max_delay 100 ms;
stream p/ca contains XYDist(uav3, av1) = xy_dist(c/pos, a/pos) with period 100 ms, max_delay 100 ms;
"""
FORMULA = "forall x in AV: x != av1 implies always XYDist(x, av1) > 10"
TOPIC_STREAMS = ("a/pos", "b/alt", "b/pos", "c/pos")
"""The SPEC's streams fed directly by a helicopter_state topic."""


@dataclass
class Rig:
    executor: Any
    dyknow: Any
    tester: Any
    clock: Any
    states: dict[str, Any]
    monitor: Any
    list_streams: Any
    load_streams: Any
    verdicts: list[Any]

    def spin_until(self, done: Callable[[], bool]) -> bool:
        for _ in range(MAX_SPINS):
            if done():
                return True
            self.executor.spin_once(timeout_sec=SPIN_TIMEOUT)
        return done()

    def call(self, client: Any, request: Any) -> Any:
        future = client.call_async(request)
        assert self.spin_until(future.done), "service call timed out"
        return future.result()

    def query(self, client: Any, request: Any) -> Any:
        """A query's answer, sent again until answered (DDS can drop a new client's first)."""
        from tests.integration.ros_wait import answer

        response = answer(self.executor, client, request, MAX_SPINS * SPIN_TIMEOUT)
        assert response is not None, "query timed out"
        return response

    def publish(self, t_ms: int, norths: dict[str, float]) -> None:
        from rosgraph_msgs.msg import Clock

        from hdrc3_interfaces.msg import HelicopterState

        stamp_kwargs = {"sec": t_ms // 1000, "nanosec": (t_ms % 1000) * 1_000_000}
        clock = Clock()
        clock.clock.sec, clock.clock.nanosec = stamp_kwargs["sec"], stamp_kwargs["nanosec"]
        self.clock.publish(clock)
        for av, north in norths.items():
            msg = HelicopterState()
            msg.header.stamp.sec, msg.header.stamp.nanosec = clock.clock.sec, clock.clock.nanosec
            msg.latitude, msg.longitude, msg.altitude = LAT0 + north / DEG_LAT_M, LON0, 100.0
            self.states[av].publish(msg)

    def samples_in(self) -> dict[str, int]:
        """Samples every stream has been offered so far, from the node's ListStreams service."""
        from hdrc3_interfaces.srv import ListStreams

        listing = self.query(self.list_streams, ListStreams.Request())
        return {info.label: info.samples_in for info in listing.streams}

    def step(self, t_ms: int, norths: dict[str, float], count: int) -> None:
        """Publish /clock and every AV's state at ``t_ms``; wait until the node has taken them.

        DDS does not order /clock against the state topics: without the wait, the next step's
        /clock could overtake this step's states, which would then arrive late. ``count`` is the
        number of samples each topic-fed stream has been offered once this step's have arrived.
        """
        self.publish(t_ms, norths)
        assert self.spin_until(
            lambda: all(self.samples_in()[label] == count for label in TOPIC_STREAMS)
        ), (t_ms, self.samples_in())


@pytest.fixture
def rig(ros_context: object) -> Iterator[Rig]:
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from rosgraph_msgs.msg import Clock

    from hdrc3_dyknow.node import DyKnowNode
    from hdrc3_interfaces.msg import HelicopterState, MonitorVerdict
    from hdrc3_interfaces.srv import ListStreams, LoadStreamSpec, MonitorFormula

    dyknow = DyKnowNode(
        context=ros_context,
        namespace="/av1",
        parameter_overrides=[
            Parameter("spec", value=SPEC),
            Parameter("use_sim_time", value=True),
            Parameter("tick_period_s", value=0.05),
        ],
    )
    tester = Node("dyknow_tester", context=ros_context)
    verdicts: list[Any] = []
    qos = QoSProfile(
        depth=100,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )
    tester.create_subscription(MonitorVerdict, "/test/verdicts", verdicts.append, qos)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(dyknow)
    executor.add_node(tester)
    topics = {
        "av1": "/av1/helicopter_state",
        "uav2": "/uav2/helicopter_state",
        "uav3": "/uav3/helicopter_state",
    }
    rig = Rig(
        executor=executor,
        dyknow=dyknow,
        tester=tester,
        clock=tester.create_publisher(Clock, "/clock", 10),
        states={
            av: tester.create_publisher(HelicopterState, topic, 50) for av, topic in topics.items()
        },
        monitor=tester.create_client(MonitorFormula, "/av1/dyknow/monitor"),
        list_streams=tester.create_client(ListStreams, "/av1/dyknow/list_streams"),
        load_streams=tester.create_client(LoadStreamSpec, "/av1/dyknow/load_streams"),
        verdicts=verdicts,
    )
    try:
        assert rig.spin_until(
            lambda: (
                all(p.get_subscription_count() > 0 for p in [rig.clock, *rig.states.values()])
                and rig.monitor.service_is_ready()
                and rig.list_streams.service_is_ready()
                and rig.load_streams.service_is_ready()
            )
        ), "discovery timed out"
        yield rig
    finally:
        executor.shutdown()
        tester.destroy_node()
        dyknow.destroy_node()


def start_request(formula: str, monitor_id: str = "sep", topic: str = "/test/verdicts") -> Any:
    from hdrc3_interfaces.srv import MonitorFormula

    request = MonitorFormula.Request()
    request.action = MonitorFormula.Request.START
    request.monitor_id = monitor_id
    request.formula = formula
    request.verdict_topic = topic
    request.state_period_ms = 100
    request.max_delay_ms = 150
    return request


def test_xydist_violation_is_detected_over_matched_streams(rig: Rig) -> None:
    from hdrc3_interfaces.msg import MonitorVerdict
    from hdrc3_interfaces.srv import ListStreams, MonitorFormula

    response = rig.call(rig.monitor, start_request(FORMULA))
    assert response.code == MonitorFormula.Response.OK, response.reason
    assert list(response.streams) == ["p/ba", "p/ca"]
    assert response.verdict_topic == "/test/verdicts"

    uav3 = [50.0, 40.0, 30.0, 20.0, 15.0, 5.0, 5.0, 5.0, 5.0, 5.0]
    for step, north in enumerate(uav3):
        rig.step(1000 + 100 * step, {"av1": 0.0, "uav2": 100.0, "uav3": north}, step + 1)
    assert rig.spin_until(
        lambda: any(v.verdict == MonitorVerdict.VERDICT_FALSE for v in rig.verdicts)
    )
    final = rig.verdicts[-1]
    assert (final.monitor_id, final.formula, final.verdict) == (
        "sep",
        FORMULA,
        MonitorVerdict.VERDICT_FALSE,
    )
    assert final.stamp.sec * 1000 + final.stamp.nanosec // 1_000_000 == 1500
    assert rig.verdicts[0].verdict == MonitorVerdict.VERDICT_UNKNOWN and rig.verdicts[0].residual

    # A stale (out-of-order) sample on one topic is counted, not fatal.
    rig.publish(1200, {"uav2": 100.0})

    def b_streams() -> dict[str, Any]:
        listing = rig.query(rig.list_streams, ListStreams.Request(label_prefix="b/"))
        return {info.label: info for info in listing.streams}

    assert rig.spin_until(lambda: b_streams()["b/pos"].out_of_order == 1)
    infos = b_streams()
    assert sorted(infos) == ["b/alt", "b/pos"]
    pos = infos["b/pos"]
    assert (pos.feature, list(pos.objects), pos.annotation) == (
        "Position",
        ["uav2"],
        "Position[uav2]",
    )
    assert pos.out_of_order == 1 and pos.samples_out == len(uav3)
    assert pos.rate_hz == pytest.approx(10.0)
    assert pos.missing_handling == "last_value" and pos.late_handling == "drop"

    stop = MonitorFormula.Request(action=MonitorFormula.Request.STOP, monitor_id="sep")
    assert rig.call(rig.monitor, stop).code == MonitorFormula.Response.OK
    assert rig.call(rig.monitor, stop).code == MonitorFormula.Response.NOT_FOUND


@pytest.mark.parametrize(
    ("formula", "action", "topic", "code", "fragment"),
    [
        ("always (", 0, "/test/verdicts", "PARSE_ERROR", "<formula>:1:"),
        ("always temperature(uav2) < 50", 0, "/test/verdicts", "UNKNOWN_SYMBOL", "p/ba"),
        ("always XYDist(uav9, av1) > 1", 0, "/test/verdicts", "UNKNOWN_SYMBOL", "'uav9'"),
        ("always altitude(uav2) > 1", 9, "/test/verdicts", "BAD_REQUEST", "unknown action 9"),
        ("always altitude(uav2) > 1", 0, "bad topic!", "BAD_REQUEST", "invalid verdict topic"),
    ],
)
def test_bad_requests_get_codes_and_reasons(
    rig: Rig, formula: str, action: int, topic: str, code: str, fragment: str
) -> None:
    from hdrc3_interfaces.srv import MonitorFormula

    request = start_request(formula, topic=topic)
    request.action = action
    response = rig.call(rig.monitor, request)
    assert response.code == getattr(MonitorFormula.Response, code)
    assert fragment in response.reason
    # The node is still serving afterwards.
    assert rig.call(rig.monitor, start_request("always altitude(uav2) > 1", "ok")).code == 0


def test_streams_can_be_loaded_at_run_time(rig: Rig) -> None:
    from hdrc3_interfaces.srv import LoadStreamSpec, MonitorFormula

    spec = (
        'stream c/alt contains altitude(uav3) from topic "/uav3/helicopter_state" field altitude;'
    )
    response = rig.call(rig.load_streams, LoadStreamSpec.Request(spec=spec))
    assert (response.code, list(response.labels)) == (LoadStreamSpec.Response.OK, ["c/alt"])
    bad = rig.call(rig.load_streams, LoadStreamSpec.Request(spec="stream x contains"))
    assert (
        bad.code == LoadStreamSpec.Response.PARSE_ERROR
        and ":1:18: unexpected end of input" in bad.reason
    )
    unknown = rig.call(
        rig.load_streams, LoadStreamSpec.Request(spec="stream x contains Warp(av1);")
    )
    assert unknown.code == LoadStreamSpec.Response.BAD_SPEC and "'Warp'" in unknown.reason
    bad_topic = 'stream y contains altitude(av1) from topic "no good!" field altitude;'
    invalid = rig.call(rig.load_streams, LoadStreamSpec.Request(spec=bad_topic))
    assert (
        invalid.code == LoadStreamSpec.Response.BAD_SPEC and "invalid topic name" in invalid.reason
    )
    started = rig.call(rig.monitor, start_request("always altitude(uav3) < 500", "alt3"))
    assert started.code == MonitorFormula.Response.OK and list(started.streams) == ["c/alt"]


def test_console_script_runs_in_a_namespace(ros_context: object, tmp_path: Any) -> None:
    """`hdrc3-dyknow --ros-args -r __ns:=... -p spec_file:=...` serves introspection, then stops."""
    import signal
    import subprocess
    import sys
    from pathlib import Path

    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from hdrc3_interfaces.srv import ListStreams
    from tests.integration.ros_wait import answer

    spec = tmp_path / "streams.spec"
    spec.write_text(SPEC)
    script = str(Path(sys.executable).parent / "hdrc3-dyknow")
    args = [script, "--ros-args", "-r", "__ns:=/uav5", "-p", f"spec_file:={spec}"]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    node = Node("dyknow_cli_tester", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    try:
        client = node.create_client(ListStreams, "/uav5/dyknow/list_streams")
        for _ in range(1500):  # bounded: ~30 s while the process starts
            if client.service_is_ready():
                break
            executor.spin_once(timeout_sec=SPIN_TIMEOUT)
        assert client.service_is_ready(), "hdrc3-dyknow did not come up"
        # a query: sent again until answered (DDS can drop the first answers to a new client;
        # one run in a fresh clone lost this one)
        response = answer(executor, client, ListStreams.Request(), 30.0)
        assert response is not None, "list_streams did not answer"
        labels = [info.label for info in response.streams]
        assert labels == ["a/pos", "b/alt", "b/pos", "c/pos", "p/ba", "p/ca"]
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            code = proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
            code = -1
        executor.shutdown()
        node.destroy_node()
    assert code == 0


@pytest.mark.parametrize(
    "params",
    [["tick_period_s:=0.0"], ["state_period_ms:=0"], ["ontology_file:=/nonexistent/onto.ttl"]],
)
def test_bad_configuration_exits_with_code_2(
    ros_domain: int, params: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    from hdrc3_dyknow.node import main

    args = ["hdrc3-dyknow", "--ros-args"]
    for param in params:
        args += ["-p", param]
    assert main(args) == 2
    assert "hdrc3-dyknow: error:" in capsys.readouterr().err
