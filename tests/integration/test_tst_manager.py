"""The tst_manager node answers every request with a defined code (in-process, real DDS)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from tests.integration.ros_wait import answer

pytestmark = pytest.mark.ros

WAIT_S = 30.0
HEAD = "world revinge\nagents uav0, uav1\npoint Sq = town_square at 30\n"
MISSION = HEAD + (
    "m(P, TS, TE) = with T1, T2, P2, T3, T4 concurrent\n"
    "  a(T1, T2) = fly-to(T1, T2, S, Sq);\n"
    "  b(P2, T3, T4) = hover(T3, T4, 20)\n"
    "where P = uav0 and P2 = uav1 and T2 - T1 <= 100\n"
)


class Rig:
    """uav0's tst_manager and a client node in one executor."""

    def __init__(self, context: Any) -> None:
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node

        from hdrc3_tst.node import TstManagerNode

        self.server = TstManagerNode(context, namespace="/uav0")
        self.node = Node("tst_test_client", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.server)
        self.executor.add_node(self.node)

    def call(self, name: str, **fields: Any) -> Any:
        import hdrc3_interfaces.srv as srv

        srv_type = getattr(srv, f"Tst{name.capitalize()}")
        client = self.node.create_client(srv_type, f"/uav0/tst_manager/{name}")
        assert client.wait_for_service(timeout_sec=WAIT_S), name
        response = answer(self.executor, client, srv_type.Request(**fields), WAIT_S)
        assert response is not None, f"no answer from {name}"
        self.node.destroy_client(client)
        return response


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    made = Rig(ros_context)
    try:
        yield made
    finally:
        made.executor.shutdown()
        made.node.destroy_node()
        made.server.destroy_node()


def codes() -> Any:
    from hdrc3_interfaces.msg import TstReturn

    return TstReturn


@pytest.mark.parametrize(
    ("text", "fixed", "code", "reason"),
    [
        (HEAD + "m(P, TS, TE) = fly-to(TS, TE, 5 Sq)\n", [], "TST_INVALID",
         "bad.tst:4:33: error E001"),
        (HEAD + "m(P, TS, TE) = hover(TS, TE, 30) where P = uav0 and TE - TS <= 10\n", [],
         "TST_INCONSISTENT", ""),
        (HEAD + "m(P, TS, TE) = hover(TS, TE, 30)\n", [], "TST_INVALID", "every node's agent P"),
        (MISSION, ["a.speed"], "TST_INVALID", "malformed fix 'a.speed'"),
        (MISSION, ["a.speed=99"], "TST_INCONSISTENT", "S = 99.0 conflicts"),
        (MISSION.replace("revinge", "flatland"), [], "TST_INVALID", "bad.tst:1:7: error E100"),
        ("x" * 1_000_001, [], "TST_INVALID", "text longer than 1000000 characters"),
    ],
)  # fmt: skip
def test_bad_missions_are_refused_with_a_reason(
    rig: Rig, text: str, fixed: list[str], code: str, reason: str
) -> None:
    response = rig.call("create", mission="m1", text=text, file="bad.tst", fixed=fixed)
    assert response.result.code == getattr(codes(), code), response.result.reason
    assert reason in response.result.reason
    if code == "TST_INCONSISTENT":
        assert list(response.result.conflict)


def test_a_mission_is_held_queried_set_and_refused_twice(rig: Rig) -> None:
    created = rig.call("create", mission="m1", text=MISSION, file="m.tst")
    assert created.result.code == codes().TST_OK, created.result.reason
    assert (created.root, list(created.nodes)) == ("m", ["m", "a"])
    again = rig.call("create", mission="m1", text=MISSION, file="m.tst")
    assert again.result.code == codes().TST_BUSY

    nodes = rig.call("query", mission="m1").nodes
    assert [(n.node_id, n.agent, n.kind, n.state) for n in nodes] == [
        ("m", "uav0", "concurrent", "created"),
        ("a", "uav0", "fly-to", "created"),
    ]
    table = [
        ("set", {"node_id": "a", "param": "speed", "value": "4"}, "TST_OK", ""),
        ("set", {"node_id": "a", "param": "speed", "value": "6"}, "TST_INCONSISTENT", ""),
        ("set", {"node_id": "a", "param": "colour", "value": "red"}, "TST_UNKNOWN_NODE", "colour"),
        ("set", {"node_id": "zz", "param": "TS", "value": "1"}, "TST_UNKNOWN_NODE", "'zz'"),
        ("execute", {"node_id": "b", "epoch": 0.0}, "TST_BUSY", "uav0 does not hold node 'b'"),
        ("execute", {"node_id": "zz", "epoch": 0.0}, "TST_UNKNOWN_NODE", "no node 'zz'"),
        ("abort", {"node_id": "zz", "reason": "x"}, "TST_UNKNOWN_NODE", "no node 'zz'"),
    ]
    for name, fields, code, reason in table:
        result = rig.call(name, mission="m1", **fields).result
        assert result.code == getattr(codes(), code), (name, fields, result.reason)
        assert reason in result.reason


def test_a_command_sent_again_with_its_key_is_answered_as_the_first_time(rig: Rig) -> None:
    fields = {"mission": "m1", "text": MISSION, "file": "m.tst"}
    first = rig.call("create", request_key="create-1", **fields)
    again = rig.call("create", request_key="create-1", **fields)
    other = rig.call("create", request_key="create-2", **fields)
    too_long = rig.call("execute", mission="m1", node_id="m", epoch=0.0, request_key="k" * 65)
    assert first.result.code == again.result.code == codes().TST_OK, again.result.reason
    assert list(again.nodes) == ["m", "a"]  # the first answer, not "already exists"
    assert other.result.code == codes().TST_BUSY  # a new key is a new request
    assert too_long.result.code == codes().TST_INVALID
    assert "request_key: 65 characters" in too_long.result.reason


@pytest.mark.parametrize("name", ["execute", "abort", "set", "query"])
def test_an_unknown_mission_is_named(rig: Rig, name: str) -> None:
    result = rig.call(name, mission="nope").result
    assert result.code == codes().TST_UNKNOWN_MISSION
    assert result.reason == "uav0 has no mission 'nope'"
